#pragma once
// The stepper controller of the protocol (docs/controller-protocol.md), as firmware would run it: frames in,
// frames out, the step schedule executed on its own tick clock. Used by the emulator (`polarcam
// controller-sim`), by the in-process simulated machine and by tests. No ports and no wall clock: the caller
// says what tick it is.
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "machine/link/protocol.hpp"
#include "machine/player/schedule.hpp"

namespace polarcam {

struct ControllerSpec {
  uint64_t tick_ps = 1000000;   // timer tick (1 us)
  uint32_t slots = 4096;        // queue items it can buffer
  uint32_t queue_bytes = 0;     // and bytes of encoded items (0: no limit); the reference firmware's is 384
  bool keep_ahead = true;       // keeps frames that arrive after a missing one (the reference firmware does not)
  uint32_t max_step_rate = 0;   // steps per second it reports (IDENT); 0: one step per axis per tick
  bool tool = true;             // drives a tool and executes tool items (IDENT's capability); false: refuses them
  std::string name = "polarcam controller emulator";
  double dr = 0, dtheta = 0;    // its machine grid, when it knows one (0: accepts any)
};

class Controller {
 public:
  explicit Controller(ControllerSpec spec, uint32_t session = 1);

  // Bytes that arrived at controller tick `now` (ticks since boot; never decreasing).
  void receive(const uint8_t* data, size_t n, uint64_t now);
  // Executes the schedule up to tick `now`.
  void advance(uint64_t now);
  // Frames to send to the host (cleared by the call).
  std::string take_output();
  // Fault injection: reboot (everything lost; a new session id; announces itself with BOOT).
  void reboot(uint64_t now);

  // Every executed step: time in ticks since START, axis, direction.
  std::function<void(uint64_t t_ticks, int axis, int dir)> on_step;
  // Every executed tool item: time in ticks since START, down (true) or up. Within a tick, after its steps.
  std::function<void(uint64_t t_ticks, bool down)> on_tool;

  // In-process use without the link (the simulated machine): configure, queue items and start directly.
  bool configure(const proto::Configure& c, std::string* why);
  bool push(const QueueItem& it, uint32_t bytes = 0);  // bytes: its encoded size, for queue_bytes
  void start(uint64_t now);
  void hold();
  void resume();

  proto::Status status() const;
  proto::State state() const { return state_; }
  uint32_t free_slots() const;
  uint32_t free_bytes() const;  // kUnlimited without a queue_bytes limit
  // The tool's state: down after a tool item that lowered it (up after CONFIGURE, ABORT and a reboot).
  bool tool_down() const { return tool_down_; }
  const ControllerSpec& spec() const { return spec_; }

 private:
  struct Axis {
    std::deque<QueueItem> q;
    std::deque<uint32_t> q_bytes;  // their encoded sizes
    AxisClock clk;           // execution clock
    AxisClock tail;          // clock at the end of the queued items (for the horizon)
    bool ended_queued = false, ended = false;
    RunCursor run;           // the current run
    int dir = 1;             // its direction
    bool has_next = false;   // next step computed
    uint64_t next_tick = 0;  // schedule tick of the next step
    uint64_t executed = 0;
    int64_t node = 0;
  };
  void handle(const proto::Frame& f, uint64_t now);
  void handle_queue(const std::string& payload);
  void send(uint8_t type, uint16_t seq, const std::string& payload);
  void send_ack();
  void send_error(proto::ErrorCode code, const std::string& text, uint16_t seq);
  bool fresh_request(uint8_t type, uint16_t id);
  bool prepare_next(Axis& a);
  void send_nak();
  void renak();
  uint64_t horizon(const Axis& a) const;
  void run_to(uint64_t now);
  void fire_due();
  void pop_tool();
  void start_ramp(int direction, proto::State during);

  ControllerSpec spec_;
  uint32_t session_;
  proto::FrameDecoder dec_;
  std::string out_;
  proto::State state_ = proto::State::idle;
  proto::ErrorCode error_ = proto::ErrorCode::none;
  bool configured_ = false;
  proto::Configure cfg_;
  ItemCodec codec_;
  Axis ax_[2];
  std::deque<QueueItem> tools_;     // tool items not executed yet, in order
  std::deque<uint32_t> tool_bytes_;
  bool tool_down_ = false;
  uint16_t next_seq_ = 1;
  std::map<uint16_t, proto::Frame> pending_;  // sequenced frames received ahead of a missing one
  std::map<uint8_t, uint16_t> last_req_;      // last request id per out-of-band type
  uint16_t last_nak_ = 0;
  bool nak_sent_ = false;
  bool hole_ = false;            // a frame came ahead of next_seq_ since it was last received
  uint32_t underruns_ = 0;
  uint32_t queued_items_ = 0;
  uint32_t queued_bytes_ = 0;
  uint32_t acked_free_bytes_ = 0;  // free_bytes in the last ACK sent
  uint64_t nak_time_ = 0;        // boot tick of the last NAK
  // clocks
  uint64_t now_ = 0;             // ticks since boot
  uint64_t start_ = 0;           // boot tick of START
  uint64_t last_step_ = 0;       // ticks since START of the latest step
  bool started_ = false;
  uint64_t tau_ = 0;             // schedule time since START, 1/65536 ticks
  uint64_t rate_ = 0;            // playback rate, in 1/ramp units (ramp_ == rate_ means 1)
  uint64_t ramp_ = 0;
  int ramp_dir_ = 0;             // -1 ramping down, +1 up, 0 steady
};

}  // namespace polarcam
