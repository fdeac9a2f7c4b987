// Milling jobs ([load] kind = "milling", [motion] speed_profile = "constant-force"): the load the dynamics see on a
// circle against the engaged angle and the mean force computed here (the circles' geometry, a quadrature of the
// slice forces); the constant-force example: its tape's step times against the schedule's t(s) at the steps'
// places on the path (found here), the force at nominal where nothing else binds, no limit exceeded.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "job/job.hpp"
#include "job/job_milling.hpp"
#include "machine/dynamics/load.hpp"
#include "pipeline/job_analysis.hpp"
#include "pipeline/job_process.hpp"
#include "pipeline/job_tape.hpp"
#include "process/milling_force.hpp"
#include "tests/scratch.hpp"

namespace tu_pipeline_test_milling_jobs {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kMm = 1e-3;

const char* kTool =
    "[tool]\ndiameter = \"12.7 mm\"\nlength = \"44.5 mm\"\nteeth = 4\nhelix_angle = \"38 deg\"\n"
    "breaking_stress = \"1500 N/mm^2\"\nyoungs_modulus = \"207 GPa\"\n";

// A circle of radius 5.08 cm milled on its outside at a constant speed.
std::string circle_job(const std::string& motion, const std::string& extra_load = "") {
  return "[machine]\nfile = \"machines/fahim1983.toml\"\n[contour]\nkind = \"circle\"\nradius = \"5.08 cm\"\n"
         "[placement]\nC = \"20.32 cm\"\nbeta = \"3*pi/2 rad\"\n[tool]\nradius = \"6.35 mm\"\nside = \"outside\"\n"
         "[motion]\n" + motion +
         "[load]\nkind = \"milling\"\ntool = \"tool.toml\"\nspindle_speed = \"2000 rpm\"\naxial_depth = \"5 mm\"\n"
         "radial_width = \"1.5 mm\"\nK_t = \"700 N/mm^2\"\nK_r = \"210 N/mm^2\"\n" + extra_load;
}

// The mean force of up milling over [0, psi] at a chip f sin(phi), by Simpson's rule: (x, y) of the feed frame.
std::pair<double, double> mean_up(double psi, double f, double b, int N, double Kt, double Kr) {
  const int n = 4000;
  double sx = 0, sy = 0;
  for (int i = 0; i <= n; ++i) {
    const double p = psi * i / n, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    const double h = f * std::sin(p);
    sx += w * (-Kt * b * h * std::cos(p) - Kr * b * h * std::sin(p));
    sy += w * (Kt * b * h * std::sin(p) - Kr * b * h * std::cos(p));
  }
  const double k = N / (2 * kPi) * psi / n / 3;
  return {k * sx, k * sy};
}

}  // namespace

// Outside a circle of radius rho = 50.8 mm the cutter's centre runs at rho_c = rho + R. Its edge meets the stock's
// boundary (radius rho + a) where |P| = rho + a, P on the cutter circle: the law of cosines, solved here by
// bisection on the angle from the circle's centre direction. The contour turns counter-clockwise and the tool is
// outside, on the right: an M03 spindle mills up. The edge's chip is the centre's feed per tooth scaled to the middle
// of the cut, (rho + a/2) / rho_c.
TEST(MillingJobs, TheLoadOnACircleIsTheSliceModelsMeanForce) {
  Scratch sc;
  sc.write("tool.toml", kTool);
  const Job job = load_job(sc.write("job.toml", circle_job("speed = \"1 cm/s\"\n")));
  ASSERT_TRUE(job.milling);
  EXPECT_EQ(job.milling->path->mode(), process::MillingMode::up);
  const double R = 6.35 * kMm, rho = 50.8 * kMm, a = 1.5 * kMm, rc = rho + R;
  double lo = 0, hi = kPi;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    const double d = std::sqrt(rc * rc + R * R - 2 * rc * R * std::cos(mid));
    (d < rho + a ? lo : hi) = mid;
  }
  const double psi = lo;
  const double V = 0.01, ft = V / (4 * 2000.0 / 60.0);  // 0.075 mm
  const auto [fx, fy] = mean_up(psi, ft * (rho + 0.5 * a) / rc, 5 * kMm, 4, 700e6, 210e6);
  const Load load = make_load(job.load);
  for (double s : {0.0, 0.05, 0.2}) {
    const ToolForce f = load.force(s, V);
    EXPECT_NEAR(f.tangential, -fx, 1e-6 * std::abs(fx));
    EXPECT_NEAR(f.normal, -fy, 1e-6 * std::abs(fy) + 1e-9);  // up milling: the material on +y
  }
  // twice the speed, twice the force
  EXPECT_NEAR(load.force(0.1, 2 * V).tangential, -2 * fx, 2e-6 * std::abs(fx));
  // `analyze` sees the same load
  const PreparedDynamics prep = prepare_dynamics(job);
  const CaseResult r = analyze_case(job, prep, DynamicsCase{std::nullopt, job.load}, AnalysisOptions{});
  EXPECT_NEAR(r.load.force(0.1, V).tangential, -fx, 1e-6 * std::abs(fx));
  EXPECT_GT(r.analysis.radial.ratio.value, 0.0);
}

TEST(MillingJobs, KeysAreChecked) {
  Scratch sc;
  sc.write("tool.toml", kTool);
  const std::string good = circle_job("speed = \"1 cm/s\"\n");
  EXPECT_NO_THROW(load_job(sc.write("good.toml", good)));
  auto bad = [&](const std::string& text) { EXPECT_THROW(load_job(sc.write("bad.toml", text)), InputError) << text; };
  bad(replace(good, "radius = \"6.35 mm\"", "radius = \"5 mm\""));          // not the mill's radius
  bad(replace(good, "radial_width = \"1.5 mm\"", "radial_width = \"13 mm\""));  // wider than the mill
  // deeper than the tool stands out of its holder (44.5 mm); the whole length is still a cut
  EXPECT_NO_THROW(load_job(sc.write("deep.toml", replace(good, "axial_depth = \"5 mm\"", "axial_depth = \"44.5 mm\""))));
  try {
    load_job(sc.write("deeper.toml", replace(good, "axial_depth = \"5 mm\"", "axial_depth = \"1e29 mm\"")));
    ADD_FAILURE() << "an axial depth of 1e29 mm was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("axial_depth"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("44.5 mm"), std::string::npos) << e.what();
  }
  bad(replace(good, "K_t = \"700 N/mm^2\"\n", ""));                         // missing
  bad(replace(good, "tool = \"tool.toml\"", "tool = \"none.toml\""));       // no such file
  bad(replace(good, "axial_depth = \"5 mm\"", "axial_depth = \"5 mm\"\ncolour = 1"));  // unknown key
  bad(circle_job("speed_profile = \"constant-force\"\nnominal_force = \"50 N\"\n"));  // no top speed
  bad(circle_job("speed_profile = \"constant-force\"\nspeed = \"1 cm/s\"\n"));  // no nominal force
  // constant force without a milling load
  bad("[machine]\nfile = \"machines/fahim1983.toml\"\n[contour]\nkind = \"circle\"\nradius = \"5.08 cm\"\n"
      "[placement]\nC = \"20.32 cm\"\nbeta = \"3*pi/2 rad\"\n[motion]\nspeed_profile = \"constant-force\"\n"
      "speed = \"1 cm/s\"\nnominal_force = \"50 N\"\n");
}

// The example: the tape's step times follow the schedule. Each step's node is placed on the tool path (the nearest
// of 40 000 points sampled along it here, searched forward from the last step's), and the time the schedule gives
// there, t(s) = sum 2 h / (V_i + V_i+1) over its stations, must be the step's time within the time the tool needs
// to cross the node's distance from the path.
TEST(MillingJobs, TheExamplesTapeFollowsTheConstantForceSchedule) {
  const Job job = load_job(std::string(POLARCAM_SOURCE_DIR) + "/examples/process/contour_milling.toml");
  const process::ConstantForceSchedule sch = constant_force_job_schedule(job);
  struct Log : StepSink {
    int64_t n = 0, m = 0;
    std::vector<std::tuple<int64_t, int64_t, int64_t>> steps;
    void begin(int64_t n0, int64_t m0) override { n = n0, m = m0; }
    void step(int axis, int dir, int64_t t) override {
      (axis == kAxisRadial ? n : m) += dir;
      steps.emplace_back(n, m, t);
    }
  } log;
  const DigitizedJob d = digitize_job(job, &log);
  ASSERT_GT(log.steps.size(), 1000u);
  // the path, sampled with its arc length
  const ToolPathPtr path = make_job_path(job);
  const int K = 40000;
  std::vector<Vec2> pts;
  std::vector<double> sv;
  double s = 0;
  for (int k = 0; k <= K; ++k) {
    const double u = path->u_begin() + (path->u_end() - path->u_begin()) * k / K;
    const Vec2 p = path->eval(u, 0).p;
    if (k > 0) s += std::hypot(p.x - pts.back().x, p.y - pts.back().y);
    pts.push_back(p);
    sv.push_back(s);
  }
  auto t_of = [&](double x) {  // the schedule's time at arc length x, V^2 linear between stations
    double t = 0;
    for (size_t i = 0; i + 1 < sch.stations.size(); ++i) {
      const auto &p = sch.stations[i], &q = sch.stations[i + 1];
      if (x >= q.s) {
        t += 2 * (q.s - p.s) / (p.v + q.v);
        continue;
      }
      const double w = (x - p.s) / (q.s - p.s);
      const double vx = std::sqrt(p.v * p.v + w * (q.v * q.v - p.v * p.v));
      return t + 2 * (x - p.s) / (p.v + vx);
    }
    return t;
  };
  const Grid& g = job.machine.grid;
  size_t at = 0;
  double worst = 0;
  for (const auto& [n, m, t] : log.steps) {
    const double r = n * g.dr, th = m * g.dtheta - d.result.theta_shift;
    const Vec2 q{r * std::cos(th), r * std::sin(th)};
    size_t best = at;
    double bd = 1e300;
    for (size_t k = at; k < std::min(pts.size(), at + 400); ++k) {
      const double dd = std::hypot(q.x - pts[k].x, q.y - pts[k].y);
      if (dd < bd) bd = dd, best = k;
    }
    at = best;
    ASSERT_LT(bd, 0.2 * kMm) << "a step's node is far from the path";
    worst = std::max(worst, std::abs(t * 1e-9 - t_of(sv[best])));
  }
  EXPECT_GT(at, pts.size() - 10);  // the steps went all the way round
  // the nodes lie within about 0.1 mm of the path (0.08 mm of angular resolution at 20 cm): 0.1 mm at the
  // slowest feed of the schedule (4.6 mm/s on entry) is 22 ms; a constant 14 mm/s would be seconds off by the end
  EXPECT_LT(worst, 0.03);
  EXPECT_NEAR(d.result.duration_ns * 1e-9, sch.total_time_s, 1e-6 * sch.total_time_s);
}

// Where the nominal force binds, the mean resultant force at the schedule's speed (by the quadrature above, at the
// station's engaged angle and edge feed) is the nominal force within 1 %, and nowhere is it above. Where the
// deflection limit binds (a tight deflection tolerance on the circle), the peak of the force perpendicular to the
// feed (the slice model sampled finely here) is at its limit and not above.
TEST(MillingJobs, ForceAtNominalAndNoLimitExceeded) {
  Scratch sc;
  sc.write("tool.toml", std::string(kTool) + "deflection_tolerance = \"0.00005 in\"\n");
  const std::string example = std::string(POLARCAM_SOURCE_DIR) + "/examples/process/contour_milling.toml";
  struct Case {
    Job job;
    double b;
    const char* binds;
  };
  const Case cases[] = {
      {load_job(example), 6.35 * kMm, "nominal_force"},
      {load_job(sc.write("job.toml", circle_job("speed_profile = \"constant-force\"\nspeed = \"1.5 cm/s\"\n"
                                                "nominal_force = \"160 N\"\n"))),
       5 * kMm, "deflection_force"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.job.file);
    const double F_nom = c.job.motion.nominal_force;
    const process::ConstantForceSchedule sch = constant_force_job_schedule(c.job);
    const process::MillingPath& mp = *c.job.milling->path;
    const process::ToolLimits& lim = c.job.milling->limits;
    const process::SliceCutter cut{4, 6.35 * kMm, 38 * kPi / 180, c.b, 700e6, 210e6, 0.0};
    int binding = 0;
    for (const process::FeedStation& f : sch.stations) {
      const process::MillingStation& st = mp.stations()[f.station];
      const double ft = f.v / (4 * 2000.0 / 60.0) * st.feed_scale;
      const auto [fx, fy] = mean_up(st.engaged_angle, ft, c.b, 4, 700e6, 210e6);
      const double F = std::hypot(fx, fy);
      EXPECT_LE(F, F_nom * 1.01);
      if (process::to_string(f.binding) != std::string(c.binds)) continue;
      ++binding;
      if (f.binding == process::FeedBinding::nominal_force) {
        EXPECT_NEAR(F, F_nom, 0.01 * F_nom);
      }
      if (f.binding == process::FeedBinding::deflection && binding % 25 == 1) {
        const process::Immersion im = process::immersion_for(process::MillingMode::up, st.engaged_angle);
        double peak = 0;
        for (int k = 0; k < 900; ++k)
          peak = std::max(peak, std::abs(process::slice_force(cut, im, ft, 2 * kPi * k / 900 / 4, 300).y));
        EXPECT_LE(peak, *lim.deflection_force_limit_N * 1.01);
        EXPECT_GE(peak, *lim.deflection_force_limit_N * 0.98);  // it is the binding one: at its limit
      }
    }
    // after the entry, the stated limit binds almost everywhere
    EXPECT_GT(binding, static_cast<int>(sch.stations.size()) * 9 / 10);
    const ProcessRun run = run_process(c.job);
    EXPECT_TRUE(run.exceeded.empty());
    if (lim.deflection_force_limit_N) {
      EXPECT_LE(run.max_normal_force_N, *lim.deflection_force_limit_N * (1 + 1e-9));
    }
    EXPECT_LE(run.max_peak_force_N, lim.breakage_force_N);
  }
}

}  // namespace tu_pipeline_test_milling_jobs
