// The comparison's parts and the comparison itself (pipeline/compare.hpp, docs/compare.md):
//  - the scaled-axis step sink, the step-rate meter, the node box, the time-scaled speed and the speed trace,
//    against hand calculations and independent recomputation;
//  - the polar and the Cartesian staircase of the same contour measured by the same metrics: a circle about the
//    polar machine's pole (closed forms for the polar staircase; CGAL and a closed-form deviation for the
//    Cartesian one), and an axis-aligned rectangle (CGAL for the polar staircase; closed forms for the
//    Cartesian one), both through compare_job() as the CLI runs it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "pipeline/compare.hpp"
#include "pipeline/job_tape.hpp"
#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "cam/scaled.hpp"
#include "tests/scratch.hpp"
#include "tests/helpers.hpp"
#include "machine/cartesian/cartesian_exact.hpp"
#include "metrics/node_box.hpp"
#include "metrics/pulse_speed.hpp"
#include "machine/player/scaling.hpp"
#include "metrics/step_rates.hpp"
#include "metrics/area_check.hpp"
#include "metrics/cartesian_error.hpp"
#include "metrics/error_metrics.hpp"

namespace tu_pipeline_test_compare {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test;

namespace {

constexpr double kPi = std::numbers::pi;

}  // namespace

// Every index the scaled stream reaches is round(n P/Q) of the input's index n (halves up), whatever the sign.
TEST(CompareParts, ScaledAxisSinkFollowsTheRoundedIndex) {
  for (Ratio s : {Ratio{1, 2}, Ratio{3, 2}, Ratio{2, 3}, Ratio{5, 1}}) {
    RecordingSink out;
    const int64_t n0 = -7;
    ScaledAxisSink sc(out, 0, s, n0);
    int64_t n = n0, m = 0;
    int64_t N = static_cast<int64_t>(std::floor(static_cast<double>(n0) * s.value() + 0.5));
    const int dirs[] = {+1, +1, +1, -1, +1, +1, +1, +1, +1, +1, +1, +1, +1, +1, -1, -1, +1, +1, +1, +1, +1};
    int64_t t = 0;
    for (int d : dirs) {
      sc.step(0, d, t);
      sc.step(1, 1, t);  // the other axis passes through
      n += d;
      ++m;
      t += 10;
    }
    int64_t got_N = N, got_m = 0;
    for (const auto& r : out.steps) (r.axis == 0 ? got_N : got_m) += r.dir;
    const int64_t want = static_cast<int64_t>(std::floor(static_cast<double>(n) * s.value() + 0.5));
    EXPECT_EQ(got_N, want) << to_string(s);
    EXPECT_EQ(got_m, m);
  }
}

TEST(CompareParts, StepRatesAndReversalsByHand) {
  StepRateMeter m;
  // axis 0: +1 at 0, 100, 250 ns; -1 at 260 (a reversal 10 ns after); -1 at 1260; axis 1: +1 at 0, +1 at 0
  m.step(0, 1, 0);
  m.step(1, 1, 0);
  m.step(1, 1, 0);
  m.step(0, 1, 100);
  m.step(0, 1, 250);
  m.step(0, -1, 260);
  m.step(0, -1, 1260);
  const AxisRates a = m.axis(0), b = m.axis(1);
  EXPECT_EQ(a.steps, 5u);
  EXPECT_EQ(a.min_interval_ns, 100);
  EXPECT_DOUBLE_EQ(a.max_rate_hz, 1e7);
  EXPECT_EQ(a.reversals, 1u);
  EXPECT_EQ(a.min_reversal_interval_ns, 10);
  EXPECT_EQ(b.min_interval_ns, 0);
  EXPECT_DOUBLE_EQ(b.max_rate_hz, 1e9);  // two steps in one nanosecond count one nanosecond apart
}

TEST(CompareParts, NodeBoxAndScaledCurve) {
  NodeBox c(false, 0.5, 0.5, 2, -3);
  c.step(0, 1, 0);
  c.step(1, -1, 0);
  c.step(0, -1, 0);
  c.step(0, -1, 0);
  EXPECT_DOUBLE_EQ(c.size().x, 1.0);  // i from 1 to 3
  EXPECT_DOUBLE_EQ(c.size().y, 0.5);  // j from -4 to -3
  NodeBox p(true, 1.0, kPi / 2, 2, 0);  // (2, 0) -> (2, 1) = (0, 2) -> (3, 1) = (0, 3)
  p.step(1, 1, 0);
  p.step(0, 1, 0);
  EXPECT_NEAR(p.size().x, 2.0, 1e-15);
  EXPECT_NEAR(p.size().y, 3.0, 1e-15);

  auto circ = make_circle({1.0, 2.0}, 3.0);
  auto half = scale_curve(circ, 0.5);
  for (double u : {0.0, 1.0, 4.0}) {
    const CurvePoint a = circ->eval(u, 2), b = half->eval(u, 2);
    EXPECT_DOUBLE_EQ(b.p.x, 0.5 * a.p.x);
    EXPECT_DOUBLE_EQ(b.d1.y, 0.5 * a.d1.y);
    EXPECT_DOUBLE_EQ(b.d2.x, 0.5 * a.d2.x);
  }
  EXPECT_THROW(scale_curve(circ, 0.0), InputError);
}

// A tape played K times faster: every speed sample is K times the original (to the nanosecond rounding of the
// scaled times), so the mean is K times and the RMS deviation from K V is K times the one from V. The trace's bins
// hold the samples whose middles fall in them.
TEST(CompareParts, TapeSpeedScalesAndTraces) {
  const double blu = 0.01e-3, V = 0.02;
  auto circle = make_circle({0.3e-3, -0.2e-3}, 2e-3);
  CartesianTrack tr = CartesianTrack::build(*circle);
  auto prof = make_constant_speed(V, tr.length());
  const std::string tape = temp_path("speed-scale.tape");
  TapeHeader h;
  h.axes = TapeAxes::cartesian;
  h.rule = TapeRule::exact_cartesian;
  h.res[0] = h.res[1] = blu;
  h.speed_mps = V;
  CartesianResult r;
  {
    TapeWriter w(tape, h);
    r = step_exact(tr, blu, *prof, &w);
    for (int a = 0; a < 2; ++a) h.start[a] = r.start[a], h.end[a] = r.end[a];
    h.duration_ticks = static_cast<uint64_t>(r.duration_ns);
    w.finish(h);
  }
  SpeedTrace trace(10, r.duration_s);
  const PulseSpeedStats s1 = measure_tape_speed(tape, V, 1.0, &trace);
  const PulseSpeedStats s3 = measure_tape_speed(tape, 3 * V, 3.0);
  std::remove(tape.c_str());
  EXPECT_NEAR(s3.mean_mps, 3 * s1.mean_mps, 1e-5 * s1.mean_mps);
  EXPECT_NEAR(s3.max_mps, 3 * s1.max_mps, 1e-5 * s1.max_mps);
  EXPECT_NEAR(s3.rms_dev_mps, 3 * s1.rms_dev_mps, 1e-3 * s1.mean_mps);
  EXPECT_EQ(s3.samples, s1.samples);
  double sw = 0, swv = 0;
  for (int i = 0; i < trace.bins(); ++i) {
    ASSERT_GT(trace.sw[static_cast<size_t>(i)], 0.0) << i;
    EXPECT_LE(trace.vmin[static_cast<size_t>(i)], trace.mean(i));
    EXPECT_GE(trace.vmax[static_cast<size_t>(i)], trace.mean(i));
    EXPECT_GE(trace.vmin[static_cast<size_t>(i)], s1.min_mps);
    EXPECT_LE(trace.vmax[static_cast<size_t>(i)], s1.max_mps);
    sw += trace.sw[static_cast<size_t>(i)];
    swv += trace.swv[static_cast<size_t>(i)];
  }
  EXPECT_NEAR(swv / sw, s1.mean_mps, 1e-12);
  EXPECT_THROW(measure_tape_speed("/nonexistent.tape", V, 0.0), InputError);
}

// The same circle on both machines, by the same metrics. Polar: the circle about the pole; the staircase is the
// circle of the nearest node radius, so the area error is the annulus pi |R^2 - (n dR)^2| and the deviation
// |R - n dR|. Cartesian: CGAL on inscribed polygons, extrapolated, and the deviation in closed form (docs).
TEST(CompareMetrics, SameCircleOnBothMachines) {
  const double dr = 0.1e-3, R = 12.337e-3;
  auto circle = make_circle({0, 0}, R);
  Grid g;
  g.dr = dr;
  g.steps_per_rev = 1440;
  g.dtheta = dtheta_from_steps(g.steps_per_rev);
  test::Run pr = run_digitizer(*circle, g, StepRule::nearest, 0.02);
  ErrorMeters em;
  em.reset(*circle, pr.track, g, 10);
  for (const auto& s : pr.steps) em.record(s.axis, s.dir);
  const ErrorMetrics pm = em.finish(pr.result.start_n, pr.result.start_m);
  const double n = std::nearbyint(R / dr);
  EXPECT_NEAR(pm.area.area_m2, kPi * std::abs(R * R - n * dr * n * dr), 1e-12 * R * R);
  EXPECT_NEAR(pm.deviation_max_m, std::abs(R - n * dr), 1e-12);

  CartesianTrack ct = CartesianTrack::build(*circle);
  auto prof = make_constant_speed(0.02, ct.length());
  RecordingSink rec;
  const CartesianResult cr = step_exact(ct, dr, *prof, &rec);
  CartesianErrorMeters cm;
  cm.reset(*circle, ct, dr);
  for (const auto& s : rec.steps) cm.record(s.axis, s.dir);
  const CartesianErrorMetrics cmet = cm.finish(cr.start[0], cr.start[1]);
  std::vector<XYNode> nodes{{cr.start[0], cr.start[1]}};
  for (const auto& s : rec.steps) {
    XYNode x = nodes.back();
    (s.axis == kAxisX ? x.i : x.j) += s.dir;
    nodes.push_back(x);
  }
  auto cgal = [&](int M) {
    std::vector<Vec2> v;
    for (int i = 0; i <= M; ++i) v.push_back(R * Vec2{std::cos(2 * kPi * (i % M) / M), std::sin(2 * kPi * (i % M) / M)});
    return area_error_cgal_cartesian(v, nodes, dr);
  };
  const double a1 = cgal(1000), a2 = cgal(2000), a3 = cgal(4000);
  const double e1 = (4 * a2 - a1) / 3, e2 = (4 * a3 - a2) / 3;
  EXPECT_LT(std::abs(e2 - cmet.area.area_m2), std::abs(e1 - cmet.area.area_m2));  // converging to the meter
  EXPECT_NEAR(cmet.area.area_m2, e2, 1e-6 * e2) << a1 << " " << a2 << " " << a3;
  double dmax = 0;
  for (size_t k = 0; k + 1 < nodes.size(); ++k) {
    const Vec2 a{nodes[k].i * dr, nodes[k].j * dr}, b{nodes[k + 1].i * dr, nodes[k + 1].j * dr};
    dmax = std::max({dmax, std::abs(norm(a) - R), std::abs(norm(b) - R)});
    const Vec2 d = b - a;
    const double t = -dot(a, d) / dot(d, d);
    if (t > 0 && t < 1) dmax = std::max(dmax, R - norm(a + t * d));
  }
  EXPECT_NEAR(cmet.deviation_max_m, dmax, 1e-9 * dr);
}

namespace {

// A job on a coarse grid (0.1 mm, 3600 steps per revolution, no work-area limits), contour given in TOML.
std::string coarse_job(const std::string& contour) {
  return "[machine]\nfile = \"machines/fahim1983.toml\"\nradial_resolution = \"0.1 mm\"\nangular_steps_per_rev = 3600\n"
         "r_min = \"0 cm\"\nr_max = \"none\"\ntheta_min = \"none\"\ntheta_max = \"none\"\n" +
         contour + "[placement]\nC = \"0 mm\"\n[tool]\nradius = \"0 mm\"\n[motion]\nspeed = \"20 mm/s\"\n";
}

}  // namespace

// Through compare_job, as the CLI runs it: a circle about the pole (polar closed forms), and an axis-aligned
// rectangle (Cartesian closed forms; the polar staircase against CGAL), with the Table 3.1 facts.
TEST(CompareJob, ClosedFormsThroughTheComparison) {
  Scratch sc;
  {
    const double R = 20.33e-3, dr = 0.1e-3;
    const Job job = load_job(sc.write("circle.toml", coarse_job("[contour]\nkind = \"circle\"\nradius = \"20.33 mm\"\n")));
    CompareOptions opt;
    const Comparison c = compare_job(job, opt);
    const double n = std::nearbyint(R / dr);
    EXPECT_NEAR(c.polar.area_m2, kPi * std::abs(R * R - n * dr * n * dr), 1e-12 * R * R);
    EXPECT_NEAR(c.polar.deviation_m, std::abs(R - n * dr), 1e-12);
    EXPECT_EQ(c.polar.steps[0], 0u);
    EXPECT_EQ(c.polar.steps[1], 3600u);
    EXPECT_NEAR(c.polar.resolution_worst_m, dr, 1e-15);  // r dtheta = 0.0355 mm at r = R is finer than dR
    EXPECT_DOUBLE_EQ(c.cartesian.resolution_worst_m, dr);
    // the DDA steps a circle of 8 R / BLU steps (R = 203.3 BLU rounds to 203: 8 x 203)
    EXPECT_EQ(c.cartesian.steps_total(), 8u * 203u);
    // speed scaling: the polar tape K times faster; the DDA re-run
    EXPECT_TRUE(c.polar.speed_scaling.without_reprocessing);
    EXPECT_NEAR(c.polar.speed_scaling.speed.mean_mps, 2 * c.polar.speed.mean_mps, 1e-5 * c.polar.speed.mean_mps);
    EXPECT_FALSE(c.cartesian.speed_scaling.without_reprocessing);
    EXPECT_TRUE(c.cartesian.speed_scaling.possible);
    EXPECT_NEAR(c.cartesian.speed_scaling.speed.mean_mps, 0.04, 0.002);
    // size scaling by 1/2: the polar circle halves (a circle of round(203 / 2) = 102 nodes radius)
    const SizeScalingFact& ps = c.polar.size_scaling.front();
    EXPECT_NEAR(ps.size.x, 2 * 102 * dr, 1e-9);
    EXPECT_NEAR(ps.wanted.x, R, 1e-9);
    ASSERT_TRUE(ps.measured);
    EXPECT_NEAR(ps.area_m2, kPi * std::abs(0.25 * R * R - 102 * dr * 102 * dr), 1e-12 * R * R);
    const SizeScalingFact& q1 = c.cartesian.size_scaling[0];
    EXPECT_NEAR(q1.size.y, 2 * 203 * dr, 1e-9);  // y not scaled
    EXPECT_NEAR(q1.size.x, 203 * dr, 1e-9);      // x from round(-203 / 2) = -101 to round(203 / 2) = 102 (halves up)
    // the verdicts: one per attribute, a winner each; here the angular step at r = 20.33 mm is 0.0355 mm, finer than
    // dR, so the polar machine's worst resolution is dR = the BLU; the polar tape's speed is steadier than the DDA's
    ASSERT_EQ(c.verdicts.size(), 9u);
    for (const AttributeVerdict& v : c.verdicts) EXPECT_TRUE(v.winner == "polar" || v.winner == "cartesian" || v.winner == "tie");
    EXPECT_EQ(c.verdicts[0].winner, "polar");
    EXPECT_EQ(c.verdicts[4].winner, "tie");
    EXPECT_EQ(c.verdicts[7].winner, "polar");  // speed scaling: no reprocessing against new feed words
    EXPECT_EQ(c.verdicts[8].winner, "polar");  // size scaling by one axis
  }
  {
    // a rectangle from (10.03, 5.02) to (30.07, 25.06) mm, i.e. (100.3, 50.2) to (300.7, 250.6) BLU
    const Job job = load_job(sc.write(
        "rect.toml", coarse_job("[contour]\nkind = \"path\"\nstart = [\"10.03 mm\", \"5.02 mm\"]\nsegments = [\n"
                                "  { kind = \"line\", to = [\"30.07 mm\", \"5.02 mm\"] },\n"
                                "  { kind = \"line\", to = [\"30.07 mm\", \"25.06 mm\"] },\n"
                                "  { kind = \"line\", to = [\"10.03 mm\", \"25.06 mm\"] },\n"
                                "  { kind = \"line\", to = [\"10.03 mm\", \"5.02 mm\"] },\n]\n")));
    CompareOptions opt;
    opt.method = CartesianMethod::exact;
    const Comparison c = compare_job(job, opt);
    const double blu = 0.1e-3;
    const double x0 = 100.3, y0 = 50.2, x1 = 300.7, y1 = 250.6, X0 = 100, Y0 = 50, X1 = 301, Y1 = 251;
    const double A = (x1 - x0) * (y1 - y0), B = (X1 - X0) * (Y1 - Y0);
    const double I = (std::min(x1, X1) - std::max(x0, X0)) * (std::min(y1, Y1) - std::max(y0, Y0));
    EXPECT_NEAR(c.cartesian.area_m2, (A + B - 2 * I) * blu * blu, 1e-12 * A * blu * blu);
    EXPECT_EQ(c.cartesian.steps[0], static_cast<uint64_t>(2 * (X1 - X0)));
    EXPECT_EQ(c.cartesian.steps[1], static_cast<uint64_t>(2 * (Y1 - Y0)));
    const Vec2 P[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, S[4] = {{X0, Y0}, {X1, Y0}, {X1, Y1}, {X0, Y1}};
    const double dmax = outline_deviation(S, P);
    EXPECT_NEAR(c.cartesian.deviation_m / blu, dmax, 1e-3);
    // the exact Cartesian tape holds the speed: samples at V along the edges; at the corners an axis's last
    // interval before the turn and the other's first after it overlap at most one step
    EXPECT_NEAR(c.cartesian.speed.mean_mps, 0.02, 2e-4);
    EXPECT_TRUE(c.cartesian.speed_scaling.without_reprocessing);  // an exact tape, played faster

    // the polar staircase of the same rectangle against CGAL's exact arrangement
    RecordingSink rec;
    const DigitizedJob d = digitize_job(job, &rec);
    std::vector<StairNode> nodes{{d.result.start_n, d.result.start_m}};
    for (const auto& s : rec.steps) {
      StairNode q = nodes.back();
      (s.axis == kAxisRadial ? q.n : q.m) += s.dir;
      nodes.push_back(q);
    }
    std::vector<Vec2> poly;
    for (int e = 0; e <= 4; ++e) poly.push_back(P[e % 4] * blu);
    const double ref = area_error_cgal(poly, nodes, job.machine.grid.dr, job.machine.grid.dtheta, job.machine.grid.steps_per_rev);
    EXPECT_NEAR(c.polar.area_m2, ref, 1e-10 * ref);
  }
}

}  // namespace tu_pipeline_test_compare
