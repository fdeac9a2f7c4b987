#include "io/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace polarcam::cli {

namespace {

std::string clock_text(double s) {
  if (!std::isfinite(s) || s < 0.0) return "--:--";
  const long t = std::lround(s);
  char b[32];
  if (t >= 3600)
    std::snprintf(b, sizeof b, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  else
    std::snprintf(b, sizeof b, "%02ld:%02ld", t / 60, t % 60);
  return b;
}

}  // namespace

TerminalBar::TerminalBar(std::string label, bool quiet)
    : label_(std::move(label)), active_(!quiet && ::isatty(STDERR_FILENO) == 1) {
  start_ = last_ = std::chrono::steady_clock::now();
}

TerminalBar::~TerminalBar() {
  if (drawn_) {
    std::fputs("\r\033[K", stderr);  // erase the line
    std::fflush(stderr);
  }
}

std::string TerminalBar::line(const std::string& label, double fraction, double elapsed_s, int width) {
  const double f = std::clamp(std::isfinite(fraction) ? fraction : 0.0, 0.0, 1.0);
  const int fill = static_cast<int>(std::lround(f * width));
  const double eta = f > 0.0 ? elapsed_s * (1.0 - f) / f : -1.0;
  char pct[16];
  std::snprintf(pct, sizeof pct, "%3.0f%%", 100.0 * f);
  return label + " [" + std::string(static_cast<size_t>(fill), '#') + std::string(static_cast<size_t>(width - fill), '-') +
         "] " + pct + " ETA " + clock_text(eta);
}

void TerminalBar::update(double fraction) {
  if (!active_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  drawn_ = true;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  std::fprintf(stderr, "\r%s\033[K", line(label_, fraction, elapsed).c_str());
  std::fflush(stderr);
}

Progress TerminalBar::callback() {
  if (!active_) return {};
  return [this](double f) { update(f); };
}

}  // namespace polarcam::cli
