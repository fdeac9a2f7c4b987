// Tool items end to end: a tape that lifts its tool (tests/player_helpers.hpp, lifting_tape) played through the
// host link to the emulator, on a clean line and on a faulty one to a controller as small as the reference
// firmware, resumed halfway, and refused by a controller that drives no tool. The emulator's log of steps and tool
// events is checked against the tape read independently and the times the tape was written with.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "cam/error.hpp"
#include "machine/controller/controller.hpp"
#include "machine/controller/emulator.hpp"
#include "machine/link/host_link.hpp"
#include "machine/link/protocol.hpp"
#include "machine/player/play_plan.hpp"
#include "tests/player_helpers.hpp"
#include "tests/temp_path.hpp"

namespace polarcam {
namespace tu_machine_controller_test_tool_link {  // named: the test files compile together

using test::kLiftDownNs;
using test::kLiftUpNs;
using test::lifting_tape;

struct Entry {
  uint64_t t_ns = 0;
  bool tool = false;
  int axis = 0, dir = 0;  // a step
  bool down = false;      // a tool event
};

struct ToolRun {
  PlayReport rep;
  std::vector<Entry> log;
};

ToolRun play(const PlayPlan& plan, const FaultSpec& faults, const ControllerSpec& spec) {
  SimTransport tr(spec, 115200, faults);
  ToolRun run;
  tr.emulator().on_step = [&](uint64_t t, int axis, int dir) { run.log.push_back({t, false, axis, dir, false}); };
  tr.emulator().on_tool = [&](uint64_t t, bool down) { run.log.push_back({t, true, 0, 0, down}); };
  HostLink link(tr, LinkOptions{});
  const proto::Ident id = link.identify();
  EXPECT_EQ(id.caps & wire::kCapTool, wire::kCapTool);
  run.rep = link.play(plan, compress_schedule(plan, id.tick_ps));
  return run;
}

// The log of a lifting tape (1 ns tape ticks) played from step `done` at speed scale K with the tool dwell, against
// the tape read independently (its steps, and its events through the tape reader): first the tool's state at that
// step (down unless the events before it left it up), then every step of the tape and the events between them, in
// order; each within one 1 us tick of its time from step `done`, scaled, plus a dwell for every tool event before
// it.
void expect_lifting_log(const std::vector<Entry>& log, const std::string& path, uint64_t done, double K,
                        double dwell_s) {
  const std::vector<test::TapeStep> tape = test::read_tape(path);
  std::vector<ToolEvent> events;
  TapeReader rd(path);
  rd.on_tool_event([&](const ToolEvent& e) { events.push_back(e); });
  for (StepRecord r; rd.next(r);) {
  }
  ASSERT_GT(events.size(), 0u);
  const double t0 = done ? static_cast<double>(tape[done - 1].t) : 0.0;
  const double dwell_ns = dwell_s * 1e9;
  std::vector<Entry> want;
  std::vector<double> exact;
  bool state = true;
  size_t e = 0;
  for (; e < events.size() && events[e].steps_before <= done; ++e) state = events[e].down;
  want.push_back({0, true, 0, 0, state});
  exact.push_back(0.0);
  double tools = 1;  // tool events so far
  for (size_t i = done; i < tape.size(); ++i) {
    for (; e < events.size() && events[e].steps_before == i; ++e) {
      want.push_back({0, true, 0, 0, events[e].down});
      exact.push_back((static_cast<double>(events[e].t_ticks) - t0) / K + tools * dwell_ns);
      ++tools;
    }
    want.push_back({0, false, tape[i].axis, tape[i].dir, false});
    exact.push_back((static_cast<double>(tape[i].t) - t0) / K + tools * dwell_ns);
  }
  ASSERT_EQ(log.size(), want.size());
  for (size_t k = 0; k < log.size(); ++k) {
    ASSERT_EQ(log[k].tool, want[k].tool) << "entry " << k;
    if (want[k].tool) {
      ASSERT_EQ(log[k].down, want[k].down) << "entry " << k;
    } else {
      ASSERT_EQ(log[k].axis, want[k].axis) << "entry " << k;
      ASSERT_EQ(log[k].dir, want[k].dir) << "entry " << k;
    }
    EXPECT_LE(std::fabs(static_cast<double>(log[k].t_ns) - exact[k]), 1000.0 + 1e-6) << "entry " << k;
  }
}

// A longer drawing: 40 strokes of 300 steps (r+ and theta+ alternating every 40 us), each but the last followed
// by the tool up 25 us later, a rapid of 60 r- steps every 15 us, and the tool down with the rapid's last step.
std::string many_lifts_tape() {
  const std::string path = test::temp_path("many-lifts.tape");
  TapeHeader h;
  h.res[0] = 0.0254e-3;
  h.steps_per_rev = 16000;
  h.res[1] = dtheta_from_steps(h.steps_per_rev);
  h.has_r_max = true;
  h.r_max = 0.3;
  h.speed_mps = 0.01;
  h.start[0] = 5000, h.start[1] = 0;
  TapeWriter w(path, h);
  uint64_t t = 0;
  for (int k = 0; k < 40; ++k) {
    for (int j = 0; j < 300; ++j) w.step(j % 2, +1, static_cast<int64_t>(t += 40000));
    if (k == 39) break;
    w.tool(false, static_cast<int64_t>(t += 25000));
    for (int j = 0; j < 60; ++j) w.step(0, -1, static_cast<int64_t>(t += 15000));
    w.tool(true, static_cast<int64_t>(t));
  }
  h.end[0] = 5000 + 40 * 150 - 39 * 60, h.end[1] = 40 * 150;
  h.duration_ticks = t;
  w.finish(h);
  return path;
}

TEST(ToolLink, LiftingTapeIsPlayedStepForStepWithItsToolEvents) {
  for (const int64_t K : {1, 4}) {
    PlayScaling s;
    s.speed = Ratio{K, 1};
    PlayPlan plan = plan_playback(lifting_tape(), s, std::nullopt);
    plan.tool_dwell_s = 0.005;
    const ToolRun run = play(plan, FaultSpec{}, ControllerSpec{});
    expect_lifting_log(run.log, lifting_tape(), 0, static_cast<double>(K), 0.005);
    EXPECT_TRUE(run.rep.completed);
    EXPECT_EQ(run.rep.tool_events, 3u);
    EXPECT_EQ(run.rep.steps_confirmed, 500u);
  }
}

// 1 % of the bytes dropped and 1 % corrupted each way, to a controller that keeps its queue as 384 bytes of items
// and no frame after a missing one (the reference firmware's): a tool item late at the controller would act late.
TEST(ToolLink, OnAFaultyLineToAControllerAsSmallAsTheFirmware) {
  ControllerSpec spec;
  spec.queue_bytes = 384;
  spec.keep_ahead = false;
  const std::string tape = many_lifts_tape();
  PlayPlan plan = plan_playback(tape, PlayScaling{}, std::nullopt);
  plan.tool_dwell_s = 0.05;
  const ToolRun run = play(plan, parse_faults("drop=0.01,corrupt=0.01,seed=9"), spec);
  expect_lifting_log(run.log, tape, 0, 1.0, 0.05);
  std::remove(tape.c_str());
  EXPECT_EQ(run.rep.tool_events, 79u);
  EXPECT_EQ(run.rep.underruns, 0u);
  EXPECT_GT(run.rep.retransmissions, 10u);  // the line did lose frames
}

// After --resume the controller is told the tool's state at the resume point before the first step: down in the
// first stroke, up in the rapid, down again in the second stroke.
TEST(ToolLink, ResumedPlayTellsTheControllerTheToolStateFirst) {
  const PlayPlan plan = plan_playback(lifting_tape(), PlayScaling{}, std::nullopt);
  for (const uint64_t done : {150u, 200u, 250u, 320u}) {
    PlayPlan r = resume_plan(plan, done);
    r.tool_dwell_s = 0.01;
    const ToolRun run = play(r, FaultSpec{}, ControllerSpec{});
    expect_lifting_log(run.log, lifting_tape(), done, 1.0, 0.01);
  }
}

// A controller that drives no tool says so at IDENTIFY (no capability bit); the host refuses a lifting tape in one
// line naming the tape before the job is configured, and sends nothing of it.
TEST(ToolLink, ControllerThatDrivesNoToolIsRefusedBeforeTheJob) {
  ControllerSpec spec;
  spec.tool = false;
  SimTransport tr(spec, 115200, FaultSpec{});
  HostLink link(tr, LinkOptions{});
  const proto::Ident id = link.identify();
  EXPECT_EQ(id.caps & wire::kCapTool, 0);
  const PlayPlan plan = plan_playback(lifting_tape(), PlayScaling{}, std::nullopt);
  try {
    link.play(plan, compress_schedule(plan, id.tick_ps));
    FAIL() << "a lifting tape needs a tool";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("drives no tool"), std::string::npos) << m;
    EXPECT_NE(m.find(lifting_tape()), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  EXPECT_EQ(tr.emulator().controller().state(), proto::State::idle);  // never configured
  EXPECT_EQ(link.report().frames_sent, 0u);                           // nothing of the job
}

// The controller itself: without a tool it refuses a QUEUE frame with a tool item (bad_queue, the job faults);
// with one, a tool item acts at its tick after the steps of that tick, and ABORT leaves the tool up.
TEST(ToolLink, ControllerExecutesOrRefusesToolItems) {
  QueueItem down;
  down.kind = ItemKind::tool;
  down.dir = 1;
  down.wait = 10;
  QueueItem run;
  run.kind = ItemKind::run;
  run.axis = 0;
  run.dir = 1;
  run.count = 3;
  run.interval = wire::kOneTick * 5;  // steps at ticks 5, 10, 15
  QueueItem end0, end1;
  end0.kind = end1.kind = ItemKind::end;
  end1.axis = 1;
  proto::Configure cfg;
  cfg.tick_ps = ControllerSpec{}.tick_ps;
  {
    ControllerSpec spec;
    spec.tool = false;
    Controller c(spec);
    ASSERT_TRUE(c.configure(cfg, nullptr));
    EXPECT_FALSE(c.push(down));
    std::string payload;
    ItemCodec codec;
    codec.encode(down, payload);
    const std::string f = proto::encode_frame(1, proto::QUEUE, payload);
    c.receive(reinterpret_cast<const uint8_t*>(f.data()), f.size(), 1);
    EXPECT_EQ(c.state(), proto::State::fault);
    EXPECT_EQ(c.status().error, proto::ErrorCode::bad_queue);
  }
  Controller c{ControllerSpec{}};
  ASSERT_TRUE(c.configure(cfg, nullptr));
  std::vector<std::string> log;
  c.on_step = [&](uint64_t t, int axis, int) { log.push_back(std::to_string(t) + (axis ? " theta" : " r")); };
  c.on_tool = [&](uint64_t t, bool d) { log.push_back(std::to_string(t) + (d ? " down" : " up")); };
  for (const QueueItem& it : {down, run, end0, end1}) ASSERT_TRUE(c.push(it));
  EXPECT_FALSE(c.tool_down());
  c.start(0);
  c.advance(100);
  EXPECT_EQ(log, (std::vector<std::string>{"5 r", "10 r", "10 down", "15 r"}));
  EXPECT_TRUE(c.tool_down());
  EXPECT_EQ(c.state(), proto::State::done);
  const std::string abort = proto::encode_frame(1, proto::ABORT, "");
  c.receive(reinterpret_cast<const uint8_t*>(abort.data()), abort.size(), 101);
  EXPECT_FALSE(c.tool_down());
}

}  // namespace tu_machine_controller_test_tool_link
}  // namespace polarcam
