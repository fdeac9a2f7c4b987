// A job of several contours on a machine that lifts its tool (pipeline/job_tape): each contour stepped exactly as
// a job of its own, each rapid move's steps against an independent walk of the straight motor-space segment (its
// level crossings in closed form, its times from an arc length integrated here), the tool events alternating, and
// the steps of the whole job adding up to its end node less its start node.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "pipeline/job_tape.hpp"

namespace tu_pipeline_test_job_lift {  // the test files of a program compile together (unity build)

using namespace polarcam;

namespace {

struct Rec {
  int axis;  // 0, 1; -1 a tool event
  int dir;   // step direction; for an event +1 down, -1 up
  int64_t t;
};

class Recorder : public StepSink {
 public:
  void step(int axis, int dir, int64_t t) override { r.push_back({axis, dir, t}); }
  void tool(bool down, int64_t t) override { r.push_back({-1, down ? 1 : -1, t}); }
  std::vector<Rec> r;
};

Grid grid() {
  Grid g;
  g.dr = 0.02e-3;
  g.steps_per_rev = 8000;
  g.dtheta = dtheta_from_steps(g.steps_per_rev);
  g.r_max = 0.1;
  return g;
}

// Three contours: a line, a circle clear of the pole (closed, no winding), another line whose start lies at a
// negative atan2 angle (so the job takes it on the turn nearest the circle's end).
Job lifting_job(double rapid_speed) {
  Job job;
  job.file = "lift-test";
  job.machine.grid = grid();
  job.machine.tool_lift = true;
  job.machine.rapid_speed = rapid_speed;
  job.parts = {make_line({0.02, 0.0}, {0.04, 0.01}), make_circle({-0.03, 0.02}, 0.01),
               make_line({-0.01, -0.03}, {0.03, -0.02})};
  job.contour = job.parts.front();
  job.contours = job.parts.size();
  job.tool.side = ToolSide::left;
  job.motion.speed = 0.02;
  job.motion.rule = StepRule::nearest;
  return job;
}

// The contour alone, as a job of one contour steps it: its own start node and branch, its own clock.
std::vector<Rec> alone(const Job& job, size_t k) {
  const ToolPathPtr p = make_tool_path(job.parts[k], job.placement, job.tool, job.motion.travel);
  const PolarTrack tr = PolarTrack::build(*p);
  Recorder rec;
  digitize(tr, job.machine.grid, job.motion.rule, *make_job_profile(job, tr.length()), &rec);
  return rec.r;
}

// Arc length along the segment linear in r and theta from (ra, tha) to (rb, thb), from 0 to fraction f: composite
// 10-point Gauss-Legendre on 16 panels, in long double.
long double arc(long double ra, long double tha, long double rb, long double thb, long double f) {
  static const long double x[5] = {0.1488743389816312108848260L, 0.4333953941292471907992659L,
                                   0.6794095682990244062343274L, 0.8650633666889845107320967L,
                                   0.9739065285171717200779640L};
  static const long double w[5] = {0.2955242247147528701738930L, 0.2692667193099963550912269L,
                                   0.2190863625159820439955349L, 0.1494513491505805931457763L,
                                   0.0666713443086881375935688L};
  const long double dr = rb - ra, dth = thb - tha;
  auto g = [&](long double u) {
    const long double r = ra + u * dr;
    return std::sqrt(dr * dr + r * r * dth * dth);
  };
  long double s = 0;
  const int panels = 16;
  for (int p = 0; p < panels; ++p) {
    const long double a = f * p / panels, b = f * (p + 1) / panels, m = 0.5L * (a + b), h = 0.5L * (b - a);
    for (int i = 0; i < 5; ++i) s += h * w[i] * (g(m - h * x[i]) + g(m + h * x[i]));
  }
  return s;
}

}  // namespace

TEST(JobLift, ContoursAreSteppedAsTheirOwnJobsAndRapidsAsStraightMotorSegments) {
  const double V_rapid = 0.05;
  const Job job = lifting_job(V_rapid);
  ASSERT_TRUE(job_lifts_tool(job));
  Recorder rec;
  const DigitizedJob d = digitize_job(job, &rec);
  ASSERT_TRUE(d.lifted);
  ASSERT_EQ(d.lifted->rapids.size(), 2u);
  const Grid g = grid();
  const double pi = std::numbers::pi;

  // split the records at the tool events: contour, up, rapid, down, contour, ...
  std::vector<std::vector<Rec>> contours(1), rapids;
  std::vector<int64_t> up_t, down_t;
  bool up = false;
  int64_t last_t = 0;
  for (const Rec& r : rec.r) {
    EXPECT_GE(r.t, last_t);
    last_t = r.t;
    if (r.axis < 0) {
      ASSERT_EQ(r.dir > 0, up) << "tool events alternate from down";
      up = r.dir < 0;
      if (up) {
        up_t.push_back(r.t);
        rapids.emplace_back();
      } else {
        down_t.push_back(r.t);
        contours.emplace_back();
      }
      continue;
    }
    (up ? rapids.back() : contours.back()).push_back(r);
  }
  EXPECT_FALSE(up);
  ASSERT_EQ(contours.size(), 3u);
  ASSERT_EQ(rapids.size(), 2u);

  // conservation: the steps of the whole tape are its end node less its start node
  int64_t sum[2] = {0, 0};
  for (const Rec& r : rec.r)
    if (r.axis >= 0) sum[r.axis] += r.dir;
  EXPECT_EQ(sum[0], d.result.end_n - d.result.start_n);
  EXPECT_EQ(sum[1], d.result.end_m - d.result.start_m);
  EXPECT_EQ(d.result.radial.steps() + d.result.angular.steps(), rec.r.size() - 4);

  // each contour: the steps of the contour as a job of its own, on the job's clock from its tool-down event
  for (size_t k = 0; k < 3; ++k) {
    SCOPED_TRACE("contour " + std::to_string(k + 1));
    const std::vector<Rec> own = alone(job, k);
    const int64_t t0 = k == 0 ? 0 : down_t[k - 1];
    ASSERT_EQ(contours[k].size(), own.size());
    for (size_t i = 0; i < own.size(); ++i) {
      EXPECT_EQ(contours[k][i].axis, own[i].axis) << i;
      EXPECT_EQ(contours[k][i].dir, own[i].dir) << i;
      EXPECT_EQ(contours[k][i].t, own[i].t + t0) << i;
    }
  }

  // each rapid: from the end of contour k to the start of contour k + 1, linear in r and theta, the start angle on
  // the turn nearest the end angle; written here from the contours' own geometry
  const double ends[3][2][2] = {
      {{0.02, 0.0}, {0.04, 0.01}}, {{-0.02, 0.02}, {-0.02, 0.02}}, {{-0.01, -0.03}, {0.03, -0.02}}};
  int64_t node[2] = {d.result.start_n, d.result.start_m};
  double th_end_prev = 0;
  for (size_t k = 0; k < 3; ++k) {
    // the angle of contour k's start on the branch the job takes (the first: [0, 2 pi))
    double th_start = std::atan2(ends[k][0][1], ends[k][0][0]);
    if (k == 0) th_start -= 2 * pi * std::floor(th_start / (2 * pi));
    else th_start += 2 * pi * std::nearbyint((th_end_prev - th_start) / (2 * pi));
    const double th_end_raw = std::atan2(ends[k][1][1], ends[k][1][0]);
    const double th_end = th_end_raw + 2 * pi * std::nearbyint((th_start - th_end_raw) / (2 * pi));
    if (k > 0) {
      SCOPED_TRACE("rapid " + std::to_string(k));
      const long double ra = std::hypot(ends[k - 1][1][0], ends[k - 1][1][1]), tha = th_end_prev;
      const long double rb = std::hypot(ends[k][0][0], ends[k][0][1]), thb = th_start;
      // the nodes the rapid starts from: where contour k ended (the steps so far)
      EXPECT_EQ(node[0], std::llround(static_cast<double>(ra / g.dr)));
      EXPECT_EQ(node[1], std::llround(static_cast<double>(tha / g.dtheta)));
      // the crossings of r = (n + 1/2) dR and theta = (m + 1/2) dtheta along the segment, by fraction f
      struct Cross {
        long double f;
        int axis, dir;
      };
      std::vector<Cross> want;
      const long double lo[2] = {ra / g.dr, tha / g.dtheta}, hi[2] = {rb / g.dr, thb / g.dtheta};
      for (int a = 0; a < 2; ++a) {
        const int dir = hi[a] > lo[a] ? 1 : -1;
        for (int64_t n = node[a];; n += dir) {
          const long double level = static_cast<long double>(n) + 0.5L * dir;
          if (dir > 0 ? !(hi[a] >= level) : !(hi[a] < level)) break;
          want.push_back({(level - lo[a]) / (hi[a] - lo[a]), a, dir});
        }
      }
      std::stable_sort(want.begin(), want.end(), [](const Cross& x, const Cross& y) {
        return x.f < y.f || (x.f == y.f && x.axis < y.axis);
      });
      const std::vector<Rec>& got = rapids[k - 1];
      EXPECT_GT(want.size(), 500u) << "a rapid of a few centimetres crosses many levels";
      ASSERT_EQ(got.size(), want.size());
      EXPECT_EQ(got.size(), d.lifted->rapids[k - 1].steps);
      const long double len = arc(ra, tha, rb, thb, 1.0L);
      EXPECT_NEAR(static_cast<double>(len), d.lifted->rapids[k - 1].length_m, 1e-12);
      for (size_t i = 0; i < want.size(); ++i) {
        EXPECT_EQ(got[i].axis, want[i].axis) << i;
        EXPECT_EQ(got[i].dir, want[i].dir) << i;
        const long double t = static_cast<long double>(up_t[k - 1]) + arc(ra, tha, rb, thb, want[i].f) / V_rapid * 1e9L;
        EXPECT_LE(std::abs(static_cast<double>(t) - static_cast<double>(got[i].t)), 1.0) << i;
      }
      // the rapid's duration at rapid_speed: its length over the speed, to the nanosecond
      EXPECT_NEAR(static_cast<double>(down_t[k - 1] - up_t[k - 1]), static_cast<double>(len / V_rapid * 1e9L), 1.0);
      for (const Rec& r : got) node[r.axis] += r.dir;
    }
    for (const Rec& r : contours[k]) node[r.axis] += r.dir;
    th_end_prev = th_end;
  }
  EXPECT_EQ(node[0], d.result.end_n);
  EXPECT_EQ(node[1], d.result.end_m);
}

TEST(JobLift, OneContourOrNoLiftIsTheJobOfOneContour) {
  Job job = lifting_job(0.05);
  job.machine.tool_lift = false;
  EXPECT_FALSE(job_lifts_tool(job));
  job.machine.tool_lift = true;
  job.parts.resize(1);
  EXPECT_FALSE(job_lifts_tool(job));
  Recorder rec;
  const DigitizedJob d = digitize_job(job, &rec);
  EXPECT_FALSE(d.lifted);
  for (const Rec& r : rec.r) EXPECT_GE(r.axis, 0) << "no tool event for one contour";
}

TEST(JobLift, AContourOutsideTheWorkAreaIsNamed) {
  Job job = lifting_job(0.05);
  job.parts[1] = make_circle({-0.08, 0.02}, 0.03);  // reaches 0.11 m > r_max
  try {
    digitize_job(job, nullptr);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("contour 2 of 3"), std::string::npos) << m;
    EXPECT_NE(m.find("r_max"), std::string::npos) << m;
    EXPECT_NE(m.find("lift-test"), std::string::npos) << m;
  }
}

}  // namespace tu_pipeline_test_job_lift
