#include "machine/controller/controller.hpp"

#include <algorithm>
#include <cmath>

#include "machine/player/int128.hpp"

namespace polarcam {

using namespace proto;

Controller::Controller(ControllerSpec spec, uint32_t session) : spec_(std::move(spec)), session_(session) {}

std::string Controller::take_output() {
  std::string o;
  o.swap(out_);
  return o;
}

void Controller::send(uint8_t type, uint16_t seq, const std::string& payload) { out_ += encode_frame(seq, type, payload); }

void Controller::send_ack() {
  Ack a;
  a.next_seq = next_seq_;
  a.free_slots = free_slots();
  a.state = static_cast<uint8_t>(state_);
  a.free_bytes = free_bytes();
  acked_free_bytes_ = a.free_bytes;
  send(ACK, 0, a.encode());
}

void Controller::send_error(ErrorCode code, const std::string& text, uint16_t seq) {
  ErrorMsg e;
  e.code = code;
  e.text = text;
  send(ERROR, seq, e.encode());
}

uint32_t Controller::free_slots() const { return queued_items_ >= spec_.slots ? 0 : spec_.slots - queued_items_; }
uint32_t Controller::free_bytes() const {
  if (spec_.queue_bytes == 0) return kUnlimited;
  return queued_bytes_ >= spec_.queue_bytes ? 0 : spec_.queue_bytes - queued_bytes_;
}

void Controller::reboot(uint64_t now) {
  ControllerSpec s = spec_;
  const uint32_t next_session = session_ + 1;
  auto step_cb = std::move(on_step);
  auto tool_cb = std::move(on_tool);
  *this = Controller(s, next_session);
  on_step = std::move(step_cb);
  on_tool = std::move(tool_cb);
  now_ = now;
  send(BOOT, 0, Writer().u32(session_).s);
}

bool Controller::fresh_request(uint8_t type, uint16_t id) {
  auto it = last_req_.find(type);
  if (it != last_req_.end() && seq_diff(id, it->second) <= 0) return false;
  last_req_[type] = id;
  return true;
}

bool Controller::configure(const Configure& c, std::string* why) {
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  if (state_ == State::running || state_ == State::holding || state_ == State::held || state_ == State::resuming ||
      state_ == State::stopping || state_ == State::underrun)
    return fail("busy: a job is running (abort it first)");
  if (c.tick_ps != spec_.tick_ps)
    return fail("tick " + std::to_string(c.tick_ps) + " ps requested, this controller's tick is " + std::to_string(spec_.tick_ps) + " ps");
  if (c.axes != 2) return fail("this controller drives 2 axes");
  if (spec_.dr > 0 && c.dr > 0 &&
      (std::fabs(c.dr - spec_.dr) > 1e-9 * spec_.dr || std::fabs(c.dtheta - spec_.dtheta) > 1e-9 * spec_.dtheta))
    return fail("grid mismatch: the job's grid differs from this machine's");
  cfg_ = c;
  configured_ = true;
  for (int a = 0; a < 2; ++a) {
    ax_[a] = Axis{};
    ax_[a].node = c.start[a];
  }
  tools_.clear();
  tool_bytes_.clear();
  tool_down_ = false;
  codec_ = ItemCodec{};
  queued_items_ = 0;
  queued_bytes_ = 0;
  next_seq_ = 1;
  pending_.clear();
  nak_sent_ = false;
  hole_ = false;
  underruns_ = 0;
  error_ = ErrorCode::none;
  started_ = false;
  ramp_ = c.ramp_ticks;
  state_ = State::ready;
  return true;
}

bool Controller::push(const QueueItem& it, uint32_t bytes) {
  if (queued_items_ >= spec_.slots || !run_is_valid(it)) return false;
  if (spec_.queue_bytes != 0 && bytes > free_bytes()) return false;
  if (it.kind == ItemKind::tool) {
    if (!spec_.tool) return false;
    tools_.push_back(it);
    tool_bytes_.push_back(bytes);
    ++queued_items_;
    queued_bytes_ += bytes;
    return true;
  }
  Axis& a = ax_[it.axis & 1];
  if (a.ended_queued) return false;
  a.q.push_back(it);
  a.q_bytes.push_back(bytes);
  ++queued_items_;
  queued_bytes_ += bytes;
  // tail clock: exact end of the item (closed form of the run)
  if (it.kind == ItemKind::wait) {
    a.tail.base += it.wait;
  } else if (it.kind == ItemKind::run) {
    // offset + n I + C(n,2) A + C(n,3) B
    const i128 n = it.count;
    const i128 pos = (static_cast<i128>(a.tail.base) << kFracBits) + a.tail.frac + it.offset + n * it.interval +
                     n * (n - 1) / 2 * it.add + n * (n - 1) * (n - 2) / 6 * it.add2;
    a.tail.base = static_cast<uint64_t>(pos >> kFracBits);
    a.tail.frac = static_cast<uint32_t>(pos & 0xffffffffu);
  } else {
    a.ended_queued = true;
  }
  return true;
}

void Controller::start(uint64_t now) {
  run_to(now);
  if (state_ != State::ready) return;
  started_ = true;
  start_ = now_;
  tau_ = 0;
  rate_ = ramp_;
  ramp_dir_ = 0;
  state_ = State::running;
  prepare_next(ax_[0]);
  prepare_next(ax_[1]);
}

void Controller::start_ramp(int direction, State during) {
  state_ = during;
  ramp_dir_ = direction;
  if (ramp_ == 0) {  // no acceleration limit: the rate switches at once
    rate_ = 0;
    ramp_dir_ = 0;
    if (direction > 0) state_ = State::running;
    else state_ = during == State::stopping ? State::underrun : State::held;
  }
}

void Controller::hold() {
  if (state_ == State::running || state_ == State::resuming) start_ramp(-1, State::holding);
}

void Controller::resume() {
  if (state_ == State::held || state_ == State::holding || state_ == State::underrun) start_ramp(+1, State::resuming);
}

void Controller::handle_queue(const std::string& p) {
  const auto* d = reinterpret_cast<const uint8_t*>(p.data());
  size_t pos = 0;
  std::vector<QueueItem> items;
  std::vector<uint32_t> sizes;
  ItemCodec trial = codec_;
  while (pos < p.size()) {
    QueueItem it;
    const size_t from = pos;
    if (!trial.decode(d, p.size(), pos, it)) {
      error_ = ErrorCode::bad_queue;
      state_ = State::fault;
      send_error(ErrorCode::bad_queue, "malformed queue item", 0);
      return;
    }
    if (it.kind == ItemKind::tool && !spec_.tool) {
      error_ = ErrorCode::bad_queue;
      state_ = State::fault;
      send_error(ErrorCode::bad_queue, "a tool item, and this controller drives no tool", 0);
      return;
    }
    items.push_back(it);
    sizes.push_back(static_cast<uint32_t>(pos - from));
  }
  if (items.size() > free_slots() || p.size() > free_bytes()) {
    error_ = ErrorCode::overflow;
    state_ = State::fault;
    send_error(ErrorCode::overflow, "queue overflow: the host sent more than its credits (items or bytes)", 0);
    return;
  }
  codec_ = trial;
  for (size_t i = 0; i < items.size(); ++i) push(items[i], sizes[i]);
  if (started_) {
    prepare_next(ax_[0]);
    prepare_next(ax_[1]);
  }
}

void Controller::handle(const Frame& f, uint64_t now) {
  switch (f.type) {
    case IDENTIFY: {
      // a host starting a session (or reconnecting) numbers its requests afresh: the ids of an earlier host's
      // requests must not make this one's look like repeats (its first CONFIGURE would be answered, not done)
      last_req_.clear();
      Ident id;
      id.tick_ps = spec_.tick_ps;
      id.slots = spec_.slots;
      id.session = session_;
      id.max_step_rate = spec_.max_step_rate ? spec_.max_step_rate
                                             : static_cast<uint32_t>(std::min<uint64_t>(2000000000000ull / spec_.tick_ps, UINT32_MAX));
      id.caps = spec_.tool ? wire::kCapTool : 0;
      id.name = spec_.name;
      send(IDENT, f.seq, id.encode());
      return;
    }
    case STATUS:
      send(STATUS_REPLY, f.seq, status().encode());
      return;
    case RESET:
      if (fresh_request(f.type, f.seq)) reboot(now);
      return;
    case CONFIGURE: {
      Configure c;
      if (!Configure::decode(f.payload, c)) {
        send_error(ErrorCode::bad_config, "malformed CONFIGURE", f.seq);
        return;
      }
      if (!fresh_request(f.type, f.seq)) {  // a repeat of the last one: answer again
        send(ACK, f.seq, Ack{next_seq_, free_slots(), static_cast<uint8_t>(state_), free_bytes()}.encode());
        return;
      }
      std::string why;
      if (!configure(c, &why)) {
        send_error(why.rfind("grid", 0) == 0 ? ErrorCode::grid_mismatch : why.rfind("busy", 0) == 0 ? ErrorCode::busy : ErrorCode::bad_config, why, f.seq);
        return;
      }
      send(ACK, f.seq, Ack{next_seq_, free_slots(), static_cast<uint8_t>(state_), free_bytes()}.encode());
      return;
    }
    case HOLD:
    case RESUME:
    case ABORT:
      if (fresh_request(f.type, f.seq)) {
        if (f.type == HOLD) hold();
        if (f.type == RESUME) resume();
        if (f.type == ABORT) {
          for (Axis& a : ax_) {
            a.q.clear();
            a.q_bytes.clear();
            a.has_next = false;
            a.run.left = 0;
          }
          tools_.clear();
          tool_bytes_.clear();
          tool_down_ = false;  // a job stopped halfway leaves the tool lifted
          queued_items_ = 0;
          queued_bytes_ = 0;
          started_ = false;
          state_ = State::aborted;
        }
      }
      send(ACK, f.seq, Ack{next_seq_, free_slots(), static_cast<uint8_t>(state_), free_bytes()}.encode());
      return;
    case QUEUE:
    case START: {
      if (!configured_) {
        send_error(ErrorCode::not_configured, "not configured", f.seq);
        return;
      }
      const int d = seq_diff(f.seq, next_seq_);
      if (d < 0) {
        send_ack();
        return;
      }
      if (d > 0) {
        if (spec_.keep_ahead && d < 64 && pending_.size() < 64) pending_.emplace(f.seq, f);
        // once per missing frame (a controller that drops the frames ahead asks again every 50 ms until it
        // comes: renak())
        hole_ = true;
        if (!nak_sent_ || last_nak_ != next_seq_) send_nak();
        return;
      }
      Frame cur = f;
      hole_ = false;
      for (;;) {
        if (state_ == State::fault || state_ == State::aborted) break;
        if (cur.type == QUEUE) handle_queue(cur.payload);
        else if (state_ == State::ready) start(now);
        ++next_seq_;
        auto it = pending_.find(next_seq_);
        if (it == pending_.end()) break;
        cur = it->second;
        pending_.erase(it);
      }
      // drop anything now stale
      for (auto it = pending_.begin(); it != pending_.end();)
        it = seq_diff(it->first, next_seq_) < 0 ? pending_.erase(it) : std::next(it);
      send_ack();
      return;
    }
    default:
      return;  // unknown types are ignored (a newer host)
  }
}

void Controller::receive(const uint8_t* data, size_t n, uint64_t now) {
  run_to(now);
  std::vector<Frame> frames;
  dec_.feed(data, n, frames);
  for (const Frame& f : frames) handle(f, now_);
  renak();
}

void Controller::advance(uint64_t now) {
  run_to(now);
  renak();
}

void Controller::send_nak() {
  send(NAK, 0, Writer().u16(next_seq_).u8(spec_.keep_ahead ? 1 : 0).s);
  nak_sent_ = true;
  last_nak_ = next_seq_;
  nak_time_ = now_;
}

// A controller that drops the frames ahead of a missing one names it again every 50 ms until it comes (its NAK,
// or the frame sent again, may be lost too), as the reference firmware does.
void Controller::renak() {
  if (!spec_.keep_ahead && hole_ && (now_ - nak_time_) * spec_.tick_ps >= 50000000000ull) send_nak();
}

bool Controller::prepare_next(Axis& a) {
  while (!a.has_next && !a.ended) {
    if (a.run.left > 0) {
      a.next_tick = a.clk.advance(a.run.next());
      a.has_next = true;
      break;
    }
    if (a.q.empty()) return false;
    QueueItem it = a.q.front();
    a.q.pop_front();
    --queued_items_;
    queued_bytes_ -= a.q_bytes.front();
    a.q_bytes.pop_front();
    // a window update: the host learns of the room without asking (its STATUS requests may be lost)
    if (spec_.queue_bytes != 0 && free_bytes() >= acked_free_bytes_ + wire::kWindowUpdate) send_ack();
    if (it.kind == ItemKind::wait) {
      a.clk.base += it.wait;
    } else if (it.kind == ItemKind::end) {
      a.ended = true;
    } else {
      a.run.begin(it);
      a.dir = it.dir;
    }
  }
  return a.has_next;
}

uint64_t Controller::horizon(const Axis& a) const { return a.ended_queued ? UINT64_MAX : a.tail.base; }

void Controller::pop_tool() {
  tools_.pop_front();
  --queued_items_;
  queued_bytes_ -= tool_bytes_.front();
  tool_bytes_.pop_front();
  if (spec_.queue_bytes != 0 && free_bytes() >= acked_free_bytes_ + wire::kWindowUpdate) send_ack();
}

void Controller::fire_due() {
  for (;;) {
    int best = -1;
    for (int i = 0; i < 2; ++i) {
      if (!ax_[i].has_next && !prepare_next(ax_[i])) continue;
      if (best < 0 || ax_[i].next_tick < ax_[best].next_tick) best = i;
    }
    // a tool item acts after the steps of its tick and before those of later ticks
    if (!tools_.empty() && (best < 0 || tools_.front().wait < ax_[best].next_tick)) {
      if ((static_cast<u128>(tools_.front().wait) << 16) > tau_) break;
      tool_down_ = tools_.front().dir > 0;
      pop_tool();
      if (on_tool) on_tool(now_ - start_, tool_down_);
      continue;
    }
    if (best < 0) break;
    Axis& a = ax_[best];
    if ((static_cast<u128>(a.next_tick) << 16) > tau_) break;
    const int dir = a.dir;
    a.node += dir;
    ++a.executed;
    a.has_next = false;
    last_step_ = now_ - start_;
    if (on_step) on_step(last_step_, best, dir);
  }
  if (ax_[0].ended && ax_[1].ended && tools_.empty() && state_ != State::fault) {
    state_ = State::done;
    started_ = false;
  }
}

void Controller::run_to(uint64_t now) {
  while (now_ < now) {
    const bool moving = started_ && (state_ == State::running || state_ == State::holding ||
                                     state_ == State::resuming || state_ == State::stopping);
    if (!moving) {
      now_ = now;
      break;
    }
    if (ramp_dir_ == 0) {
      // steady at rate 1: jump to the next step, the underrun trigger or `now`
      uint64_t next = now;
      auto ahead = [&](uint64_t sched_tick) -> uint64_t {
        const u128 target = static_cast<u128>(sched_tick) << 16;
        if (target <= tau_) return now_;
        const u128 d = (target - tau_ + 65535) >> 16;
        return d > now - now_ ? now : now_ + static_cast<uint64_t>(d);
      };
      for (Axis& a : ax_) {
        if (a.has_next || prepare_next(a)) next = std::min(next, ahead(a.next_tick));
      }
      if (!tools_.empty()) next = std::min(next, ahead(tools_.front().wait));
      uint64_t trigger = UINT64_MAX;
      for (const Axis& a : ax_) {
        if (a.ended) continue;
        const uint64_t h = horizon(a);
        if (h == UINT64_MAX) continue;
        const uint64_t t = h > ramp_ / 2 ? h - ramp_ / 2 : 0;
        trigger = std::min(trigger, ahead(t));
      }
      next = std::min(next, trigger);
      tau_ += static_cast<u128>(next - now_) << 16;
      now_ = next;
      fire_due();
      if (state_ == State::running && trigger != UINT64_MAX && now_ >= trigger) {
        // re-check after firing: the host may not have refilled, the schedule ends within the stopping distance
        bool short_of_steps = false;
        for (const Axis& a : ax_) {
          if (a.ended) continue;
          const uint64_t h = horizon(a);
          if (h != UINT64_MAX && (static_cast<u128>(h > ramp_ / 2 ? h - ramp_ / 2 : 0) << 16) <= tau_) short_of_steps = true;
        }
        if (short_of_steps) {
          ++underruns_;
          start_ramp(-1, State::stopping);
        }
      }
      continue;
    }
    // ramping: one tick at a time
    ++now_;
    if (ramp_dir_ < 0 && rate_ > 0) --rate_;
    if (ramp_dir_ > 0 && rate_ < ramp_) ++rate_;
    tau_ += (static_cast<u128>(rate_) << 16) / ramp_;
    fire_due();
    if (rate_ == 0 && ramp_dir_ < 0) {
      ramp_dir_ = 0;
      if (state_ == State::stopping) state_ = State::underrun;
      else if (state_ == State::holding) state_ = State::held;
    } else if (rate_ == ramp_ && ramp_dir_ > 0) {
      ramp_dir_ = 0;
      if (state_ == State::resuming) state_ = State::running;
    }
  }
}

Status Controller::status() const {
  Status s;
  s.state = state_;
  s.error = error_;
  s.underruns = underruns_;
  s.now_ticks = state_ == State::done ? last_step_ : started_ ? now_ - start_ : 0;
  s.schedule_ticks = static_cast<uint64_t>(tau_ >> 16);
  s.free_slots = free_slots();
  s.free_bytes = free_bytes();
  s.queued = queued_items_;
  for (int a = 0; a < 2; ++a) {
    s.executed[a] = ax_[a].executed;
    s.node[a] = ax_[a].node;
  }
  s.next_seq = next_seq_;
  s.session = session_;
  s.bad_frames = static_cast<uint32_t>(dec_.bad_frames());
  return s;
}

}  // namespace polarcam
