#pragma once
// An emulated serial line between host and controller, with fault injection (docs/controller-protocol.md,
// "Emulator"). Each direction carries bytes at the line rate (10 bits a byte) on a simulated clock (seconds),
// and can drop, corrupt or delay bytes. Deterministic for a given seed.
#include <cstdint>
#include <deque>
#include <random>
#include <string>

namespace polarcam {

struct FaultSpec {
  double drop = 0, corrupt = 0, delay = 0;  // fractions of bytes, each direction
  double delay_s = 0.02;                    // pause before a delayed byte
  double stall_at = -1, stall_s = 0;        // the controller stops reading for stall_s seconds from stall_at
  double disconnect_at = -1, disconnect_s = 0;  // the line carries nothing either way for disconnect_s seconds
  double reset_at = -1;                     // the controller reboots at this time
  uint64_t seed = 1;
  bool any() const {
    return drop > 0 || corrupt > 0 || delay > 0 || stall_at >= 0 || disconnect_at >= 0 || reset_at >= 0;
  }
};

// "drop=0.01,corrupt=0.01,delay=0.001,delay_ms=20,stall=2@5,disconnect=1@3,reset@4,seed=7" (times in seconds of
// the emulator's clock; stall=DURATION@TIME). Throws InputError naming the bad item.
FaultSpec parse_faults(const std::string& spec);
std::string to_string(const FaultSpec& f);

class LineDirection {
 public:
  LineDirection(double baud, const FaultSpec& faults, uint64_t seed);
  // Bytes handed to the line at time `now` (s).
  void send(const uint8_t* data, size_t n, double now);
  void send(const std::string& s, double now) { send(reinterpret_cast<const uint8_t*>(s.data()), s.size(), now); }
  // Bytes that have arrived by `now`.
  std::string deliver(double now);
  // Time the next byte arrives (infinity when none is in flight).
  double next_arrival() const;
  size_t in_flight() const { return q_.size(); }
  void cut(bool down) { down_ = down; }  // a disconnected line loses everything
  uint64_t dropped = 0, corrupted = 0, delayed = 0, carried = 0;

 private:
  double byte_s_;
  FaultSpec f_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> u_{0.0, 1.0};
  std::deque<std::pair<double, uint8_t>> q_;
  double last_ = 0;
  bool down_ = false;
};

}  // namespace polarcam
