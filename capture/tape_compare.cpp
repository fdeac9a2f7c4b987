#include "capture/tape_compare.hpp"

#include <algorithm>

#include "cam/error.hpp"
#include "digitizer/tape.hpp"

namespace polarcam {
namespace {

__extension__ typedef __int128 i128;

i128 abs128(i128 v) { return v < 0 ? -v : v; }

}  // namespace

const char* to_string(TapeMismatch::Kind k) {
  switch (k) {
    case TapeMismatch::order: return "order";
    case TapeMismatch::time: return "time";
    case TapeMismatch::missing: return "missing";
    case TapeMismatch::extra: return "extra";
  }
  return "?";
}

TapeComparer::TapeComparer(const std::string& expected_tape, const TapeCompareOptions& o) : o_(o) {
  if (o.speed_num < 1 || o.speed_den < 1 || o.speed_num > (int64_t{1} << 30) || o.speed_den > (int64_t{1} << 30))
    throw InputError("the speed scale must be a ratio of whole numbers from 1 to 2^30", "--speed-scale");
  if (o.tick_ns < 0 || o.tick_ns > 1000000000) throw InputError("must be a time from 0 to 1 s", "--tick");
  if (o.tolerance_ns < 0 || o.tolerance_ns > 1000000000000)
    throw InputError("must be a time from 0 to 1000 s", "--tolerance");
  reader_ = std::make_unique<TapeReader>(expected_tape);
  reader_->on_tool_event([](const ToolEvent&) {});  // the tool's events are no steps: not compared
  tick_ps_ = reader_->header().tick_ps;
}

TapeComparer::~TapeComparer() = default;

bool TapeComparer::fill(size_t n) {
  while (ahead_.size() < n && !finished_) {
    StepRecord rec;
    if (!reader_->next(rec)) {
      finished_ = true;
      break;
    }
    cum_ += rec.interval;
    ahead_.push_back({rec.axis, rec.dir, cum_});
    ++r_.steps_expected;
  }
  return ahead_.size() >= n;
}

void TapeComparer::list(const TapeMismatch& m) {
  if (r_.listed.size() < o_.max_listed) r_.listed.push_back(m);
}

void TapeComparer::match(const Seen& s) {
  const uint64_t index = r_.matched + r_.order_mismatches + r_.time_mismatches + 1;
  TapeMismatch m;
  m.index = index;
  m.seen_axis = s.axis;
  m.seen_dir = s.dir;
  m.seen_ns = s.t_ns;
  if (!fill(1)) {  // more steps seen than expected: counted by the totals
    m.kind = TapeMismatch::extra;
    m.index = r_.steps_seen;
    list(m);
    return;
  }
  const Expected e = ahead_.front();
  ahead_.pop_front();
  m.expected_axis = e.axis;
  m.expected_dir = e.dir;
  // in ps times num: expected = ticks * tick_ps * den, seen = t_ns * 1000 * num
  const i128 num = o_.speed_num, den = o_.speed_den;
  const i128 expected = static_cast<i128>(e.t_ticks) * static_cast<i128>(tick_ps_) * den;
  m.expected_ns = static_cast<double>(expected) / static_cast<double>(num) / 1000.0;
  if (e.axis != s.axis || e.dir != s.dir) {
    ++r_.order_mismatches;
    m.kind = TapeMismatch::order;
    list(m);
    return;
  }
  const i128 raw_ps = static_cast<i128>(s.t_ns) * 1000;
  i128 at_ps = raw_ps;
  if (o_.tick_ns > 0) {
    const i128 tick = static_cast<i128>(o_.tick_ns) * 1000;
    at_ps = (raw_ps >= 0 ? (raw_ps + tick / 2) / tick : -((-raw_ps + tick / 2) / tick)) * tick;
    r_.max_jitter_ns = std::max(r_.max_jitter_ns, static_cast<double>(abs128(raw_ps - at_ps)) / 1000.0);
  }
  const i128 err = abs128(at_ps * num - expected), raw_err = abs128(raw_ps * num - expected);
  const double err_ns = static_cast<double>(err) / static_cast<double>(num) / 1000.0;
  r_.max_raw_error_ns = std::max(r_.max_raw_error_ns, static_cast<double>(raw_err) / static_cast<double>(num) / 1000.0);
  if (r_.worst_step == 0 || err_ns > r_.max_time_error_ns) {
    r_.max_time_error_ns = err_ns;
    r_.worst_step = index;
  }
  if (err > static_cast<i128>(o_.tolerance_ns) * 1000 * num) {
    ++r_.time_mismatches;
    m.kind = TapeMismatch::time;
    m.error_ns = err_ns;
    list(m);
    return;
  }
  ++r_.matched;
}

int64_t TapeComparer::on_tick(int64_t t_ns) const {
  if (o_.tick_ns <= 0) return t_ns;
  return t_ns >= 0 ? (t_ns + o_.tick_ns / 2) / o_.tick_ns : -((-t_ns + o_.tick_ns / 2) / o_.tick_ns);
}

void TapeComparer::step(int axis, int dir, int64_t t_ns) {
  const Seen s{axis, dir, t_ns};
  ++r_.steps_seen;
  if (have_held_) {
    if (on_tick(held_.t_ns) == on_tick(s.t_ns) && held_.axis != s.axis && fill(2)) {
      const Expected& e0 = ahead_[0];
      const Expected& e1 = ahead_[1];
      const bool in_order = e0.axis == held_.axis && e0.dir == held_.dir && e1.axis == s.axis && e1.dir == s.dir;
      const bool swapped = e0.axis == s.axis && e0.dir == s.dir && e1.axis == held_.axis && e1.dir == held_.dir;
      if (!in_order && swapped) {
        ++r_.simultaneous_swapped;
        match(s);
        match(held_);
        have_held_ = false;
        return;
      }
    }
    match(held_);
  }
  held_ = s;
  have_held_ = true;
}

TapeComparison TapeComparer::finish() {
  if (have_held_) match(held_);
  have_held_ = false;
  while (fill(1)) {
    const Expected e = ahead_.front();
    ahead_.pop_front();
    TapeMismatch m;
    m.kind = TapeMismatch::missing;
    m.index = r_.steps_expected - ahead_.size();
    m.expected_axis = e.axis;
    m.expected_dir = e.dir;
    m.expected_ns = static_cast<double>(static_cast<i128>(e.t_ticks) * static_cast<i128>(tick_ps_) * o_.speed_den) /
                    static_cast<double>(o_.speed_num) / 1000.0;
    list(m);
  }
  return r_;
}

TapeComparison compare_tapes(const std::string& expected_tape, const std::string& seen_tape,
                             const TapeCompareOptions& o) {
  TapeComparer c(expected_tape, o);
  TapeReader seen(seen_tape);
  if (seen.header().axes != c.expected().header().axes)
    throw InputError(std::string("a ") + (seen.header().axes == TapeAxes::polar ? "polar" : "Cartesian") +
                         " tape compared with a " +
                         (c.expected().header().axes == TapeAxes::polar ? "polar" : "Cartesian") +
                         " one: compare tapes of the same machine",
                     seen_tape);
  seen.on_tool_event([](const ToolEvent&) {});
  const i128 tick_ps = seen.header().tick_ps;
  uint64_t cum = 0;
  StepRecord rec;
  while (seen.next(rec)) {
    cum += rec.interval;
    c.step(rec.axis, rec.dir, static_cast<int64_t>((static_cast<i128>(cum) * tick_ps + 500) / 1000));
  }
  return c.finish();
}

}  // namespace polarcam
