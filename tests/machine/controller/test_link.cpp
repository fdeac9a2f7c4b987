// The controller protocol end to end in-process: the host link over an emulated serial line with
// faults (virtual clock), the emulator's executed steps against the tape, underruns, holds, resets.
#include <gtest/gtest.h>

#include <atomic>

#include "cam/error.hpp"
#include "machine/controller/emulator.hpp"
#include "machine/link/host_link.hpp"
#include "machine/player/play_plan.hpp"
#include "machine/link/protocol.hpp"
#include "machine/link/sim_line.hpp"
#include "tests/player_helpers.hpp"
#include "tests/tape_log.hpp"

namespace polarcam {
namespace tu_machine_controller_test_link {  // named: the test files compile together

using test::example_tape;

using Logged = test::LoggedStep;

struct LinkRun {
  PlayReport rep;
  std::vector<Logged> log;
};

LinkRun play_in_process(const std::string& tape, int64_t K, const FaultSpec& faults, double baud = 115200,
                        uint32_t slots = 4096, LinkOptions lo = LinkOptions{}, ControllerSpec spec = ControllerSpec{}) {
  PlayScaling s;
  s.speed = Ratio{K, 1};
  PlayPlan plan = plan_playback(tape, s, std::nullopt);
  spec.slots = slots;
  SimTransport tr(spec, baud, faults);
  LinkRun run;
  tr.emulator().on_step = [&](uint64_t t, int axis, int dir) { run.log.push_back({t, axis, dir}); };
  HostLink link(tr, lo);
  proto::Ident id = link.identify();
  Schedule sc = compress_schedule(plan, id.tick_ps);
  run.rep = link.play(plan, sc);
  return run;
}

TEST(Link, LimaconAtOneAndTenTimesSpeedWithoutFaults) {
  const std::string tape = example_tape("limacon");
  for (int64_t K : {1, 10}) {
    LinkRun run = play_in_process(tape, K, FaultSpec{});
    test::expect_log_follows_tape(tape, K, run.log);
    EXPECT_TRUE(run.rep.completed);
    EXPECT_EQ(run.rep.underruns, 0u);
    EXPECT_EQ(run.rep.retransmissions, 0u);
    EXPECT_EQ(run.rep.steps_confirmed, run.log.size());
  }
}

TEST(Link, OnePercentOfBytesDroppedOrCorruptedInEachDirection) {
  for (const char* name : {"limacon", "serpentine"})
    for (int64_t K : {1, 10}) {
      const std::string tape = example_tape(name);
      const FaultSpec f = parse_faults("drop=0.01,corrupt=0.01,seed=" + std::to_string(K + 11));
      LinkRun run = play_in_process(tape, K, f);
      test::expect_log_follows_tape(tape, K, run.log);
      EXPECT_EQ(run.rep.underruns, 0u) << name << " x" << K;
      EXPECT_GT(run.rep.retransmissions, 0u);
    }
}

// A controller as small as the reference firmware: its queue holds 384 bytes of encoded items (the limacon's
// schedule is about 1 150), and it drops the frames that arrive after a missing one (its NAK says so; the host
// sends them again with the missing one). On a clean line nothing is sent twice; with 1 % of the bytes dropped and
// 1 % corrupted each way, no underrun on several seeds, every step within one tick. Without byte credits the host
// would overrun its queue (the controller faults with "queue overflow").
TEST(Link, SmallQueueInBytesWithoutFramesAheadRidesOutAFaultyLine) {
  ControllerSpec small;
  small.queue_bytes = 384;
  small.keep_ahead = false;
  for (const auto& [name, K] : {std::pair<const char*, int64_t>{"limacon", 2}, {"serpentine", 1}}) {
    const std::string tape = example_tape(name);
    LinkRun clean = play_in_process(tape, K, FaultSpec{}, 115200, 4096, LinkOptions{}, small);
    test::expect_log_follows_tape(tape, K, clean.log);
    EXPECT_EQ(clean.rep.underruns, 0u) << name;
    EXPECT_EQ(clean.rep.retransmissions, 0u) << name;
    EXPECT_EQ(clean.rep.naks, 0u) << name;
    for (int seed : {3, 7, 11}) {
      const FaultSpec f = parse_faults("drop=0.01,corrupt=0.01,seed=" + std::to_string(seed));
      LinkRun run = play_in_process(tape, K, f, 115200, 4096, LinkOptions{}, small);
      test::expect_log_follows_tape(tape, K, run.log);
      EXPECT_EQ(run.rep.underruns, 0u) << name << " seed " << seed;
      EXPECT_GT(run.rep.naks, 0u) << name << " seed " << seed;
      EXPECT_TRUE(run.rep.completed);
    }
  }
}

TEST(Link, DelayedBytesAndAShortStallAreAbsorbedByTheBuffer) {
  const std::string tape = example_tape("witch");
  const FaultSpec f = parse_faults("delay=0.001,stall=0.3@1,disconnect=0.3@2");
  LinkRun run = play_in_process(tape, 10, f);
  test::expect_log_follows_tape(tape, 10, run.log);
  EXPECT_EQ(run.rep.underruns, 0u);
}

TEST(Link, UnderrunIsDetectedReportedAndStopsTheAxes) {
  // 2400 baud cannot carry the serpentine at 20x: the controller must stop (never stretch timing silently),
  // report it, and the host resumes once it has refilled the buffer
  const std::string tape = example_tape("serpentine");
  LinkOptions lo;
  lo.prefill_s = 0.05;
  lo.ramp_s = 0.01;
  lo.baud = 2400;
  LinkRun run = play_in_process(tape, 20, FaultSpec{}, 2400, 4096, lo);
  EXPECT_GT(run.rep.underruns, 0u);
  EXPECT_TRUE(run.rep.completed);
  EXPECT_EQ(run.rep.steps_confirmed, run.rep.steps_total);
  // the axes still executed the tape's steps in order; only the timing around the stops differs
  TapeReader rd(tape);
  StepRecord r;
  size_t i = 0;
  while (rd.next(r)) {
    ASSERT_EQ(run.log[i].axis, r.axis);
    ASSERT_EQ(run.log[i].dir, r.dir);
    ++i;
  }
}

// A line that loses every STATUS reply sent while the controller is stopped for want of items (the long frames a
// noisy line loses first: 86 bytes, whole one time in six at 2 % of the bytes lost). The host sees the stop, and
// its RESUME taken, from the ACKs, which carry the controller's state too; a host that waited for a STATUS reply
// would never resume (the line's clock runs out at 600 s: a failure, not a hang).
struct LosesUnderrunStatus : Transport {
  SimTransport& t;
  proto::FrameDecoder dec;
  uint64_t lost = 0;
  explicit LosesUnderrunStatus(SimTransport& s) : t(s) {}
  bool write(const std::string& b, double to) override { return t.write(b, to); }
  std::string read(double to) override {
    if (t.now() > 600) throw PlayError("the play did not end within 600 s of the line's clock");
    const std::string in = t.read(to);
    std::vector<proto::Frame> frames;
    dec.feed(reinterpret_cast<const uint8_t*>(in.data()), in.size(), frames);
    std::string out;
    for (const proto::Frame& f : frames) {
      proto::Status st;
      if (f.type == proto::STATUS_REPLY && proto::Status::decode(f.payload, st) && st.state == proto::State::underrun) {
        ++lost;
        continue;
      }
      out += proto::encode_frame(f.seq, f.type, f.payload);
    }
    return out;
  }
  double now() override { return t.now(); }
  std::string describe() const override { return "a line that loses the underrun's STATUS replies"; }
};

TEST(Link, AnUnderrunStopIsSeenAndResumedFromTheAcksWithoutAStatusReply) {
  // as above: 2400 baud cannot carry the serpentine at 20x
  const std::string tape = example_tape("serpentine");
  PlayScaling s;
  s.speed = Ratio{20, 1};
  PlayPlan plan = plan_playback(tape, s, std::nullopt);
  SimTransport sim(ControllerSpec{}, 2400, FaultSpec{});
  std::vector<Logged> log;
  sim.emulator().on_step = [&](uint64_t t, int axis, int dir) { log.push_back({t, axis, dir}); };
  LosesUnderrunStatus line(sim);
  LinkOptions lo;
  lo.prefill_s = 0.05;
  lo.ramp_s = 0.01;
  lo.baud = 2400;
  HostLink link(line, lo);
  const proto::Ident id = link.identify();
  const Schedule sc = compress_schedule(plan, id.tick_ps);
  const PlayReport rep = link.play(plan, sc);
  EXPECT_TRUE(rep.completed);
  EXPECT_GT(rep.underruns, 0u);
  EXPECT_GT(line.lost, 0u);  // the controller was stopped when asked, and no STATUS reply said so
  EXPECT_EQ(rep.steps_confirmed, rep.steps_total);
  TapeReader rd(tape);
  StepRecord r;
  size_t i = 0;
  while (rd.next(r)) {
    ASSERT_LT(i, log.size());
    ASSERT_EQ(log[i].axis, r.axis);
    ASSERT_EQ(log[i].dir, r.dir);
    ++i;
  }
  EXPECT_EQ(i, log.size());
}

TEST(Link, ControllerResetStopsThePlayWithTheLastConfirmedStep) {
  const std::string tape = example_tape("witch");
  FaultSpec f;
  f.reset_at = 1.5;
  try {
    play_in_process(tape, 1, f);
    FAIL() << "a reset must stop the play";
  } catch (const PlayError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("reset"), std::string::npos) << m;
    EXPECT_NE(m.find("confirmed"), std::string::npos) << m;
    EXPECT_NE(m.find("re-home"), std::string::npos) << m;
  }
}

TEST(Link, SilentControllerIsAClearErrorBeforeAnyStep) {
  const std::string tape = example_tape("witch");
  ControllerSpec spec;
  SimTransport tr(spec, 115200, FaultSpec{});
  tr.emulator().garble = true;  // a wrong baud rate: nothing intelligible either way
  LinkOptions lo;
  lo.identify_tries = 2;
  lo.identify_timeout_s = 0.05;
  HostLink link(tr, lo);
  try {
    link.identify();
    FAIL();
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("--baud"), std::string::npos) << e.what();
  }
  EXPECT_EQ(tr.emulator().controller().status().queued, 0u);
}

TEST(Link, ControllerWithAnotherGridRefusesTheJob) {
  const std::string tape = example_tape("witch");
  PlayPlan plan = plan_playback(tape, PlayScaling{}, std::nullopt);
  ControllerSpec spec;
  spec.dr = plan.header.res[0] * 2;
  spec.dtheta = plan.header.res[1];
  SimTransport tr(spec, 115200, FaultSpec{});
  HostLink link(tr, LinkOptions{});
  proto::Ident id = link.identify();
  Schedule sc = compress_schedule(plan, id.tick_ps);
  EXPECT_THROW(link.play(plan, sc), InputError);
  EXPECT_EQ(tr.emulator().controller().status().executed[0] + tr.emulator().controller().status().executed[1], 0u);
}

// A transport that asks for a feed hold at 1 s and a resume at 3 s of its clock.
struct HoldingTransport : Transport {
  SimTransport& t;
  std::atomic<bool>& hold;
  std::atomic<bool>& resume;
  bool held = false, resumed = false;
  HoldingTransport(SimTransport& s, std::atomic<bool>& h, std::atomic<bool>& r) : t(s), hold(h), resume(r) {}
  bool write(const std::string& b, double to) override { return t.write(b, to); }
  std::string read(double to) override {
    if (!held && t.now() > 1.0) held = true, hold.store(true);
    if (!resumed && t.now() > 3.0) resumed = true, resume.store(true);
    return t.read(to);
  }
  double now() override { return t.now(); }
  std::string describe() const override { return "holding"; }
};

TEST(Link, FeedHoldAndResumeKeepEveryStepInOrder) {
  const std::string tape = example_tape("witch");
  PlayScaling s;
  s.speed = Ratio{10, 1};
  PlayPlan plan = plan_playback(tape, s, std::nullopt);
  SimTransport tr(ControllerSpec{}, 115200, FaultSpec{});
  std::vector<Logged> log;
  tr.emulator().on_step = [&](uint64_t t, int axis, int dir) { log.push_back({t, axis, dir}); };
  std::atomic<bool> hold{false}, resume{false};
  HoldingTransport ht(tr, hold, resume);
  LinkOptions lo;
  lo.ramp_s = 0.05;
  HostLink link(ht, lo);
  link.hold_request = &hold;
  link.resume_request = &resume;
  proto::Ident id = link.identify();
  PlayReport rep = link.play(plan, compress_schedule(plan, id.tick_ps));
  EXPECT_EQ(rep.underruns, 0u);
  ASSERT_EQ(log.size(), plan.steps.size());
  for (size_t i = 0; i < log.size(); ++i) {
    ASSERT_EQ(log[i].axis, plan.steps[i].axis);
    ASSERT_EQ(log[i].dir, plan.steps[i].dir);
  }
  // the job (2.9 s at 10x) took about 2 s longer: held from about 1 s to 3 s of the host's clock
  EXPECT_GT(rep.duration_s, 4.0);
  EXPECT_LT(rep.duration_s, 5.5);
}

TEST(Controller, HoldAndResumeRampTheRateAndKeepEveryStep) {
  const std::string tape = example_tape("witch");
  PlayScaling s;
  PlayPlan plan = plan_playback(tape, s, std::nullopt);
  Schedule sc = compress_schedule(plan, 1000000);
  ControllerSpec spec;
  spec.slots = static_cast<uint32_t>(sc.items.size() + 1);
  Controller c(spec);
  proto::Configure cfg;
  cfg.tick_ps = spec.tick_ps;
  cfg.ramp_ticks = 100000;  // 0.1 s
  cfg.start[0] = plan.start[0];
  cfg.start[1] = plan.start[1];
  ASSERT_TRUE(c.configure(cfg, nullptr));
  for (const QueueItem& it : sc.items) ASSERT_TRUE(c.push(it));
  std::vector<uint64_t> t;
  std::vector<int> ax;
  c.on_step = [&](uint64_t tk, int a, int) {
    t.push_back(tk);
    ax.push_back(a);
  };
  c.start(0);
  c.advance(5000000);  // 5 s
  const size_t before = t.size();
  c.hold();
  c.advance(5100000);
  EXPECT_EQ(c.state(), proto::State::held);
  const size_t held_at = t.size();
  c.advance(8000000);  // 3 s held: nothing moves
  EXPECT_EQ(t.size(), held_at);
  c.resume();
  c.advance(sc.last_tick + 10000000);
  EXPECT_EQ(c.state(), proto::State::done);
  ASSERT_EQ(t.size(), plan.steps.size());
  for (size_t i = 0; i < t.size(); ++i) ASSERT_EQ(ax[i], plan.steps[i].axis);
  // before the hold, exact; after, shifted by the hold (about 3 s plus half of each ramp)
  EXPECT_GT(held_at, before);
  const uint64_t shift = t.back() - sc.last_tick;
  EXPECT_NEAR(static_cast<double>(shift), 3.0e6, 0.15e6);
}

}  // namespace tu_machine_controller_test_link
}  // namespace polarcam
