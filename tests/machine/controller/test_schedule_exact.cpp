// The controller's executed times against the tape: the player's compressed schedule run on the simulated
// machine (the controller's own arithmetic), step for step against the tape read independently.
#include <gtest/gtest.h>

#include "machine/controller/sim_machine.hpp"
#include "machine/player/int128.hpp"
#include "machine/player/play_plan.hpp"
#include "machine/player/schedule.hpp"
#include "tests/player_helpers.hpp"

namespace polarcam {
namespace tu_machine_controller_test_schedule_exact {  // named: the test files compile together

using test::example_tape;
using test::read_tape;
using test::scaling;

// Executed times of the compressed schedule, on the controller's own arithmetic, against the tape read
// independently: same axis and direction step for step, and within one controller tick of t / K.
void check_exact(const std::string& name, int64_t K, uint64_t tick_ps) {
  const std::string tape = example_tape(name);
  const auto ref = read_tape(tape);
  PlayPlan p = plan_playback(tape, scaling(std::to_string(K)), std::nullopt);
  Schedule sc = compress_schedule(p, tick_ps);
  ASSERT_EQ(sc.steps[0] + sc.steps[1], ref.size());
  struct Obs : StepMonitor {
    std::vector<ExecutedStep> v;
    void on_step(const ExecutedStep& s) override { v.push_back(s); }
  } obs;
  SimResult r = simulate_playback(p, sc, machine_from_header(p.header), &obs);
  ASSERT_EQ(obs.v.size(), ref.size());
  const uint64_t tape_tick_ps = TapeReader(tape).header().tick_ps;
  for (size_t i = 0; i < ref.size(); ++i) {
    ASSERT_EQ(obs.v[i].axis, ref[i].axis) << name << " step " << i + 1;
    ASSERT_EQ(obs.v[i].dir, ref[i].dir) << name << " step " << i + 1;
    ASSERT_EQ(obs.v[i].node[0], ref[i].n);
    ASSERT_EQ(obs.v[i].node[1], ref[i].m);
    // |executed_ps - t_ps / K| <= tick_ps, in exact integers: |K executed_ps - t_ps| <= K tick_ps
    const i128 exec_ps = static_cast<i128>(obs.v[i].t_ns) * 1000;
    const i128 d = static_cast<i128>(K) * exec_ps - static_cast<i128>(ref[i].t) * tape_tick_ps;
    ASSERT_LE(d < 0 ? -d : d, static_cast<i128>(K) * tick_ps) << name << " step " << i + 1;
  }
  EXPECT_EQ(r.mismatched, 0u);
  EXPECT_LE(r.max_time_error_ns, tick_ps / 1000.0);
}

TEST(Schedule, ExecutedStepsMatchTheTapeWithinOneTickAtOneAndTenTimesSpeed) {
  for (const char* name : {"limacon", "witch", "serpentine", "circle"})
    for (int64_t K : {1, 10}) check_exact(name, K, 1000000);
}

TEST(Schedule, ExactOnAFineTickToo) {
  check_exact("witch", 1, 100000);  // 100 ns tick
  check_exact("limacon", 3, 250000);
}

}  // namespace tu_machine_controller_test_schedule_exact
}  // namespace polarcam
