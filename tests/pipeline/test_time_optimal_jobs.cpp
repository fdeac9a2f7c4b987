// The time-optimal schedule of jobs (pipeline/job_analysis plan_speed, [motion] speed_profile = "time-optimal"):
// on the eight Ch. 6 jobs it is never slower than the best constant speed at the same safety factor and keeps every
// torque ratio within 1/SF + 1e-3 as the existing analysis measures it; the constant speed it is compared with is
// the largest that passes `analyze`; a time-optimal job digitizes along the schedule and `analyze` follows it; the
// machine keys are checked.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "job/job.hpp"
#include "machine/dynamics/verdict.hpp"
#include "pipeline/job_analysis.hpp"
#include "pipeline/job_tape.hpp"
#include "tests/scratch.hpp"

namespace tu_pipeline_test_time_optimal_jobs {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test;

namespace {

std::string example(const std::string& name) { return std::string(POLARCAM_SOURCE_DIR) + "/examples/ch6/" + name + ".toml"; }

const char* kJobs[] = {"circle_inertial",     "circle_grinding", "limacon_inertial", "limacon_grinding",
                       "serpentine_inertial", "serpentine_grinding", "witch_inertial",   "witch_grinding"};

// A circle of the Ch. 5 machine with a time-optimal schedule; `extra_machine` goes into [machine].
std::string topp_job(const std::string& speed = "10 cm/s", const std::string& extra_machine = "",
                     const std::string& extra_motion = "") {
  return "[machine]\nfile = \"machines/fahim1983.toml\"\n" + extra_machine +
         "[contour]\nkind = \"circle\"\nradius = \"5.08 cm\"\n[placement]\nC = \"20.32 cm\"\nbeta = \"3*pi/2 rad\"\n"
         "[tool]\nside = \"left\"\n[motion]\nspeed = \"" + speed + "\"\nspeed_profile = \"time-optimal\"\n" +
         extra_motion + "[load]\nkind = \"inertial\"\nmass = \"14.6 kg\"\n[limits]\nsafety_factor = 1.2\n";
}

}  // namespace

TEST(TimeOptimalJobs, Chapter6JobsBeatTheBestConstantSpeedWithinTheLimits) {
  for (const char* name : kJobs) {
    SCOPED_TRACE(name);
    const Job job = load_job(example(name));
    const PreparedDynamics prep = prepare_dynamics(job);
    const SpeedPlan plan = plan_speed(job, prep, job.load);
    const MachineModel& m = *job.machine.dynamics;
    const double limit = 1.0 / job.safety_factor;

    // the schedule, analysed by the existing analysis at a denser sampling than its own check
    AnalysisOptions dense;
    dense.target_samples = 12000;
    const DynamicsSetup setup = dynamics_setup(job, DynamicsCase{std::nullopt, job.load});
    const DynamicsInput in{prep.path.get(), &prep.track, prep.theta_shift, plan.schedule.profile.get(), &m, &setup.load,
                           prep.side};
    const TorqueAnalysis a = analyze_torques(in, dense);
    EXPECT_LE(a.radial.ratio.value, limit + 1e-3);
    EXPECT_LE(a.angular.ratio.value, limit + 1e-3);
    if (m.radial.max_step_rate) {
      EXPECT_LE(a.radial.step_rate.value, *m.radial.max_step_rate * (1 + 1e-9));
    }
    if (m.angular.max_step_rate) {
      EXPECT_LE(a.angular.step_rate.value, *m.angular.max_step_rate * (1 + 1e-9));
    }
    EXPECT_NEAR(a.duration, plan.time(), 1e-9 * plan.time());

    // the constant speed it is compared with passes `analyze` (the job at that speed), and 1 % more does not
    ASSERT_TRUE(plan.constant_speed.has_value());
    const CaseResult at = analyze_case(job, prep, DynamicsCase{*plan.constant_speed, job.load}, AnalysisOptions{}, false);
    EXPECT_TRUE(at.verdict.go);
    const CaseResult above =
        analyze_case(job, prep, DynamicsCase{*plan.constant_speed * 1.01, job.load}, AnalysisOptions{}, false);
    EXPECT_FALSE(above.verdict.go);
    const double constant_time = prep.track.length() / *plan.constant_speed;
    EXPECT_NEAR(plan.constant_time, constant_time, 1e-12 * constant_time);
    EXPECT_LE(plan.time(), constant_time);
    // from rest to rest
    EXPECT_EQ(plan.schedule.profile->speed_at(0.0), 0.0);
    EXPECT_EQ(plan.schedule.profile->speed_at(prep.track.length()), 0.0);
  }
}

TEST(TimeOptimalJobs, DigitizeAndAnalyzeFollowTheSchedule) {
  Scratch sc;
  const Job job = load_job(sc.write("topp.toml", topp_job()));
  ASSERT_TRUE(job.motion.time_optimal);
  const PreparedDynamics prep = prepare_dynamics(job);
  const SpeedPlan plan = plan_speed(job, prep, job.load);
  // never above the job's speed, which caps the constant speed too
  for (const SpeedStation& st : plan.schedule.stations) ASSERT_LE(st.v, 0.1);
  ASSERT_TRUE(plan.constant_speed.has_value());
  EXPECT_LE(*plan.constant_speed, 0.1);

  const DigitizedJob d = digitize_job(job, nullptr);
  // the tape's profile is the schedule: the same speeds and times everywhere
  for (double f : {0.0, 0.1, 0.37, 0.5, 0.9, 1.0}) {
    const double s = f * prep.track.length();
    EXPECT_EQ(d.profile->speed_at(s), plan.schedule.profile->speed_at(s));
    EXPECT_EQ(d.profile->time_at(s), plan.schedule.profile->time_at(s));
  }
  // the last step is no later than the schedule's end, and within the last stretch at rest-bound speed of it
  const double T = plan.time();
  EXPECT_LE(d.result.last_step_ns * 1e-9, T + 1e-9);
  EXPECT_GT(d.result.last_step_ns * 1e-9, 0.9 * T);

  // analyze: along the schedule, GO, with the comparison
  const CaseResult c = analyze_case(job, prep, DynamicsCase{std::nullopt, job.load}, AnalysisOptions{});
  ASSERT_TRUE(c.plan.has_value());
  EXPECT_TRUE(c.verdict.go);
  EXPECT_NEAR(c.analysis.duration, T, 1e-12 * T);
  EXPECT_NEAR(c.plan->saving(), c.plan->constant_time - T, 1e-12);
}

TEST(TimeOptimalJobs, MachineAndMotionKeysAreChecked) {
  Scratch sc;
  const Job ok = load_job(sc.write("a.toml", topp_job("10 cm/s", "max_acceleration = \"2 cm/s^2\"\n")));
  ASSERT_TRUE(ok.machine.max_acceleration.has_value());
  EXPECT_DOUBLE_EQ(*ok.machine.max_acceleration, 0.02);
  // the schedule keeps it
  const PreparedDynamics prep = prepare_dynamics(ok);
  const SpeedPlan plan = plan_speed(ok, prep, ok.load);
  for (const TorqueSample& x : plan.schedule.check.series) ASSERT_LE(std::abs(x.st.a_t), 0.02 * (1 + 1e-9));
  const double ramp = 0.005;  // V^2 = 2 a s on the first 5 mm (the radial step rate caps it after 9 mm)
  const double v_hand = std::sqrt(2 * 0.02 * ramp);
  EXPECT_LE(plan.schedule.profile->speed_at(ramp), v_hand);
  EXPECT_NEAR(plan.schedule.profile->speed_at(ramp), v_hand, 2e-4 * v_hand);

  auto refused = [&](const std::string& text, const std::string& mention) {
    try {
      load_job(sc.write("bad.toml", text));
      ADD_FAILURE() << "accepted: " << mention;
    } catch (const InputError& e) {
      const std::string w = e.what();
      EXPECT_NE(w.find(mention), std::string::npos) << w;
      EXPECT_EQ(w.find('\n'), std::string::npos) << w;
    }
  };
  refused(topp_job("10 cm/s", "max_acceleration = \"-1 m/s^2\"\n"), "max_acceleration");
  refused(topp_job("10 cm/s", "max_acceleration = \"3 mm\"\n"), "max_acceleration");
  refused(topp_job("10 cm/s", "max_jerk = \"1 m/s^3\"\n"), "max_jerk");
  refused(topp_job("10 cm/s", "", "accel = \"1 m/s^2\"\n"), "accel");
  refused(topp_job("0 cm/s"), "speed");
}

}  // namespace tu_pipeline_test_time_optimal_jobs
