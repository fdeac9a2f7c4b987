#include "machine/link/host_link.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <vector>

#include "cam/error.hpp"

namespace polarcam {

using namespace proto;

HostLink::HostLink(Transport& t, LinkOptions o) : t_(t), o_(o) {}

void HostLink::send_raw(const std::string& f) {
  if (!t_.write(f, o_.write_timeout_s))
    throw PlayError(t_.describe() + ": the controller has stopped reading (nothing taken for " +
                    std::to_string(o_.write_timeout_s) + " s)");
  ++rep_.frames_sent;
  rep_.bytes_sent += f.size();
  const double now = t_.now();
  line_free_at_ = std::max(line_free_at_, now) + (o_.baud > 0 ? static_cast<double>(f.size()) * 10.0 / o_.baud : 0.0);
}

void HostLink::on_frame(const Frame& f) {
  switch (f.type) {
    case ACK: {
      Ack a;
      if (!Ack::decode(f.payload, a)) return;
      if (f.seq != 0) {  // the answer to an out-of-band request
        reply_seq_ = f.seq;
        got_reply_ = true;
      }
      if (!got_ack_ || seq_diff(a.next_seq, ack_.next_seq) >= 0) ack_ = a;
      got_ack_ = true;
      state_ = static_cast<State>(a.state);  // the controller's state as it sent this
      state_at_ = t_.now();
      return;
    }
    case NAK: {
      wire::Nak n;
      if (n.decode(reinterpret_cast<const uint8_t*>(f.payload.data()), f.payload.size())) {
        nak_seq_ = n.next_seq;
        nak_kept_ = n.kept != 0;
        got_nak_ = true;
        ++rep_.naks;
      }
      return;
    }
    case IDENT:
      // a controller of another protocol version is named at identify(), not taken for silence
      if (Ident::decode(f.payload, ident_) || (!f.payload.empty() && ident_.version != kVersion)) {
        got_ident_ = true;
        reply_seq_ = f.seq;
      }
      return;
    case STATUS_REPLY:
      if (Status::decode(f.payload, status_)) {
        got_status_ = true;
        state_ = status_.state;
        state_at_ = t_.now();
        if (got_ack_ && seq_diff(status_.next_seq, ack_.next_seq) >= 0) {  // fresher credits than the last ACK
          ack_.next_seq = status_.next_seq;
          ack_.free_slots = status_.free_slots;
          ack_.free_bytes = status_.free_bytes;
        }
        if (have_session_ && status_.session != session_) {
          rebooted_ = true;
          boot_session_ = status_.session;
        }
      }
      return;
    case ERROR:
      if (ErrorMsg::decode(f.payload, error_)) {
        got_error_ = true;
        reply_seq_ = f.seq;
      }
      return;
    case BOOT:
      rebooted_ = true;
      if (f.payload.size() == 4) boot_session_ = static_cast<uint32_t>(Reader{f.payload}.u32());
      return;
    default:
      return;
  }
}

void HostLink::poll(double timeout_s) {
  std::string in = t_.read(timeout_s);
  if (in.empty()) return;
  last_rx_ = t_.now();
  std::vector<Frame> frames;
  dec_.feed(reinterpret_cast<const uint8_t*>(in.data()), in.size(), frames);
  rep_.bad_frames = dec_.bad_frames();
  for (const Frame& f : frames) on_frame(f);
}

Ident HostLink::identify() {
  for (int attempt = 0; attempt < o_.identify_tries; ++attempt) {
    got_ident_ = false;
    const uint16_t id = next_req();
    send_raw(encode_frame(id, IDENTIFY, ""));
    const double until = t_.now() + o_.identify_timeout_s;
    while (t_.now() < until) {
      poll(0.01);
      if (got_ident_) {
        if (ident_.version != kVersion)
          throw InputError("the controller speaks protocol version " + std::to_string(ident_.version) +
                           ", this polarcam speaks version " + std::to_string(kVersion), t_.describe());
        if (ident_.tick_ps == 0) throw InputError("the controller reports a zero tick", t_.describe());
        session_ = ident_.session;
        have_session_ = true;
        rebooted_ = false;  // a BOOT before this answer was the controller starting up (a board resets on open)
        return ident_;
      }
    }
  }
  throw DeviceError("no answer from a polarcam controller (" + std::to_string(o_.identify_tries) +
                   " tries): check --port and --baud", t_.describe());
}

Ack HostLink::configure(const Configure& c) {
  const double give_up = t_.now() + o_.link_timeout_s + o_.reconnect_timeout_s;
  const uint16_t first = static_cast<uint16_t>(req_ + 1);
  // a reply to any of this call's attempts will do (the same configuration each time)
  auto ours = [&](uint16_t seq) { return seq_diff(seq, first) >= 0 && seq_diff(seq, req_) <= 0; };
  while (t_.now() < give_up) {
    const uint16_t id = next_req();
    got_reply_ = false;
    got_error_ = false;
    send_raw(encode_frame(id, CONFIGURE, c.encode()));
    const double until = line_free_at_ + o_.rto_s;
    while (t_.now() < until) {
      poll(0.01);
      if (got_error_ && ours(reply_seq_)) {
        if (error_.code == ErrorCode::grid_mismatch || error_.code == ErrorCode::bad_config || error_.code == ErrorCode::busy)
          throw InputError("the controller refuses the job: " + error_.text, t_.describe());
        throw PlayError(t_.describe() + ": the controller refuses the job: " + error_.text);
      }
      if (got_reply_ && ours(reply_seq_)) return ack_;
      if (rebooted_) throw PlayError(t_.describe() + ": the controller reset while being configured");
    }
  }
  throw PlayError(t_.describe() + ": the controller does not answer CONFIGURE");
}

PlayReport HostLink::play(const PlayPlan& plan, const Schedule& sc) {
  rep_ = PlayReport{};
  rep_.controller = ident_.name;
  rep_.tick_ps = sc.tick_ps;
  rep_.steps_total = sc.steps[0] + sc.steps[1];
  rep_.items = sc.items.size();
  rep_.tool_events = sc.tools;
  const double tick_s = static_cast<double>(sc.tick_ps) * 1e-12;
  const double t0 = t_.now();
  // a lifting tape needs a controller that drives a tool: refused before the job is sent
  if (sc.tools > 0 && !(ident_.caps & wire::kCapTool))
    throw InputError("the tape lifts and lowers the tool (" + std::to_string(plan.header.event_count) +
                         " tool events) and the controller on " + t_.describe() + " (" + ident_.name +
                         ") drives no tool: play it on a controller with a tool output, or each contour as a tape "
                         "of its own",
                     plan.tape);

  Configure c;
  c.tick_ps = sc.tick_ps;
  c.ramp_ticks = static_cast<uint64_t>(std::llround(o_.ramp_s / tick_s));
  c.start[0] = plan.start[0];
  c.start[1] = plan.start[1];
  c.dr = plan.header.res[0];
  c.dtheta = plan.header.res[1];
  Ack a = configure(c);
  uint16_t next_seq = a.next_seq;
  ack_ = a;
  const uint32_t slots = ident_.slots;

  std::deque<Out> inflight;
  size_t k = 0;  // next item to send
  bool start_sent = false, resume_pending = false;
  bool status_schedule_at_underrun = false;  // status_.schedule_ticks is where the underrun stopped the clock
  double resume_sent = -1e9;
  uint64_t steps_sent = 0;
  uint32_t underruns_seen = 0;
  double last_status = -1e9;
  bool status_outstanding = false;
  last_rx_ = t_.now();
  ItemCodec codec;
  const double prefill_ticks = o_.prefill_s / tick_s;
  bool stopping = false;
  double stop_sent = 0;
  // frame size adapts to the line: halved at each retransmission, grown again by acknowledged frames
  size_t payload_limit = o_.max_payload;
  const size_t min_payload = std::min<size_t>(16, o_.max_payload);

  auto inflight_slots = [&] {
    uint64_t s = 0;
    for (const Out& o : inflight) s += o.slots;
    return s;
  };
  // credits in bytes of encoded items, when the controller counts them (a small controller stores items as their
  // bytes); items in unacknowledged frames are spent
  auto byte_credits = [&]() -> int64_t {
    if (ack_.free_bytes == kUnlimited) return INT64_MAX;
    int64_t s = 0;
    for (const Out& o : inflight) s += static_cast<int64_t>(o.item_bytes);
    return static_cast<int64_t>(ack_.free_bytes) - s;
  };
  // the next item's encoded size (its bytes depend on the prediction, so on what was sent before it)
  auto next_item_bytes = [&]() -> int64_t {
    if (k >= sc.items.size()) return 0;
    std::string one;
    ItemCodec trial = codec;
    trial.encode(sc.items[k], one);
    return static_cast<int64_t>(one.size());
  };
  uint16_t start_seq = 0;
  uint16_t gbn_seq = 0;   // the last NAK answered by going back (a controller that drops frames ahead)
  double gbn_time = -1e9;
  // a STATUS request unanswered for this long is sent again: the RTO, or four times the reply's time on a slow
  // line (a reply is lost whole to one bad byte in about a hundred)
  const double status_timeout =
      std::max(o_.rto_s, o_.baud > 0 ? 4.0 * static_cast<double>(kOverhead + wire::Status::kSize) * 10.0 / o_.baud : 0.0);
  auto confirm_report = [&] {
    rep_.steps_confirmed = status_.executed[0] + status_.executed[1];
    rep_.end_node[0] = status_.node[0];
    rep_.end_node[1] = status_.node[1];
    rep_.underruns = status_.underruns;
  };
  auto where = [&] {
    return "it confirmed " + std::to_string(status_.executed[0] + status_.executed[1]) + " of " +
           std::to_string(rep_.steps_total) + " steps, axes at node (" + std::to_string(status_.node[0]) + ", " +
           std::to_string(status_.node[1]) + ")";
  };

  try {
  for (;;) {
    const double now = t_.now();
    // acknowledged frames leave the window
    while (!inflight.empty() && seq_diff(inflight.front().seq, ack_.next_seq) < 0) {
      inflight.pop_front();
      payload_limit = std::min(o_.max_payload, payload_limit + 2);
    }
    if (rebooted_) {
      confirm_report();
      throw PlayError(t_.describe() + ": the controller reset during the job (session " + std::to_string(session_) + " -> " +
                      std::to_string(boot_session_) + "); before the reset " + where() +
                      ". Its position is unknown now: re-home the machine and play the tape again");
    }
    if (got_error_) {
      confirm_report();
      throw PlayError(t_.describe() + ": controller error: " + error_.text + "; " + where());
    }
    // operator stop: hold, then abort once held
    if (stop && stop->load() && !stopping) {
      stopping = true;
      stop_sent = now;
      send_raw(encode_frame(next_req(), HOLD, ""));
    }
    if (stopping && got_status_ && (status_.state == State::held || status_.state == State::underrun ||
                                    status_.state == State::ready || status_.state == State::done ||
                                    now - stop_sent > o_.ramp_s + 5.0)) {
      send_raw(encode_frame(next_req(), ABORT, ""));
      confirm_report();
      rep_.resumable = true;
      throw PlayError("stopped by the operator: " + where());
    }
    // feed hold and resume
    if (hold_request && hold_request->exchange(false)) send_raw(encode_frame(next_req(), HOLD, ""));
    if (resume_request && resume_request->exchange(false)) send_raw(encode_frame(next_req(), RESUME, ""));
    // new frames, within the window and the credits
    while (!stopping && inflight.size() < o_.window && line_free_at_ <= t_.now() + o_.pace_s) {
      // START once the buffer holds the prefill, is full, or holds the whole job, and every frame before it has
      // been acknowledged (the controller has taken them: it fills its step pipeline at START without frames
      // arriving behind it); no QUEUE frame follows START before START is acknowledged
      const int64_t credits0 = static_cast<int64_t>(ack_.free_slots) - static_cast<int64_t>(inflight_slots());
      const bool full = credits0 <= 0 || byte_credits() < next_item_bytes();
      const bool prefilled = k == sc.items.size() || full ||
                             (k > 0 && static_cast<double>(sc.horizon[k - 1] == UINT64_MAX ? 0 : sc.horizon[k - 1]) >= prefill_ticks);
      if (!start_sent && prefilled) {
        if (!inflight.empty()) break;
        const uint16_t seq = next_seq++;
        start_seq = seq;
        Out o{seq, encode_frame(seq, START, ""), 0, 0, 0, now};
        send_raw(o.bytes);
        o.sent = line_free_at_;
        inflight.push_back(std::move(o));
        start_sent = true;
        continue;
      }
      if (start_sent && seq_diff(start_seq, ack_.next_seq) >= 0) break;  // START not acknowledged yet
      const int64_t credits = static_cast<int64_t>(ack_.free_slots) - static_cast<int64_t>(inflight_slots());
      const int64_t room = byte_credits();
      if (k < sc.items.size() && credits > 0 && room >= next_item_bytes()) {
        std::string payload;
        uint32_t n = 0;
        uint64_t steps = 0;
        while (k < sc.items.size() && n < credits) {
          std::string one;
          ItemCodec trial = codec;
          trial.encode(sc.items[k], one);
          if (!payload.empty() && payload.size() + one.size() > payload_limit) break;
          if (static_cast<int64_t>(payload.size() + one.size()) > room) break;
          codec = trial;
          payload += one;
          const QueueItem& it = sc.items[k];
          if (it.kind == ItemKind::run) steps += it.count;
          ++n;
          ++k;
        }
        const uint16_t seq = next_seq++;
        Out o{seq, encode_frame(seq, QUEUE, payload), n, payload.size(), steps, now};
        send_raw(o.bytes);
        o.sent = line_free_at_;
        steps_sent += steps;
        inflight.push_back(std::move(o));
        continue;
      }
      break;
    }
    rep_.steps_sent = steps_sent;
    // retransmissions: the frame the controller asks for (and the frames after it, when the controller dropped
    // them: go-back-N), and any frame unacknowledged for rto_s
    if (got_nak_) {
      got_nak_ = false;
      // a NAK answered already (the frame it names went again less than a quarter RTO ago) is ignored; else the
      // frame goes again, and when the controller dropped the frames after it, they follow it (go-back-N). Such a
      // controller names each missing frame once as it reaches it (again only if frames still come 50 ms later):
      // a NAK of another frame than the last one answered is news, whenever that frame went
      const bool news = !nak_kept_ && (nak_seq_ != gbn_seq || now - gbn_time > o_.rto_s / 4);
      bool missing_resent = false;
      for (Out& o : inflight)
        if ((o.seq == nak_seq_ && (news || now - o.sent > o_.rto_s / 4)) || (missing_resent && !nak_kept_)) {
          if (!nak_kept_ && !missing_resent) {
            gbn_seq = nak_seq_;
            gbn_time = now;
          }
          missing_resent = true;
          send_raw(o.bytes);
          o.sent = line_free_at_;
          ++rep_.retransmissions;
          payload_limit = std::max(min_payload, payload_limit / 2);
        }
    }
    for (Out& o : inflight)
      if (now - o.sent > o_.rto_s && line_free_at_ <= now + o_.pace_s) {
        send_raw(o.bytes);
        o.sent = line_free_at_;
        ++rep_.retransmissions;
        payload_limit = std::max(min_payload, payload_limit / 2);
      }
    // status
    // one status request at a time (a slow line must not pile up stale replies)
    if ((!status_outstanding && now - last_status >= o_.status_period_s) ||
        (status_outstanding && now - last_status > status_timeout)) {
      send_raw(encode_frame(next_req(), STATUS, ""));
      last_status = now;
      status_outstanding = true;
    }
    if (got_status_) {
      got_status_ = false;
      status_outstanding = false;
      confirm_report();
      if (status_.underruns > underruns_seen) {
        underruns_seen = status_.underruns;
        resume_pending = true;
        status_schedule_at_underrun = true;
      }
      if (on_progress) {
        PlayProgress p;
        p.steps_confirmed = rep_.steps_confirmed;
        p.steps_total = rep_.steps_total;
        p.schedule_s = static_cast<double>(status_.schedule_ticks) * tick_s;
        p.total_s = static_cast<double>(sc.last_tick) * tick_s;
        p.elapsed_s = now - t0;
        p.buffer_fill = slots ? 1.0 - static_cast<double>(status_.free_slots) / slots : 0.0;
        p.state = status_.state;
        on_progress(p);
      }
      if (status_.state == State::fault || status_.state == State::aborted)
        throw PlayError(t_.describe() + ": the controller stopped (" + state_name(status_.state) + "); " + where());
      if (status_.state == State::done && k == sc.items.size() && inflight.empty()) {
        rep_.duration_s = static_cast<double>(status_.now_ticks) * tick_s;
        break;
      }
    }
    // after an underrun stop, resume once the buffer is refilled. The controller's state is the latest one heard,
    // from a STATUS reply or an ACK, whichever came last: an ACK carries the state too, and being short it gets
    // through a noisy line far more often than a STATUS reply (on a line that loses 2 % of the bytes, an 86-byte
    // reply arrives whole one time in six), so the stop is seen, and the RESUME confirmed, when the first frame
    // after it is acknowledged rather than seconds later
    if (state_ == State::underrun && state_at_ > resume_sent) resume_pending = true;
    if (resume_pending && state_ == State::underrun && inflight.empty() &&
        (k == sc.items.size() || ack_.free_slots == 0 || byte_credits() < next_item_bytes() ||
         (status_schedule_at_underrun && status_.state == State::underrun &&
          static_cast<double>(sc.horizon[k - 1]) - static_cast<double>(status_.schedule_ticks) >= prefill_ticks))) {
      // sent again while the controller still reports the stop (a RESUME can be lost like any frame)
      if (now - resume_sent > o_.rto_s) {
        send_raw(encode_frame(next_req(), RESUME, ""));
        resume_sent = now;
      }
    }
    if (resume_pending && state_ != State::underrun && state_ != State::stopping && state_at_ > resume_sent &&
        resume_sent > -1e8) {
      resume_pending = false;
      status_schedule_at_underrun = false;
    }
    // a silent link: reconnect, then carry on if it is the same controller session
    if (now - last_rx_ > o_.link_timeout_s) {
      const double until = now + o_.reconnect_timeout_s;
      bool back = false;
      bool reopened = false;
      while (t_.now() < until && !back) {
        // a port that vanished is reopened; either way the controller is asked who it is
        if (!reopened && t_.reconnect()) {
          reopened = true;
          ++rep_.reconnects;
        }
        got_ident_ = false;
        send_raw(encode_frame(next_req(), IDENTIFY, ""));
        const double wait_until = t_.now() + o_.identify_timeout_s;
        while (t_.now() < wait_until && !got_ident_) poll(0.01);
        back = got_ident_;
        if (!back) reopened = false;
      }
      if (!back) {
        rep_.resumable = true;
        throw PlayError(t_.describe() + ": the link to the controller is lost (no answer for " +
                        std::to_string(o_.link_timeout_s + o_.reconnect_timeout_s) + " s); " + where());
      }
      if (ident_.session != session_) {
        rebooted_ = true;
        boot_session_ = ident_.session;
      }
      last_rx_ = t_.now();
      continue;
    }
    poll(0.002);
  }
  } catch (const LinkLost& e) {
    // the port failed: where the controller last said it was (a controller that shuts down says so first: what
    // is still in the port's input is read)
    for (int i = 0; i < 20; ++i) {
      try {
        poll(0.005);
      } catch (const LinkLost&) {
        break;
      }
    }
    confirm_report();
    rep_.resumable = true;
    throw PlayError(std::string(e.what()) + "; " + where());
  }
  rep_.wall_s = t_.now() - t0;
  rep_.completed = true;
  if (rep_.steps_confirmed != rep_.steps_total || rep_.end_node[0] != plan.end[0] || rep_.end_node[1] != plan.end[1])
    throw PlayError(t_.describe() + ": the controller finished with " + std::to_string(rep_.steps_confirmed) + " of " +
                    std::to_string(rep_.steps_total) + " steps at node (" + std::to_string(rep_.end_node[0]) + ", " +
                    std::to_string(rep_.end_node[1]) + "), expected (" + std::to_string(plan.end[0]) + ", " +
                    std::to_string(plan.end[1]) + ")");
  return rep_;
}

}  // namespace polarcam
