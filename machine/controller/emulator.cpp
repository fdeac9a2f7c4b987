#include "machine/controller/emulator.hpp"

#include <algorithm>
#include <cmath>

namespace polarcam {

Emulator::Emulator(const ControllerSpec& spec, double baud, const FaultSpec& faults)
    : spec_(spec), f_(faults), ctl_(std::make_unique<Controller>(spec, 1)), up_(baud, faults, faults.seed * 2 + 1),
      down_(baud, faults, faults.seed * 2 + 2) {
  ctl_->on_step = [this](uint64_t t, int axis, int dir) {
    if (on_step) on_step(static_cast<uint64_t>(static_cast<double>(t) * static_cast<double>(spec_.tick_ps) / 1000.0 + 0.5), axis, dir);
  };
  ctl_->on_tool = [this](uint64_t t, bool down) {
    if (on_tool) on_tool(static_cast<uint64_t>(static_cast<double>(t) * static_cast<double>(spec_.tick_ps) / 1000.0 + 0.5), down);
  };
  if (spec_.tick_ps % 1000 == 0) {
    const uint64_t ns = spec_.tick_ps / 1000;
    ctl_->on_step = [this, ns](uint64_t t, int axis, int dir) {
      if (on_step) on_step(t * ns, axis, dir);
    };
    ctl_->on_tool = [this, ns](uint64_t t, bool down) {
      if (on_tool) on_tool(t * ns, down);
    };
  }
}

uint64_t Emulator::ticks(double now) const {
  return static_cast<uint64_t>(std::floor(now * 1e12 / static_cast<double>(spec_.tick_ps)));
}

bool Emulator::stalled(double now) const {
  return f_.stall_at >= 0 && now >= f_.stall_at && now < f_.stall_at + f_.stall_s;
}

bool Emulator::reading(double now) const { return !stalled(now) && up_.in_flight() < 512; }

void Emulator::from_host(const std::string& bytes, double now) {
  if (garble) {
    std::string g = bytes;
    for (char& c : g) c = static_cast<char>(c ^ 0x55);
    up_.send(g, now);
    return;
  }
  up_.send(bytes, now);
}

void Emulator::advance(double now) {
  now_ = std::max(now_, now);
  const bool down = f_.disconnect_at >= 0 && now_ >= f_.disconnect_at && now_ < f_.disconnect_at + f_.disconnect_s;
  up_.cut(down);
  down_.cut(down);
  if (f_.reset_at >= 0 && !reset_done_ && now_ >= f_.reset_at) {
    reset_done_ = true;
    ++resets;
    ctl_->reboot(ticks(now_));
  }
  const std::string in = stalled(now_) ? std::string() : up_.deliver(now_);  // a stalled reader takes nothing
  if (!in.empty()) ctl_->receive(reinterpret_cast<const uint8_t*>(in.data()), in.size(), ticks(now_));
  ctl_->advance(ticks(now_));
  const std::string out = ctl_->take_output();
  if (!out.empty()) down_.send(out, now_);
}

std::string Emulator::to_host(double now) {
  std::string s = down_.deliver(now);
  if (garble)
    for (char& c : s) c = static_cast<char>(c ^ 0x55);
  return s;
}

double Emulator::next_event() const { return std::min(up_.next_arrival(), down_.next_arrival()); }

// ------------------------------------------------------------------------------------------------ SimTransport

SimTransport::SimTransport(const ControllerSpec& spec, double baud, const FaultSpec& faults) : emu_(spec, baud, faults) {}

void SimTransport::run_until(double t) {
  // step the virtual clock through line events, at most 1 ms at a time so the controller's timers run
  while (now_ < t) {
    double next = std::min(t, now_ + 1e-3);
    next = std::min(next, std::max(emu_.next_event(), now_ + 1e-6));
    now_ = next;
    emu_.advance(now_);
    pending_ += emu_.to_host(now_);
    if (!pending_.empty()) return;
  }
}

bool SimTransport::write(const std::string& bytes, double) {
  emu_.from_host(bytes, now_);
  return true;
}

std::string SimTransport::read(double timeout_s) {
  if (pending_.empty()) run_until(now_ + timeout_s);
  std::string s;
  s.swap(pending_);
  return s;
}

}  // namespace polarcam
