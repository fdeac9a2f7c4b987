#pragma once
// The controller emulator's core: a Controller behind an emulated serial line with faults, on a simulated clock
// in seconds. `polarcam controller-sim` drives it from the wall clock over a pseudo-terminal; tests and
// SimTransport drive it from a virtual clock in-process.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "machine/controller/controller.hpp"
#include "machine/link/host_link.hpp"
#include "machine/link/sim_line.hpp"

namespace polarcam {

class Emulator {
 public:
  Emulator(const ControllerSpec& spec, double baud, const FaultSpec& faults);
  // Bytes the host wrote, handed to the line at `now` (s). Dropped while the line is disconnected.
  void from_host(const std::string& bytes, double now);
  // Runs the faults' timers, delivers what has arrived to the controller and executes the schedule to `now`.
  void advance(double now);
  // Bytes that have reached the host by `now`.
  std::string to_host(double now);
  // Whether the controller reads its input now: false while stalled, and while the line still carries more
  // than a UART's worth of earlier bytes (so a host that writes faster than the line rate is held back by
  // the port, as on real hardware).
  bool reading(double now) const;
  bool stalled(double now) const;
  // The next time something happens on the lines (for a virtual clock).
  double next_event() const;
  Controller& controller() { return *ctl_; }
  // Every executed step: ns since START (the tick times the tick length), axis, direction.
  std::function<void(uint64_t t_ns, int axis, int dir)> on_step;
  // Every executed tool item: ns since START, down (true) or up.
  std::function<void(uint64_t t_ns, bool down)> on_tool;
  bool garble = false;  // the host's line settings do not match: every byte arrives damaged
  uint64_t resets = 0;

 private:
  uint64_t ticks(double now) const;
  ControllerSpec spec_;
  FaultSpec f_;
  std::unique_ptr<Controller> ctl_;
  LineDirection up_, down_;  // host -> controller, controller -> host
  bool reset_done_ = false;
  double now_ = 0;
};

// A Transport to an in-process Emulator on a virtual clock: deterministic, as fast as the CPU allows.
class SimTransport : public Transport {
 public:
  SimTransport(const ControllerSpec& spec, double baud, const FaultSpec& faults);
  bool write(const std::string& bytes, double timeout_s) override;
  std::string read(double timeout_s) override;
  double now() override { return now_; }
  std::string describe() const override { return "simulated controller"; }
  Emulator& emulator() { return emu_; }

 private:
  void run_until(double t);
  Emulator emu_;
  double now_ = 0;
  std::string pending_;  // bytes for the host
};

}  // namespace polarcam
