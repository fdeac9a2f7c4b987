// A large theta-rho pattern through the pipeline (pipeline/job_tape, pipeline/preview) on the example sand table
// (coupled arm): digitized from its streamed track (no track pieces held), its steps against a count made here from
// the vertices, and the preview from one pass of the digitizer drawing the nodes the tape walks.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "job/pattern.hpp"
#include "pipeline/job_tape.hpp"
#include "pipeline/preview.hpp"
#include "tests/big_pattern.hpp"
#include "tests/scratch.hpp"

namespace tu_pipeline_test_pattern_stream {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test;

namespace {

// The example sand table's grid, coupling and radius, as its machine file states them (worked out here).
const double kDr = 0.040 / (200 * 16);
const double kDtheta = 2 * std::numbers::pi / (200 * 16 * 6.25);
const double kCoupling = 2560 * kDr / (2 * std::numbers::pi);
const double kRadius = 0.200;

Job pattern_job(const Scratch& sc, const std::vector<PatternVertex>& v) {
  PatternOptions o;
  o.machine_file = std::string(POLARCAM_SOURCE_DIR) + "/examples/machines/sand-table.toml";
  o.speed = 0.040;
  return load_job_or_pattern(sc.write("big.thr", thr_text(v)), o);
}

long long node(double q, double res) { return static_cast<long long>(std::floor(q / res + 0.5)); }

class Count : public StepSink {
 public:
  void step(int axis, int, int64_t) override { ++n[axis]; }
  long long n[2] = {0, 0};
};

}  // namespace

TEST(PatternStream, APatternIsDigitizedFromItsVerticesWithoutHoldingATrack) {
  Scratch sc;
  const auto v = big_spiral_pattern(20000);
  const Job job = pattern_job(sc, v);
  Count count;
  const DigitizedJob d = digitize_job(job, &count);
  // what is held: the streamed track of the vertices, no track pieces
  ASSERT_TRUE(d.polyline.has_value());
  EXPECT_TRUE(d.track.pieces().empty());
  EXPECT_GE(d.polyline->size(), v.size() - 1);
  EXPECT_EQ(&d.polyline->path(), job_theta_rho_path(*d.path));
  // on each segment both motor coordinates are linear: a motor moves by the difference of its nearest nodes at
  // the two ends
  long long radial = 0, angular = 0;
  for (size_t k = 1; k < v.size(); ++k) {
    const double qa = v[k - 1].rho * kRadius + kCoupling * v[k - 1].theta, qb = v[k].rho * kRadius + kCoupling * v[k].theta;
    radial += std::llabs(node(qb, kDr) - node(qa, kDr));
    angular += std::llabs(node(v[k].theta, kDtheta) - node(v[k - 1].theta, kDtheta));
  }
  EXPECT_EQ(count.n[0], radial);
  EXPECT_EQ(count.n[1], angular);
  EXPECT_EQ(static_cast<long long>(d.result.radial.steps()), radial);
  EXPECT_EQ(static_cast<long long>(d.result.angular.steps()), angular);
  // the ranges of what the ball draws (rho 0..1 of the table, theta from the first vertex to the last)
  const PathRanges pr = path_ranges(d);
  EXPECT_EQ(pr.r_min, 0.0);
  EXPECT_DOUBLE_EQ(pr.r_max, kRadius);
  EXPECT_DOUBLE_EQ(pr.theta_min, v.front().theta);
  EXPECT_DOUBLE_EQ(pr.theta_max, v.back().theta);
}

TEST(PatternStream, ThePreviewComesFromOnePassAndDrawsTheTapesNodes) {
  Scratch sc;
  const auto v = big_spiral_pattern(5000);
  const Job job = pattern_job(sc, v);
  DigitizedJob d;
  const Preview pv = preview_job(job, 0.05, &d);
  EXPECT_EQ(pv.steps, d.result.radial.steps() + d.result.angular.steps());
  ASSERT_TRUE(d.polyline.has_value());
  // the tool path: 16 samples a piece of the track and its end
  ASSERT_EQ(pv.path.size(), 1u);
  EXPECT_EQ(pv.path[0].x.size(), 16 * d.polyline->size() + 1);
  EXPECT_NEAR(pv.path[0].x.front(), v.front().rho * kRadius * std::cos(v.front().theta) * 1e3, 1e-9);
  EXPECT_NEAR(pv.path[0].y.back(), v.back().rho * kRadius * std::sin(v.back().theta) * 1e3, 1e-9);
  // the stepped motion starts on the tape's start node and ends on its end node (the ball at r = q - c theta)
  auto xy = [](int64_t n, int64_t m, double& x, double& y) {
    const double th = static_cast<double>(m) * kDtheta, r = static_cast<double>(n) * kDr - kCoupling * th;
    x = r * std::cos(th) * 1e3, y = r * std::sin(th) * 1e3;
  };
  double x, y;
  ASSERT_FALSE(pv.stepped.empty());
  xy(d.result.start_n, d.result.start_m, x, y);
  EXPECT_NEAR(pv.stepped.front().x.front(), x, 1e-9);
  EXPECT_NEAR(pv.stepped.front().y.front(), y, 1e-9);
  EXPECT_EQ(d.result.start_n, node(v.front().rho * kRadius + kCoupling * v.front().theta, kDr));
  EXPECT_EQ(d.result.start_m, node(v.front().theta, kDtheta));
  xy(d.result.end_n, d.result.end_m, x, y);
  EXPECT_NEAR(pv.stepped.back().x.back(), x, 1e-9);
  EXPECT_NEAR(pv.stepped.back().y.back(), y, 1e-9);
  // the slowed stretches: near the centre (the timing radius is 40 mm/s over 3 rad/s = 13.3 mm), nowhere else
  ASSERT_FALSE(pv.slowed.empty());
  for (const Polyline& s : pv.slowed)
    for (size_t i = 0; i < s.x.size(); ++i) EXPECT_LE(std::hypot(s.x[i], s.y[i]), 40.0 / 3.0 + 1e-6);
}

}  // namespace tu_pipeline_test_pattern_stream
