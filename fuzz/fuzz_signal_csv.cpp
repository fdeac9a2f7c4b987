// Process signal files (process/signal_file.hpp): parse_signal_csv on the bytes and, when they parse, the monitor
// (process/monitor.hpp) on the chosen column and on the force estimated from current_A and speed_rad_per_s, at
// 600 rpm with 4 teeth: a typed error or events, never a crash, a hang or a NaN escaping as an exception.
#include "fuzz/fuzz_common.hpp"
#include "process/monitor.hpp"
#include "process/signal_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace polarcam;
  const std::string text(fuzz::as_text(data, size));
  fuzz::expect_typed([&] {
    const process::SignalRecord r = process::parse_signal_csv(text, "fuzz.csv");
    for (bool estimate : {false, true})
      fuzz::expect_typed([&] {
        const auto s = process::select_signal(r, "fuzz.csv", "", estimate);
        process::MonitorOptions o;
        o.sample_rate_hz = s.sample_rate_hz;
        o.spindle_rev_per_s = 10.0;
        o.teeth = 4;
        o.learn_revolutions = 1.0;
        o.overload = 100.0;
        process::monitor_signal(s.x, o);
      });
  });
  return 0;
}
