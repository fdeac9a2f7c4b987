// The contour error of two servo axes (J. Peng 1989, Sec. 4.2-4.3): the straight-line error from mismatched axes
// (Eq. 4.78, 4.91, computed here from Eq. 4.85), its sign, none for matched axes, the tolerance intervals, the
// signed distance to a path, the reference sampled from steps; the drives file's checks.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cam/error.hpp"
#include "machine/servo/contour.hpp"
#include "machine/servo/drives_file.hpp"
#include "machine/servo/step_reference.hpp"

namespace tu_machine_servo_test_contour {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::servo;

namespace {

const std::string kPeng = std::string(POLARCAM_SOURCE_DIR) + "/examples/drives/peng1989.toml";

// Eq. 4.85 in m for an axis at speed f (m/s), from the parameters.
double eq_4_85(const AxisDrive& d, double f) {
  const ServoParams& p = d.params;
  const double K1 = p.K_t * p.S_g * p.K_I * p.K_v / (p.L_a * p.J_e);
  const double K3 = (p.B * (p.R_a + p.K_v * p.K_a) + p.K_t * (p.K_b + p.H_g * p.T_g * p.K_v * p.K_I)) / (p.J_e * p.L_a);
  const double D1 = p.K_p * (1.0 + p.a) / (1.0 + p.b);
  const double counts_per_m = 4000.0 / 5.08e-3;
  return f * counts_per_m * K3 / (K1 * p.K_e * p.K_d * D1) / counts_per_m;
}

}  // namespace

TEST(Contour, DiamondLineErrorOfMismatchedAxes) {
  // 20 mm/s on each axis (Sec. 4.3.2): e_c = (f_cx e_sy - f_cy e_sx)/f_c = (e_sy - e_sx) cos 45 deg on the first leg
  const Drives d = read_drives_file(kPeng);
  const double f = 20e-3 * std::sqrt(2.0);
  const ContourResult c = run_contour(d, test_path(TestPath::diamond, f, 1e-3));
  const double ex = eq_4_85(d.axis[0], 20e-3), ey = eq_4_85(d.axis[1], 20e-3);
  const double expected = (ey - ex) * std::cos(std::numbers::pi / 4);
  const size_t mid = 1250;  // t = 1.25 s: the middle of the first leg (2.5 s long)
  EXPECT_NEAR(c.e_c[mid], expected, 1e-6 * expected);
  EXPECT_GT(c.e_c[mid], 0.0);  // y lags more: the tool runs right of (below) the up-right leg
  EXPECT_NEAR(c.e_c[mid], 0.034e-3, 0.01 * 0.034e-3);  // printed 0.034 mm
  // the following errors at steady speed, both axes at 20 mm/s
  ASSERT_TRUE(c.steady[0].found && c.steady[1].found);
  EXPECT_NEAR(c.steady[0].error, ex, 1e-6 * ex);
  EXPECT_NEAR(c.steady[1].error, ey, 1e-6 * ey);
  EXPECT_NEAR(std::abs(c.steady[0].speed), 20e-3, 1e-12);
  // the corners are worse than the legs; the largest error is at a corner, and leaves 0.05 mm
  EXPECT_GT(c.max_abs_contour_error, 0.1e-3);
  EXPECT_FALSE(c.within_tolerance());
  const double leg_time = 2.5;
  const double nearest_corner = std::round(c.max_at_t / leg_time) * leg_time;
  EXPECT_LT(std::abs(c.max_at_t - nearest_corner), 0.1);
  EXPECT_GT(c.max_at_t, 1.0);
}

TEST(Contour, MatchedAxesHaveNoLineError) {
  Drives d = read_drives_file(kPeng);
  d.axis[1].params = d.axis[0].params;
  const ContourResult c = run_contour(d, test_path(TestPath::diamond, 20e-3 * std::sqrt(2.0), 1e-3));
  EXPECT_LT(std::abs(c.e_c[1250]), 1e-10);
  EXPECT_NEAR(c.steady[0].error, c.steady[1].error, 1e-6 * c.steady[0].error);  // averaged over different stretches
}

TEST(Contour, ToleranceIntervals) {
  const Drives d = read_drives_file(kPeng);
  ServoOptions o;
  o.tolerance = 1e-3;  // 1 mm: never left
  const Reference r = test_path(TestPath::square, 20e-3, 1e-3);
  const ContourResult loose = run_contour(d, r, o);
  EXPECT_TRUE(loose.within_tolerance());
  o.tolerance = 0.05e-3;
  const ContourResult tight = run_contour(d, r, o);
  ASSERT_FALSE(tight.within_tolerance());
  // each interval is out of tolerance throughout and its ends are in order
  for (const Interval& iv : tight.out_of_tolerance) {
    EXPECT_LE(iv.t_begin, iv.t_end);
    EXPECT_GT(iv.max_abs_error, 0.05e-3);
    const size_t k = static_cast<size_t>(std::llround((iv.t_begin + iv.t_end) / 2 / 1e-3));
    EXPECT_GT(std::abs(tight.e_c[k]), 0.05e-3);
  }
  // on the square one axis moves at a time: at steady speed along a side no contour error
  EXPECT_LT(std::abs(tight.e_c[1250]), 1e-9);
}

TEST(Contour, SignedDistance) {
  // path (0,0) -> (1,0) -> (1,1); points right and left of the travel
  const std::vector<double> x = {0, 1, 1}, y = {0, 0, 1};
  double at = 0;
  EXPECT_DOUBLE_EQ(signed_distance(x, y, 0, 2, 0.5, -0.25, at), 0.25);  // below the first leg: right
  EXPECT_DOUBLE_EQ(at, 0.5);
  EXPECT_DOUBLE_EQ(signed_distance(x, y, 0, 2, 0.5, 0.25, at), -0.25);
  EXPECT_DOUBLE_EQ(signed_distance(x, y, 0, 2, 1.5, 0.5, at), 0.5);  // right of the upward leg
  EXPECT_DOUBLE_EQ(at, 1.5);
}

TEST(Contour, PolarToolPoint) {
  // a polar machine on a circle about the pole: r constant, theta a ramp: the contour error is r times the
  // angular error's radial part, i.e. the tool stays on the circle: |e_c| tiny against the angular lag r e_theta
  const Drives d = read_drives_file(std::string(POLARCAM_SOURCE_DIR) + "/examples/drives/polar_servo.toml");
  ASSERT_TRUE(d.polar);
  Reference r;
  const double R = 0.15, w = 0.02 / R;
  for (int k = 0; k < 3000; ++k) {
    r.q[0].push_back(R);
    r.q[1].push_back(w * k * 1e-3);
  }
  const ContourResult c = run_contour(d, r);
  ASSERT_TRUE(c.steady[1].found);
  EXPECT_GT(R * c.steady[1].error, 1e-5);
  // the actual point lies on the circle of radius R: its distance to the polyline of 1 ms chords is the chord's sag
  const double sag = R * (1 - std::cos(w * 1e-3 / 2));
  EXPECT_LT(std::abs(c.e_c[2000]), sag * 1.01 + 1e-12);
}

TEST(StepReference, SamplesTheNodeReached) {
  const double res[2] = {1e-5, 1e-3};
  StepSampler s(res, 10, -2);
  s.step(0, +1, 500000);    // 0.5 ms
  s.step(1, -1, 1000000);   // 1 ms: seen at sample 1
  s.step(0, +1, 1000001);   // just after: sample 2
  const Reference r = s.sample(1e-3, 0.002);
  ASSERT_EQ(r.q[0].size(), 5u);  // t = 0 to 4 ms: the last step at 1.000001 ms, then 2 ms held
  EXPECT_DOUBLE_EQ(r.q[0][0], 10 * 1e-5);
  EXPECT_DOUBLE_EQ(r.q[0][1], 11 * 1e-5);
  EXPECT_DOUBLE_EQ(r.q[1][1], -3 * 1e-3);
  EXPECT_DOUBLE_EQ(r.q[0][2], 12 * 1e-5);
  EXPECT_DOUBLE_EQ(r.q[1][0], -2 * 1e-3);
}

TEST(DrivesFile, ReadsPengsAxes) {
  const Drives d = read_drives_file(kPeng);
  EXPECT_FALSE(d.polar);
  EXPECT_EQ(d.axis[0].name, "x");
  EXPECT_NEAR(d.axis[0].params.K_e, 636.62, 0.005);
  EXPECT_DOUBLE_EQ(d.axis[0].params.K_d, 0.0781);
  EXPECT_DOUBLE_EQ(d.axis[0].params.L_a, 2e-3);
  EXPECT_DOUBLE_EQ(d.axis[0].params.B, 0.09);
  EXPECT_DOUBLE_EQ(d.axis[1].params.B, 0.3);
  EXPECT_DOUBLE_EQ(d.axis[0].pitch, 5.08e-3);
}

namespace {
std::string axis_table(const std::string& name, const std::string& extra = "", const std::string& drop = "") {
  const char* keys[][2] = {{"R_a", "\"0.4 ohm\""}, {"L_a", "\"2 mH\""}, {"K_t", "\"0.3 N m/A\""},
                           {"K_b", "\"0.3 V s/rad\""}, {"J_e", "\"0.0036 kg m^2\""}, {"B", "\"0.09 N m s/rad\""},
                           {"K_a", "0.0643"}, {"K_I", "\"25.5 A/V\""}, {"K_v", "21.934"},
                           {"H_g", "\"0.08872 V s/rad\""}, {"T_g", "0.13183"}, {"S_g", "0.0648"},
                           {"K_e", "\"636.62 counts/rad\""}, {"K_d", "\"0.0781 V/count\""}, {"K_p", "2.5"},
                           {"a", "-0.8825"}, {"b", "0"}, {"sample_period", "\"1 ms\""}, {"pitch", "\"5.08 mm\""}};
  std::string s = "[" + name + "]\n";
  for (auto& k : keys)
    if (drop != k[0]) s += std::string(k[0]) + " = " + k[1] + "\n";
  return s + extra;
}
std::string error_of(const std::string& text) {
  try {
    parse_drives_toml(text, "d.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(DrivesFile, RefusesWhatIsWrong) {
  EXPECT_EQ(error_of(axis_table("x") + axis_table("y")), "");
  EXPECT_NE(error_of(axis_table("x") + axis_table("y", "K_z = 1\n")).find("d.toml:41: unknown key 'y.K_z'"),
            std::string::npos);
  EXPECT_NE(error_of(axis_table("x", "", "L_a") + axis_table("y")).find("key 'x.L_a'"), std::string::npos);
  EXPECT_NE(error_of(axis_table("x") + axis_table("y")).size(), 1u);
  std::string wrong_unit = axis_table("x") + axis_table("y");
  wrong_unit.replace(wrong_unit.find("\"2 mH\""), 6, "\"2 mm\"");
  EXPECT_NE(error_of(wrong_unit).find("d.toml:3: key 'x.L_a'"), std::string::npos);
  EXPECT_NE(error_of(axis_table("x")).find("missing the [y] table"), std::string::npos);
  EXPECT_NE(error_of(axis_table("x") + axis_table("z")).find("unknown table [z]"), std::string::npos);
  std::string unstable = axis_table("x") + axis_table("y");
  unstable.replace(unstable.find("K_p = 2.5"), 9, "K_p = 40");
  EXPECT_NE(error_of(unstable).find("key 'x.K_p'"), std::string::npos);
  // theta needs a worm ratio, not a pitch
  EXPECT_NE(error_of(axis_table("r") + axis_table("theta")).find("key 'theta.ratio'"), std::string::npos);
  EXPECT_NE(error_of(axis_table("r") + axis_table("theta", "ratio = 40\n")).find("unknown key 'theta.pitch'"),
            std::string::npos);
}

TEST(CornerSpline, PengsWorkedExample) {
  // Sec. 4.4.3, the diamond corner at (150, 150) mm, 1 mm each way, 20 mm/s on each axis
  const double ps[2] = {149, 149}, pf[2] = {151, 149}, vs[2] = {20, 20}, vf[2] = {20, -20};
  const SplineSegment one = hermite_segment(ps, vs, pf, vf, 0.1);  // Eq. 4.144
  const double a1[2][4] = {{0, 0, 2, 149}, {0, -2, 2, 149}};
  for (int i = 0; i < 2; ++i)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(one.A[i][c], a1[i][c], 1e-12) << i << c;
  // Case 2 with P_m = (150, 149.99), f = (20, 0) there: Eq. 4.148 and 4.151 (Eq. 4.146, 4.147, 4.149 print 149.0)
  const double pm[2] = {150, 149.99}, vm[2] = {20, 0};
  const SplineSegment s1 = hermite_segment(ps, vs, pm, vm, 0.05), s2 = hermite_segment(pm, vm, pf, vf, 0.05);
  const double b1[2][4] = {{0, 0, 1, 149}, {-0.98, 0.97, 1, 149}}, b2[2][4] = {{0, 0, 1, 150}, {0.98, -1.97, 0, 149.99}};
  for (int i = 0; i < 2; ++i)
    for (int c = 0; c < 4; ++c) {
      EXPECT_NEAR(s1.A[i][c], b1[i][c], 1e-9) << i << c;
      EXPECT_NEAR(s2.A[i][c], b2[i][c], 1e-9) << i << c;
    }
}

TEST(CornerSpline, DiamondPathThroughTheSplines) {
  // the splined diamond's top corner is Peng's corner moved to (0, 50 mm); the reference is continuous in
  // position and speed; the blend cuts the corner error of the step reference
  const double f = 20e-3 * std::sqrt(2.0);
  const SplinedPath p = test_path_with_splines(TestPath::diamond, f, 1e-3, 1, std::sqrt(2.0) * 1e-3);
  ASSERT_EQ(p.corners.size(), 3u);
  EXPECT_DOUBLE_EQ(p.corners[0].corner[1], 50e-3);
  const SplineSegment& g = p.corners[0].segments[0];
  EXPECT_NEAR(g.A[1][1], -2e-3, 1e-12);  // y: -2 s^2 (mm), as Eq. 4.145
  EXPECT_NEAR(g.A[0][2], 2e-3, 1e-12);
  // no velocity step after the start: the second difference stays at the splines' acceleration (400 mm/s^2 on y:
  // 4e-7 m a sample), far below a step of the legs' speed (2e-5 m), through the first two corners
  for (int a = 0; a < 2; ++a) {
    const std::vector<double>& q = p.reference.q[a];
    for (size_t k = 3; k < q.size() / 2; ++k)
      ASSERT_LT(std::abs(q[k] - 2 * q[k - 1] + q[k - 2]), 1e-6) << a << " " << k;
  }
  // the blend cuts the corner error of the step reference
  const Drives d = read_drives_file(kPeng);
  const ContourResult splined = run_contour(d, p.reference);
  const ContourResult step = run_contour(d, test_path(TestPath::diamond, f, 1e-3));
  EXPECT_LT(splined.max_abs_contour_error, step.max_abs_contour_error);
}

TEST(Strategies, RankOfTable41) {
  // Table 4.1 (diamond corner, 20 mm/s on each axis) as a ranking: 0.1 s acceleration ramps << sharp corners <
  // integral action; mismatched axes worse than matched
  const double f = 20e-3 * std::sqrt(2.0);
  const Drives mis = read_drives_file(kPeng);
  Drives matched = mis;
  matched.axis[1].params = matched.axis[0].params;
  Drives integral = mis;
  for (auto& a : integral.axis) a.params.C_I = 0.5;
  const Reference step = test_path(TestPath::diamond, f, 1e-3), ramp = test_path(TestPath::diamond, f, 1e-3, 0.1);
  const double step_mis = run_contour(mis, step).max_abs_contour_error;
  const double step_matched = run_contour(matched, step).max_abs_contour_error;
  const double ramp_mis = run_contour(mis, ramp).max_abs_contour_error;
  const double ramp_matched = run_contour(matched, ramp).max_abs_contour_error;
  const double integral_mis = run_contour(integral, step).max_abs_contour_error;
  EXPECT_LT(ramp_matched, ramp_mis);
  EXPECT_LT(ramp_mis, 0.5 * step_matched);
  EXPECT_LT(step_matched, step_mis);
  EXPECT_LT(step_mis, integral_mis);
}

TEST(DrivesFile, PeakCurrent) {
  const Drives d = read_drives_file(kPeng);
  EXPECT_DOUBLE_EQ(d.axis[0].peak_current, 30.0);
  EXPECT_NE(error_of(axis_table("x", "peak_current = \"-1 A\"\n") + axis_table("y")).find("key 'x.peak_current'"),
            std::string::npos);
  EXPECT_NE(error_of(axis_table("x", "peak_current = \"1 V\"\n") + axis_table("y")).find("key 'x.peak_current'"),
            std::string::npos);
}

}  // namespace tu_machine_servo_test_contour
