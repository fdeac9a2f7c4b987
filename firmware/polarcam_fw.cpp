// The reference stepper controller of polarcam's serial protocol (docs/controller-protocol.md, docs/firmware.md)
// for an Arduino Uno (ATmega328P at 16 MHz) with a CNC shield v3: radial axis on X (step D2 = PD2, direction
// D5 = PD5), angular axis on Y (step D3 = PD3, direction D6 = PD6), drivers' enable D8 = PB0 (active low), the
// board's LED D13 = PB5 lit while a job runs (its rising edge is schedule tick 0, START), and the tool on the
// shield's spindle-enable pin D12 = PB4: high while the tool is down (a pen servo's or a Z axis's driver reads it;
// low after reset, CONFIGURE and ABORT).
//
// Three parts:
//   - the wire (machine/link/wire.hpp, shared with the host): frames, CRC, payloads, queue items, run arithmetic;
//   - the main loop: reassembles frames, answers them, keeps the queued items, and runs each axis's clock ahead
//     of time, turning the runs into timed events (one tick, which pins step) in a ring;
//   - the Timer1 compare interrupt (tick 4 us: 16 MHz / 64): at each event's tick it sets the direction pins,
//     raises the step pins, holds them 2 us, lowers them. It computes nothing but the next compare, so its
//     latency is the same for every step.
// Schedule tick s fires at timer tick s + offset; START sets the offset, RESUME after a hold or an underrun moves
// it on by the time stopped. Holds and underrun stops are immediate (no ramp: CONFIGURE with ramp_ticks > 0 is
// refused). The queued items are kept as the bytes they arrived in (about 11 a run instead of 36 decoded), decoded
// again as each axis reaches them; the host's credits count those bytes (ACK's free_bytes). Frames that arrive
// ahead of a missing one are not kept (RAM): NAK says so, and the host sends them again behind the missing one.
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/pgmspace.h>
#include <avr/sleep.h>
#include <string.h>

#include "machine/link/wire.hpp"

using namespace polarcam::wire;

namespace {

// ---- the board ----------------------------------------------------------------------------------------------

constexpr uint64_t kTickPs = 4000000;   // Timer1 at 16 MHz / 64: 4 us, 64 CPU cycles
constexpr uint16_t kStore = 384;        // bytes of queued items, as they arrived (a run is about 11)
constexpr uint32_t kMaxStepRate = 6000;  // steps/s, both axes together, sustained (measured: docs/firmware.md)
const char kName[] PROGMEM = "polarcam firmware, ATmega328P, CNC shield v3";

constexpr uint8_t kRStep = _BV(PD2), kTStep = _BV(PD3), kRDir = _BV(PD5), kTDir = _BV(PD6);
constexpr uint8_t kEnable = _BV(PB0), kLed = _BV(PB5), kTool = _BV(PB4);

// ---- UART (115200 baud, 8N1; U2X: UBRR 16 gives 117 647 baud, 2.1 % fast, as every Uno) ---------------------

constexpr uint8_t kRxSize = 128, kTxSize = 64;  // powers of two
uint8_t rx_buf[kRxSize], tx_buf[kTxSize];
volatile uint8_t rx_head, rx_tail, tx_head, tx_tail;

ISR(USART_RX_vect) {
  const uint8_t c = UDR0;  // clears the interrupt; then let the step timer in
  sei();
  const uint8_t h = rx_head, n = static_cast<uint8_t>((h + 1) & (kRxSize - 1));
  if (n != rx_tail) {
    rx_buf[h] = c;
    rx_head = n;
  }
}

ISR(USART_UDRE_vect) {
  const uint8_t t = tx_tail;
  if (t == tx_head) {
    UCSR0B &= static_cast<uint8_t>(~_BV(UDRIE0));
    return;
  }
  UDR0 = tx_buf[t];  // clears the interrupt; then let the step timer in
  sei();
  tx_tail = static_cast<uint8_t>((t + 1) & (kTxSize - 1));
}

void tx_put(uint8_t c) {
  const uint8_t h = tx_head, n = static_cast<uint8_t>((h + 1) & (kTxSize - 1));
  while (n == tx_tail) {
  }
  tx_buf[h] = c;
  tx_head = n;
  UCSR0B |= _BV(UDRIE0);
}

uint8_t out_frame[kOverhead + Status::kSize + 8];  // the largest reply is STATUS_REPLY (IDENT is shorter)

void send(uint16_t seq, uint8_t type, size_t n) {  // payload already at out_frame + kHeader
  const size_t total = frame_encode(out_frame, seq, type, out_frame + kHeader, n);
  for (size_t i = 0; i < total; ++i) tx_put(out_frame[i]);
}
uint8_t* payload_out() { return out_frame + kHeader; }
constexpr size_t kPayloadOut = sizeof out_frame - kOverhead;

// ---- events: what the timer interrupt executes ---------------------------------------------------------------
//
// The main loop precomputes everything an event does: its timer tick (32 bits), the whole of PORTD at its step
// (both direction pins and the step pins of the axes stepping at that tick) and whether it toggles the LED or the
// tool pin. The interrupt writes them: the step edges of every event, the LED's edge at START and the tool's
// edges, come the same few cycles after their tick begins, on one code path, whatever the event.

constexpr uint8_t kDirs = kRDir | kTDir, kSteps = kRStep | kTStep;
// ev_bits: kEvLed and kEvTool are the LED's and the tool's bits in PINB (toggles)
constexpr uint8_t kEvLed = kLed, kEvTool = kTool, kEvStop = 1, kEvEnd = 2;
constexpr uint8_t kEvents = 32;   // power of two
uint32_t ev_time[kEvents];        // timer ticks
uint8_t ev_pd[kEvents];           // PORTD at the event: directions | steps
uint8_t ev_bits[kEvents];
uint8_t ev_gap[kEvents];          // ticks after the event before it in the ring (255: 255 or more)
volatile uint8_t ev_head, ev_tail;  // the main loop writes at head, the interrupt reads at tail
uint8_t ev_done;                  // the main loop's count of executed events (executed[], moved[]) reached here

volatile bool running;          // the schedule clock advances
uint32_t offset;                // timer tick = schedule tick + offset (main loop only)
volatile uint16_t timer_hi;     // Timer1 overflows: the timer extended to 32 bits
volatile bool stop_armed;       // an underrun stop in the ring still applies (the main loop disarms it)
volatile uint32_t stop_time;    // timer tick where the clock stopped (hold or underrun)
volatile uint8_t stop_reason;   // 0 none, 1 underrun, 2 hold
volatile bool done;
uint32_t start_time, last_step_time;  // timer ticks
uint32_t executed[2];
int32_t moved[2];               // node - start node
volatile uint32_t underruns;

// The 32-bit timer now (interrupts off).
__attribute__((always_inline)) inline uint32_t now32() {
  const uint16_t lo = TCNT1;
  uint16_t hi = timer_hi;
  if ((TIFR1 & _BV(TOV1)) && lo < 0x8000) ++hi;  // an overflow not counted yet
  return static_cast<uint32_t>(hi) << 16 | lo;
}

// The timer now, from the main loop.
uint32_t timer_now() {
  const uint8_t s = SREG;
  cli();
  const uint32_t t = now32();
  SREG = s;
  return t;
}

// The rare events (interrupts off).
__attribute__((noinline)) void special(uint8_t b, uint32_t t) {
  if ((b & kEvStop) && stop_armed) {  // underrun: the schedule clock stops here
    running = false;
    stop_time = t;
    stop_reason = 1;
    stop_armed = false;
    ++underruns;
  }
  if (b & kEvEnd) {
    done = true;
    running = false;
  }
}

// Fires the events that are due and sets the compare for the next one (interrupts off). The compare wakes the
// interrupt four ticks ahead of an event; it sets the event's direction pins, waits for the tick on the timer's
// low byte and writes the precomputed pins. While the step pulse is high (2 us at least: DRV8825 1.9 us, A4988
// 1 us) it fetches the next event; one due within 3 ticks of this one (its gap, precomputed) is waited for at
// once on the low byte, with its direction pins set as this step falls, so that events one tick apart keep their
// ticks (a direction changes only for the axis stepping next, whose last step rose a tick earlier at least:
// DRV8825's hold 650 ns). A compare is only set within the timer's current 16-bit period; the overflow
// interrupt sets the ones beyond. A compare at another time does no harm: events fire by the extended time,
// never by the compare alone.
bool ovf_wake;  // the next event is in a later 16-bit period of the timer: the overflow looks at it
void schedule() {
  ovf_wake = false;
  if (!running) return;
  uint8_t i = ev_tail;
  if (i == ev_head) return;
  uint32_t due = ev_time[i];
  uint8_t pd = ev_pd[i];
  PORTD = static_cast<uint8_t>(pd & kDirs);  // its directions: at least 1 us before its step (see below)
  int32_t d = static_cast<int32_t>(due - now32());
  for (;;) {
    if (d > 5) {
      // the compare matches at the end of tick `wake`: the interrupt at due - 4, which leaves the interrupt's
      // entry and the code above (about 140 cycles) and another interrupt or a pause of the interrupts (up to
      // about 100 cycles) four ticks
      const uint32_t wake = due - 5;
      const uint32_t now = now32();
      if ((wake >> 16) != (now >> 16)) {  // in a later period: the overflow interrupt comes first
        ovf_wake = true;
        return;
      }
      // (a stale compare flag costs one harmless interrupt; clearing it with TIFR1 would also clear a pending
      // overflow in simavr 1.6)
      OCR1A = static_cast<uint16_t>(wake);
      d = static_cast<int32_t>(due - now32());
      if (d > 5) return;  // the timer is still short of `wake`: the compare will match
      continue;           // it passed while being set: fire from here
    }
    uint8_t lo = static_cast<uint8_t>(due);
    for (;;) {
      const uint8_t b = ev_bits[i];
      const uint8_t led = b & (kEvLed | kEvTool);
      if (d >= -64) {  // at most 5 ticks ahead: the low byte suffices (a late event fires at once)
        while (static_cast<int8_t>(TCNT1L - lo) < 0) {
        }
      }
      PORTD = pd;   // the steps
      PINB = led;   // START's and the end's LED edge, the tool's edges, on the same cycle grid
      i = static_cast<uint8_t>((i + 1) & (kEvents - 1));
      ev_tail = i;
      if (b & (kEvStop | kEvEnd)) {
        __builtin_avr_delay_cycles(32);
        PORTD = static_cast<uint8_t>(pd & kDirs);
        special(b, due);
        if (!running) return;
      }
      if (i == ev_head) {
        __builtin_avr_delay_cycles(24);  // the pulse's 2 us
        PORTD = static_cast<uint8_t>(pd & kDirs);
        return;
      }
      const uint8_t g = ev_gap[i];
      pd = ev_pd[i];
      if (g > 3 || d < -64) break;
      // the next event is due 0 to 3 ticks after this one
      lo = static_cast<uint8_t>(lo + g);  // (the pulse: 38 cycles from here, measured in the simulator)
      PORTD = static_cast<uint8_t>(pd & kDirs);  // the step falls; the next event's directions
    }
    due = ev_time[i];
    d = static_cast<int32_t>(due - now32());
    PORTD = static_cast<uint8_t>(pd & kDirs);  // the step falls (2 us: the loads and the clock above); directions
  }
}

ISR(TIMER1_COMPA_vect) { schedule(); }
ISR(TIMER1_OVF_vect) {
  ++timer_hi;
  if (ovf_wake) schedule();  // else short: it may delay the compare's interrupt
}

// Makes the timer look at the ring now (after START or RESUME, or when new events may be due sooner).
void kick() {
  const uint8_t s = SREG;
  cli();
  schedule();
  SREG = s;
}

// Counts the events the interrupt has executed (steps, nodes, the last step's time) and frees their entries.
void account() {
  const uint8_t t = ev_tail;
  while (ev_done != t) {
    const uint8_t i = ev_done, pd = ev_pd[i];
    if (pd & kRStep) {
      ++executed[0];
      moved[0] += (pd & kRDir) ? 1 : -1;
    }
    if (pd & kTStep) {
      ++executed[1];
      moved[1] += (pd & kTDir) ? 1 : -1;
    }
    if (pd & kSteps) last_step_time = ev_time[i];
    ev_done = static_cast<uint8_t>((i + 1) & (kEvents - 1));
  }
}

// ---- queued items: their wire bytes in a ring, read by each axis in turn ----------------------------------------
//
// A QUEUE frame's payload is checked whole (every item decoded and validated with the producer's predictions),
// then its bytes are appended to the ring as they came. Each axis reads the ring from its own position with its
// own predictions (an item's prediction depends only on the earlier items of its axis), skipping the other axis's
// items and the tool items; a third reader takes the tool items and skips the rest. The bytes behind all three
// positions are free again.

uint8_t store[kStore];
uint16_t st_tail, st_used;  // the oldest byte still needed; bytes held from there
uint16_t rd[3];             // each axis's read position, and the tool items': bytes after st_tail
uint16_t tools_stored;      // tool items in the ring that the tool reader has not taken
ItemCodec reader;           // the predictions of the items read back
uint8_t item_buf[kMaxItemBytes];

void store_reset() {
  st_tail = st_used = 0;
  rd[0] = rd[1] = rd[2] = 0;
  tools_stored = 0;
  reader = ItemCodec{};
}

// ---- the controller ----------------------------------------------------------------------------------------------

struct Axis {
  RunCursor run;
  AxisClock clk;
  bool dir_plus = true;
  bool has_next = false;
  uint64_t next_tick = 0;
  bool ended = false;
};

State state = State::idle;
ErrorCode error = ErrorCode::none;
bool configured;
int64_t start_node[2];
uint16_t next_seq = 1;
uint16_t last_nak;
bool nak_sent;
uint32_t nak_time;                             // timer tick of the last NAK
constexpr uint32_t kNakRepeatTicks = 12500;    // 50 ms
bool hole;                                     // a frame came ahead of next_seq since it was last received

void send_nak() {
  Nak k;
  k.next_seq = next_seq;
  k.kept = 0;
  send(0, NAK, k.encode(payload_out(), kPayloadOut));
  nak_sent = true;
  last_nak = next_seq;
  nak_time = timer_now();
}

void renak() {
  if (hole && timer_now() - nak_time > kNakRepeatTicks) send_nak();
}
uint16_t last_req[10];  // last request id per out-of-band type (IDENTIFY .. STATUS)
bool have_req[10];
uint32_t session;
uint32_t bad_frames;
ItemCodec codec;
Axis axes[2];
bool end_emitted, stop_emitted;
// the next tool item (read from the ring, not yet in the event ring), and the tool pin's level after the last
// tool event the producer emitted
struct Tool {
  bool has_next = false;
  bool down = false;
  uint64_t tick = 0;
  bool level = false;
} tool;

// Credits: bytes (an item is one byte at least, so as many items)
uint32_t free_slots() { return kStore - st_used; }
uint32_t queued() { return st_used; }

bool fresh_request(uint8_t type, uint16_t id) {
  const uint8_t k = type < 10 ? type : 0;
  if (have_req[k] && seq_diff(id, last_req[k]) <= 0) return false;
  have_req[k] = true;
  last_req[k] = id;
  return true;
}

uint16_t acked_free;  // free bytes in the last ACK sent

void send_ack(uint16_t seq) {
  Ack a;
  a.next_seq = next_seq;
  a.free_slots = free_slots();
  a.free_bytes = free_slots();
  acked_free = static_cast<uint16_t>(a.free_bytes);
  a.state = static_cast<uint8_t>(state);
  send(seq, ACK, a.encode(payload_out(), kPayloadOut));
}

// text: a string in flash (PSTR)
void send_error(ErrorCode code, const char* text, uint16_t seq) {
  char t[72];
  strncpy_P(t, text, sizeof t - 1);
  t[sizeof t - 1] = 0;
  send(seq, ERROR, encode_error(payload_out(), kPayloadOut, code, t, strlen(t)));
}

uint8_t pd_dirs;  // the direction pins after the last event in the ring (the producer's)

void stop_timer_events() {
  const uint8_t s = SREG;
  cli();
  running = false;
  stop_armed = false;
  SREG = s;
  account();
  ev_tail = ev_done = ev_head;  // the events not executed are dropped
  PORTD = pd_dirs = static_cast<uint8_t>(PORTD & kDirs);
}

void reset_job() {
  stop_timer_events();
  store_reset();
  for (Axis& a : axes) a = Axis{};
  tool = Tool{};
  PORTB &= static_cast<uint8_t>(~kTool);  // the tool up
  codec = ItemCodec{};
  next_seq = 1;
  nak_sent = false;
  hole = false;
  end_emitted = stop_emitted = false;
  done = false;
  stop_reason = 0;
  underruns = 0;
  executed[0] = executed[1] = 0;
  moved[0] = moved[1] = 0;
  error = ErrorCode::none;
  last_step_time = start_time = 0;
  PORTB &= static_cast<uint8_t>(~kLed);
}

bool prepare_tool();

// Frees the bytes behind the axes' and the tool reader's positions (an ended axis reads nothing more; the tool
// reader reads on to its next item first).
void store_release() {
  prepare_tool();
  uint16_t m = rd[2];
  for (uint8_t ai = 0; ai < 2; ++ai)
    if (!axes[ai].ended && rd[ai] < m) m = rd[ai];
  if (m == 0) return;
  st_tail = static_cast<uint16_t>(st_tail + m >= kStore ? st_tail + m - kStore : st_tail + m);
  st_used = static_cast<uint16_t>(st_used - m);
  for (uint8_t ai = 0; ai < 3; ++ai) rd[ai] = static_cast<uint16_t>(rd[ai] > m ? rd[ai] - m : 0);
}

// The next item of axis ai (2: the next tool item) from the ring before byte `limit` (false: none there yet). The
// bytes were checked when they arrived.
__attribute__((noinline)) bool next_item(uint8_t ai, QueueItem& it, uint16_t limit) {
  for (;;) {
    const uint16_t avail = static_cast<uint16_t>(st_used - rd[ai]);
    if (rd[ai] >= limit) return false;
    const uint8_t m = static_cast<uint8_t>(avail < kMaxItemBytes ? avail : kMaxItemBytes);
    uint16_t j = static_cast<uint16_t>(st_tail + rd[ai]);
    if (j >= kStore) j = static_cast<uint16_t>(j - kStore);
    for (uint8_t k = 0; k < m; ++k) {
      item_buf[k] = store[j];
      if (++j == kStore) j = 0;
    }
    size_t pos = 0;
    if (!reader.parse(item_buf, m, pos, it)) return false;  // (cannot happen: checked on arrival)
    rd[ai] = static_cast<uint16_t>(rd[ai] + pos);
    if (it.kind == ItemKind::tool ? ai == 2 : (it.axis & 1) == ai) {
      reader.take(it);
      return true;
    }
  }
}

// The next step of an axis: takes its items as the emulator's controller does.
bool prepare(uint8_t ai) {
  Axis& a = axes[ai];
  while (!a.has_next && !a.ended) {
    if (a.run.left > 0) {
      a.next_tick = a.clk.advance(a.run.next());
      a.has_next = true;
      break;
    }
    QueueItem it;
    if (!next_item(ai, it, st_used)) return false;
    if (it.kind == ItemKind::wait) {
      a.clk.base += it.wait;
    } else if (it.kind == ItemKind::end) {
      a.ended = true;
    } else {
      a.run.begin(it);
      a.dir_plus = it.dir > 0;
    }
    store_release();
  }
  return a.has_next;
}

// The next tool item, read once (its bytes stay held until it is in the event ring).
// The tool reader reads only as far as the axes have: a tool item is queued before the first item that lets the
// schedule reach its tick, so while it lies beyond every axis's position, some axis's next step or stop comes
// before its tick, and there is no need to know it yet. So it parses each item once, a few at a time, and nothing
// when no tool item is queued.
bool prepare_tool() {
  if (tool.has_next) return true;
  if (tools_stored == 0) {
    rd[2] = st_used;
    return false;
  }
  uint16_t far = 0;
  bool all_ended = true;
  for (uint8_t ai = 0; ai < 2; ++ai)
    if (!axes[ai].ended) {
      all_ended = false;
      if (rd[ai] > far) far = rd[ai];
    }
  QueueItem it;
  if (next_item(2, it, all_ended ? st_used : far)) {
    --tools_stored;
    tool.has_next = true;
    tool.down = it.dir > 0;
    tool.tick = it.wait;
  }
  return tool.has_next;
}

bool ring_full() {
  account();
  return static_cast<uint8_t>((ev_head + 1) & (kEvents - 1)) == ev_done;
}
uint32_t last_emitted;
// An event at schedule tick `tick`: steps (kRStep, kTStep in `steps`, each axis's direction in `dirs`) and bits.
void emit(uint32_t tick, uint8_t steps, uint8_t dirs, uint8_t bits) {
  const uint8_t h = ev_head;
  pd_dirs = static_cast<uint8_t>((pd_dirs & ~((steps & kRStep ? kRDir : 0) | (steps & kTStep ? kTDir : 0))) | dirs);
  ev_time[h] = tick + offset;
  ev_pd[h] = static_cast<uint8_t>(pd_dirs | steps);
  ev_bits[h] = bits;
  const uint32_t gap = tick - last_emitted;
  ev_gap[h] = static_cast<uint8_t>(gap < 255 ? gap : 255);
  last_emitted = tick;
  asm volatile("" ::: "memory");  // the entry is written before the interrupt can see it
  const uint8_t s = SREG;
  cli();  // (the interrupt may empty the ring between a test and the new head: both at once)
  const bool was_empty = h == ev_tail;
  ev_head = static_cast<uint8_t>((h + 1) & (kEvents - 1));
  if (was_empty) schedule();  // the interrupt had nothing to wait for: set the compare for this one
  SREG = s;
}

// The tool event of the next tool item: the pin toggles when the item changes the tool's state.
void emit_tool() {
  emit(static_cast<uint32_t>(tool.tick), 0, 0, tool.down != tool.level ? kEvTool : 0);
  tool.level = tool.down;
  tool.has_next = false;
  store_release();
}

// Runs the axes' clocks ahead, in time order, into the event ring. An axis whose items have run out (and that
// has not ended) gets a stop at the end of its clock: the schedule stops there unless items come first.
void produce_events();
void produce() { produce_events(); }  // (emit() kicks the timer when the ring was empty)
void produce_events() {
  if (!configured || state == State::ready || state == State::idle || state == State::fault ||
      state == State::aborted || end_emitted)
    return;
  while (!ring_full()) {
    if (stop_emitted) {
      // an underrun stop waits in the ring: disarm it if the starved axis has items again
      bool still = false;
      for (uint8_t ai = 0; ai < 2; ++ai)
        if (!axes[ai].ended && !prepare(ai)) still = true;
      if (still) return;
      const uint8_t s = SREG;
      cli();
      const bool armed = stop_armed;
      stop_armed = false;
      SREG = s;
      if (!armed && stop_reason == 1) return;  // it has fired: RESUME clears it
      stop_emitted = false;
    }
    for (uint8_t ai = 0; ai < 2; ++ai) prepare(ai);
    Axis &r = axes[0], &t = axes[1];
    if (r.ended && t.ended) {
      if (prepare_tool()) {  // (a host sends no tool item after the last steps; one that does gets it done)
        emit_tool();
        continue;
      }
      emit(last_emitted, 0, 0, static_cast<uint8_t>(kEvEnd | kEvLed));  // right after the last step; LED off
      end_emitted = true;
      return;
    }
    // candidates: a step at its tick, or (an axis short of items) a stop at its clock, after steps of that tick
    uint64_t best = UINT64_MAX;
    bool best_stop = false;
    for (uint8_t ai = 0; ai < 2; ++ai) {
      const Axis& a = axes[ai];
      if (a.ended) continue;
      if (a.has_next) {
        if (a.next_tick < best || (a.next_tick == best && best_stop)) {
          best = a.next_tick;
          best_stop = false;
        }
      } else if (a.clk.base < best) {
        best = a.clk.base;
        best_stop = true;
      }
    }
    // a tool item acts after the steps of its tick, before a stop there and the steps of later ticks
    if (prepare_tool() && (tool.tick < best || (tool.tick == best && best_stop))) {
      emit_tool();
      continue;
    }
    if (best_stop) {
      const uint8_t s = SREG;
      cli();
      stop_armed = true;
      emit(static_cast<uint32_t>(best), 0, 0, kEvStop);
      SREG = s;
      stop_emitted = true;
      return;
    }
    uint8_t steps = 0, dirs = 0;
    for (uint8_t ai = 0; ai < 2; ++ai) {
      Axis& a = axes[ai];
      if (!a.ended && a.has_next && a.next_tick == best) {
        steps |= ai == 0 ? kRStep : kTStep;
        if (a.dir_plus) dirs |= ai == 0 ? kRDir : kTDir;
        a.has_next = false;
      }
    }
    emit(static_cast<uint32_t>(best), steps, dirs, 0);
  }
}

void update_state() {
  if (state == State::running && done) state = State::done;
  if (state == State::running && !running && stop_reason == 1) state = State::underrun;
}

// Apart, so that their stack frames are not live at once (2 KB of RAM).
__attribute__((noinline)) bool parse_item(const ItemCodec& c, const uint8_t* p, size_t n, size_t& pos, QueueItem& it) {
  return c.parse(p, n, pos, it);
}
__attribute__((noinline)) bool valid_run(const QueueItem& it) { return run_is_valid(it); }

// A QUEUE payload: every item decoded and checked first (a frame with a bad item is refused whole), then taken.
__attribute__((noinline)) void handle_queue(const uint8_t* p, size_t n) {
  bool ok = true;
  const bool overflow = n > kStore - st_used;
  if (!overflow) {
    ItemCodec trial = codec;
    size_t pos = 0;
    uint16_t tools = 0;
    while (pos < n) {
      QueueItem it;
      if (!parse_item(trial, p, n, pos, it) || !valid_run(it)) {
        ok = false;
        break;
      }
      if (it.kind == ItemKind::tool) ++tools;
      trial.take(it);
      produce();  // keep the event ring fed while a long frame is checked
    }
    if (ok) {
      codec = trial;
      tools_stored = static_cast<uint16_t>(tools_stored + tools);
    }
  }
  if (!ok || overflow) {
    error = overflow ? ErrorCode::overflow : ErrorCode::bad_queue;
    state = State::fault;
    stop_timer_events();
    send_error(error, overflow ? PSTR("queue overflow: the host sent more than its credits (items or bytes)") : PSTR("malformed queue item"), 0);
    return;
  }
  uint16_t j = static_cast<uint16_t>(st_tail + st_used);
  if (j >= kStore) j = static_cast<uint16_t>(j - kStore);
  for (size_t i = 0; i < n; ++i) {
    store[j] = p[i];
    if (++j == kStore) j = 0;
  }
  st_used = static_cast<uint16_t>(st_used + n);
}

void start_job() {
  const uint8_t s = SREG;
  cli();
  // schedule tick 0 2 ms from now: the first events are computed before it (each axis's first item decoded from
  // its bytes, the other axis's items skipped: up to 0.9 ms measured; at 64 us the first step came late)
  const uint32_t t = timer_now() + 500;
  offset = t;
  start_time = t;
  running = true;
  emit(0, 0, 0, kEvLed);  // START's own event: the LED at tick 0, before every step (steps are at tick 1 or later)
  SREG = s;
  produce();
}

void resume_job() {
  const uint8_t s = SREG;
  cli();
  // the schedule goes on 4 ticks from now where it stopped: the events waiting in the ring move by as much
  const uint32_t delta = timer_now() + 4 - stop_time;
  for (uint8_t i = ev_tail; i != ev_head; i = static_cast<uint8_t>((i + 1) & (kEvents - 1))) ev_time[i] += delta;
  offset += delta;
  stop_reason = 0;
  running = true;
  SREG = s;
  state = State::running;
  produce();
  kick();
}

void fill_status(Status& st) {
  account();  // outside the interrupts' pause: a long one would delay a step
  st.executed[0] = executed[0];
  st.executed[1] = executed[1];
  st.node[0] = start_node[0] + moved[0];
  st.node[1] = start_node[1] + moved[1];
  const uint8_t s = SREG;
  cli();  // (short: the interrupt's variables only)
  st.underruns = underruns;
  const uint32_t now = now32();
  const bool was_running = running;
  const uint32_t stopped = stop_time;
  SREG = s;
  const uint32_t sched = (was_running ? now : stopped) - offset;
  const uint32_t start = start_time, last = last_step_time;
  st.state = state;
  st.error = error;
  const bool started = state != State::idle && state != State::ready && state != State::aborted && state != State::fault;
  st.now_ticks = state == State::done ? last - start : started ? now - start : 0;
  st.schedule_ticks = started && state != State::done ? sched : 0;
  st.free_slots = free_slots();
  st.free_bytes = free_slots();
  st.queued = queued();
  st.next_seq = next_seq;
  st.session = session;
  st.bad_frames = bad_frames;
}

__attribute__((noinline)) void configure(uint16_t seq, const uint8_t* p, size_t n) {
  Configure c;
  if (!c.decode(p, n)) {
    send_error(ErrorCode::bad_config, PSTR("malformed CONFIGURE"), seq);
    return;
  }
  if (!fresh_request(CONFIGURE, seq)) {  // a repeat: answer again
    send_ack(seq);
    return;
  }
  if (state == State::running || state == State::held || state == State::underrun) {
    send_error(ErrorCode::busy, PSTR("busy: a job is running (abort it first)"), seq);
    return;
  }
  if (c.tick_ps != kTickPs) {
    send_error(ErrorCode::bad_config, PSTR("tick requested differs from this controller's tick of 4000000 ps"), seq);
    return;
  }
  if (c.axes != 2) {
    send_error(ErrorCode::bad_config, PSTR("this controller drives 2 axes"), seq);
    return;
  }
  if (c.ramp_ticks != 0) {
    send_error(ErrorCode::bad_config, PSTR("no ramp in this firmware: play without an acceleration limit"), seq);
    return;
  }
  reset_job();
  start_node[0] = c.start[0];
  start_node[1] = c.start[1];
  configured = true;
  state = State::ready;
  PORTB &= static_cast<uint8_t>(~kEnable);  // drivers on: the axes hold their start node
  send_ack(seq);
}

__attribute__((noinline)) void reply_ident(uint16_t seq) {
  Ident id;
  id.tick_ps = kTickPs;
  id.slots = kStore;
  id.session = session;
  id.max_step_rate = kMaxStepRate;
  id.caps = kCapTool;
  char name[sizeof kName];
  strcpy_P(name, kName);
  id.name = name;
  id.name_len = sizeof kName - 1;
  send(seq, IDENT, id.encode(payload_out(), kPayloadOut));
}

__attribute__((noinline)) void reply_status(uint16_t seq) {
  Status st;
  fill_status(st);
  send(seq, STATUS_REPLY, st.encode(payload_out(), kPayloadOut));
}

__attribute__((noinline)) void handle(const uint8_t* f) {
  const uint16_t seq = frame_seq(f);
  const uint8_t type = frame_type(f);
  const uint8_t* p = frame_payload(f);
  const size_t n = frame_payload_size(f);
  update_state();
  switch (type) {
    case IDENTIFY:
      // a host starting a session (or reconnecting) numbers its requests afresh: forget an earlier host's ids
      for (bool& h : have_req) h = false;
      reply_ident(seq);
      return;
    case STATUS:
      reply_status(seq);
      return;
    case RESET:
      if (fresh_request(type, seq)) {
        // a clean reboot through the watchdog would lose the session counter; start over in place instead
        reset_job();
        configured = false;
        state = State::idle;
        PORTB |= kEnable;
        for (bool& h : have_req) h = false;
        ++session;
        Put(payload_out(), kPayloadOut).u32(session);
        send(0, BOOT, 4);
      }
      return;
    case CONFIGURE:
      configure(seq, p, n);
      return;
    case HOLD:
    case RESUME:
    case ABORT:
      if (fresh_request(type, seq)) {
        if (type == HOLD && state == State::running) {
          const uint8_t s = SREG;
          cli();
          if (running) {
            stop_time = timer_now();
            running = false;
            stop_reason = 2;
          }
          SREG = s;
          update_state();
          if (state == State::running) state = State::held;
        }
        if (type == RESUME && (state == State::held || state == State::underrun)) resume_job();
        if (type == ABORT) {
          reset_job();
          state = State::aborted;
        }
      }
      send_ack(seq);
      return;
    case QUEUE:
    case START: {
      if (!configured) {
        send_error(ErrorCode::not_configured, PSTR("not configured"), seq);
        return;
      }
      const int d = seq_diff(seq, next_seq);
      if (d < 0) {
        send_ack(0);
        return;
      }
      if (d > 0) {  // ahead of a missing frame: not kept (NAK says so: the host sends them again after it)
        hole = true;  // asked for once here, and every 50 ms until it comes (renak(): the NAK or the frame lost)
        if (!nak_sent || last_nak != next_seq) send_nak();
        return;
      }
      hole = false;
      if (state != State::fault && state != State::aborted) {
        if (type == QUEUE) handle_queue(p, n);
        else if (state == State::ready) {
          state = State::running;
          start_job();
        }
      }
      if (state != State::fault) ++next_seq;
      produce();
      send_ack(0);
      return;
    }
    default:
      return;  // unknown types are ignored (a newer host)
  }
}

// ---- frame reassembly (the same rules as the host's decoder) -----------------------------------------------------

// Frames of up to 96 payload bytes are taken (the host's QUEUE frames carry 64 at most, CONFIGURE 57): a longer
// one is skipped as damaged. RAM is 2 KB.
constexpr size_t kMaxRxPayload = 96;
uint8_t fb[kOverhead + kMaxRxPayload];
uint8_t fn;

void consume(uint8_t k) {
  memmove(fb, fb + k, fn - k);
  fn = static_cast<uint8_t>(fn - k);
}

void receive() {
  while (fn < sizeof fb && rx_tail != rx_head) {
    const uint8_t t = rx_tail;
    fb[fn++] = rx_buf[t];
    rx_tail = static_cast<uint8_t>((t + 1) & (kRxSize - 1));
  }
  for (;;) {
    uint8_t pos = 0;
    while (pos < fn && fb[pos] != kSync) ++pos;
    if (pos) consume(pos);
    if (fn < 3) return;
    if (!frame_len_ok(fb[1], fb[2]) || fb[1] > kMaxRxPayload + 3) {  // not a frame start, a damaged length
      consume(1);
      continue;
    }
    const size_t total = frame_size(fb[1]);
    if (fn < total) return;
    if (!frame_crc_ok(fb)) {
      ++bad_frames;
      consume(1);  // a good frame may start inside the damaged one
      continue;
    }
    handle(fb);
    consume(static_cast<uint8_t>(total));
  }
}

}  // namespace

int main() {
  DDRD |= kRStep | kTStep | kRDir | kTDir;
  DDRB |= kEnable | kLed | kTool;
  PORTB |= kEnable;  // drivers off until a job is configured
  // UART 115200 8N1, double speed
  UCSR0A = _BV(U2X0);
  UBRR0 = 16;
  UCSR0B = _BV(RXEN0) | _BV(TXEN0) | _BV(RXCIE0);
  UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);
  // Timer1: normal mode, clock / 64 (4 us), compare A interrupt
  TCCR1A = 0;
  TCCR1B = _BV(CS11) | _BV(CS10);
  TIMSK1 = _BV(OCIE1A) | _BV(TOIE1);
  store_reset();
  session = 1;
  set_sleep_mode(SLEEP_MODE_IDLE);
  sei();
  Put(payload_out(), kPayloadOut).u32(session);
  send(0, BOOT, 4);
  for (;;) {
    receive();
    produce();
    update_state();
    // a window update: the host learns of the room the schedule freed without asking
    if (configured && free_slots() >= acked_free + kWindowUpdate) send_ack(0);
    renak();
    // sleep until the next interrupt when there is nothing to do (the simulator then skips the idle cycles)
    cli();
    if (rx_tail == rx_head) {
      sleep_enable();
      sei();
      sleep_cpu();
      sleep_disable();
    }
    sei();
  }
}
