#pragma once
// The host side of the controller protocol (docs/controller-protocol.md): identifies and configures the
// controller, streams the compressed schedule under its buffer credits with acknowledgements and selective
// retransmission, polls status, resumes after an underrun stop, reconnects after a silent link, and stops with
// a clear message after a controller reset. Works over any Transport (a serial port, or an in-process line).
#include <atomic>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

#include "cam/error.hpp"
#include "machine/player/play_plan.hpp"
#include "machine/link/protocol.hpp"
#include "machine/player/schedule.hpp"

namespace polarcam {

// The playback failed after it began (link lost, controller reset or fault, operator stop): a device error,
// exit status 3.
class PlayError : public DeviceError {
 public:
  using DeviceError::DeviceError;
};

// The port itself failed (hung up, a read or write error): the controller is gone or unplugged.
class LinkLost : public PlayError {
 public:
  using PlayError::PlayError;
};

class Transport {
 public:
  virtual ~Transport() = default;
  // Writes all bytes; false when the other side did not take them within timeout_s (a stalled reader).
  // Throws PlayError when the port is gone.
  virtual bool write(const std::string& bytes, double timeout_s) = 0;
  // Bytes that arrive within timeout_s (possibly none). Throws PlayError when the port is gone.
  virtual std::string read(double timeout_s) = 0;
  virtual double now() = 0;  // seconds, monotonic
  // Closes and reopens the port; false when it cannot be reopened now.
  virtual bool reconnect() { return false; }
  virtual std::string describe() const = 0;  // "/dev/ttyUSB0 at 115200 baud"
};

struct LinkOptions {
  size_t max_payload = 64;       // QUEUE payload bytes per frame
  unsigned window = 16;          // frames in flight
  double rto_s = 0.2;            // retransmission timeout
  double status_period_s = 0.1;  // status polling
  // IDENTIFY is asked again every identify_timeout_s (a reply to any earlier ask counts): its ~60-byte reply
  // arrives whole with probability 0.98^70 = 0.24 on a line that drops and corrupts 1 % of bytes each way, so
  // 20 asks fail together with probability 0.76^20 = 0.4 % (8 asks: 11 %); 3 s in all before "no answer".
  double identify_timeout_s = 0.15;
  int identify_tries = 20;
  double link_timeout_s = 2.0;   // silence before a reconnect
  double reconnect_timeout_s = 10.0;
  double write_timeout_s = 5.0;  // a reader that takes nothing for this long has stalled: fail
  double prefill_s = 2.0;        // schedule time queued before START (or a full buffer, or the whole job)
  double ramp_s = 0.0;           // hold/resume/underrun ramp of the playback rate
  double baud = 115200;          // line rate, for pacing: the host never queues more than pace_s of bytes ahead
  double pace_s = 0.03;          //   of the line, and times retransmissions from when a frame has left
};

struct PlayProgress {
  uint64_t steps_confirmed = 0, steps_total = 0;
  double schedule_s = 0, total_s = 0, elapsed_s = 0;
  double buffer_fill = 0;  // 0..1
  proto::State state = proto::State::idle;
};

struct PlayReport {
  std::string controller;
  uint64_t tick_ps = 0;
  uint64_t steps_total = 0, steps_sent = 0, steps_confirmed = 0;
  uint64_t items = 0, frames_sent = 0, bytes_sent = 0, retransmissions = 0, naks = 0, bad_frames = 0;
  uint64_t underruns = 0, reconnects = 0;
  uint64_t tool_events = 0;  // tool items in the schedule (the tool's state at the start, then the tape's events)
  double duration_s = 0;   // controller time from START to the last step
  double wall_s = 0;
  int64_t end_node[2] = {0, 0};
  bool completed = false;
  // The run stopped where the controller said it was (the link was lost, or the operator stopped it) and can go on
  // from steps_confirmed on the same machine; false after a controller reset (its position is unknown).
  bool resumable = false;
};

class HostLink {
 public:
  HostLink(Transport& t, LinkOptions o);
  // IDENTIFY (with retries). Throws InputError when nothing answers (wrong port or baud rate).
  proto::Ident identify();
  // Configures the controller for `plan` and streams `sched`; returns when the controller has executed it.
  PlayReport play(const PlayPlan& plan, const Schedule& sched);
  // What was sent and confirmed so far (also after play() threw).
  const PlayReport& report() const { return rep_; }

  std::function<void(const PlayProgress&)> on_progress;
  std::atomic<bool>* stop = nullptr;  // set by a signal handler: hold, then abort
  // Feed hold and resume (set by the caller, e.g. from signals; cleared when sent). The controller ramps the
  // playback rate down or up with the job's acceleration limit (LinkOptions::ramp_s).
  std::atomic<bool>* hold_request = nullptr;
  std::atomic<bool>* resume_request = nullptr;

 private:
  struct Out {
    uint16_t seq;
    std::string bytes;
    uint32_t slots;
    size_t item_bytes;  // the payload: encoded items
    uint64_t steps;
    double sent;
  };
  void send_raw(const std::string& f);
  double line_free_at_ = 0;      // when the bytes written so far will have left the host
  void poll(double timeout_s);
  void on_frame(const proto::Frame& f);
  uint16_t next_req() { return ++req_; }
  proto::Ack configure(const proto::Configure& c);

  Transport& t_;
  LinkOptions o_;
  proto::FrameDecoder dec_;
  uint16_t req_ = 0;
  uint32_t session_ = 0;
  bool have_session_ = false;
  // latest answers
  bool got_ident_ = false, got_status_ = false, got_ack_ = false;
  proto::Ident ident_;
  proto::Status status_;
  proto::Ack ack_;           // latest ACK of the sequenced stream
  uint16_t reply_seq_ = 0;   // seq of the latest reply to an out-of-band request
  bool got_reply_ = false;
  proto::ErrorMsg error_;
  bool got_error_ = false, rebooted_ = false;
  uint32_t boot_session_ = 0;
  proto::State state_ = proto::State::idle;  // the controller's latest state heard (ACK or STATUS reply)
  double state_at_ = -1e9;                   // when it was heard
  uint16_t nak_seq_ = 0;
  bool got_nak_ = false, nak_kept_ = true;
  double last_rx_ = 0;
  PlayReport rep_;
};

}  // namespace polarcam
