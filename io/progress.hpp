#pragma once
// Progress of long work. A library that can take more than about a second accepts a `Progress` (empty by default)
// and calls it with the fraction done, 0 to 1, from the thread doing the work; it never prints. The CLI turns it
// into a bar on the terminal (TerminalBar): a bar, the percentage and an estimate of the time left, on stderr only
// when stderr is a terminal and --quiet is not given, redrawn at most ten times a second and erased at the end.
#include <chrono>
#include <functional>
#include <mutex>
#include <string>

namespace polarcam {

using Progress = std::function<void(double fraction)>;

// Calls `p` when it is set.
inline void report_progress(const Progress& p, double fraction) {
  if (p) p(fraction);
}

// A stage of long work that covers [from, to] of the whole: its own 0..1 mapped there (empty when `p` is).
inline Progress progress_part(const Progress& p, double from, double to) {
  if (!p) return {};
  return [p, from, to](double f) { p(from + (to - from) * f); };
}

}  // namespace polarcam

namespace polarcam::cli {

class TerminalBar {
 public:
  // Active when stderr is a terminal and not `quiet`.
  TerminalBar(std::string label, bool quiet);
  ~TerminalBar();  // erases the bar
  TerminalBar(const TerminalBar&) = delete;
  TerminalBar& operator=(const TerminalBar&) = delete;

  bool active() const { return active_; }
  // Thread-safe; draws at most every 100 ms (and at the first call).
  void update(double fraction);
  // A Progress that updates this bar (empty when the bar is not active); the bar must outlive its use.
  Progress callback();

  // The line drawn for `fraction` done after `elapsed_s` seconds, `width` characters of bar (no terminal needed).
  static std::string line(const std::string& label, double fraction, double elapsed_s, int width = 30);

 private:
  std::string label_;
  bool active_ = false, drawn_ = false;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace polarcam::cli
