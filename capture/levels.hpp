#pragma once
// Logic levels recorded by a logic analyser or a simulator, as a stream of samples: after each sample time, the
// level of every signal asked for. The VCD reader (capture/vcd.hpp) and the CSV reader (capture/csv_levels.hpp)
// produce it; the quadrature and step/dir decoders (capture/capture.hpp) consume it. Times are exact:
// femtoseconds in a 128-bit integer, as recorded (no origin taken, no rounding).
//
// This header and capture/vcd.cpp depend on nothing but cam/error.hpp (a program outside the CMake build can
// compile the VCD reader with them).
#include <cstdint>
#include <string>

namespace polarcam {

__extension__ typedef __int128 capture_i128;

// At most this many signals per reader (bits of LevelSample::levels).
inline constexpr int kMaxLevelSignals = 32;

struct LevelSample {
  capture_i128 t_fs = 0;  // the sample's time in femtoseconds, as recorded
  uint32_t levels = 0;    // bit i: level of signal i after this time's changes (0 while unknown)
  uint32_t known = 0;     // bit i: signal i has had a level 0 or 1
  uint32_t changed = 0;   // bit i: signal i changed level at this sample (from a known level or from unknown, or
                          // to unknown where the reader allows that)
  uint64_t line = 0;      // the line of the file that completed the sample (for messages)
};

// Samples in time order: one per recorded time at which an asked-for signal changed. A signal that changes twice
// at one recorded time (a glitch narrower than the resolution) splits that time into two samples with equal
// times, so no change is lost; changes of two signals at one time are one sample.
class LevelSource {
 public:
  virtual ~LevelSource() = default;
  // The next sample; false at the end of the file. Throws InputError naming FILE:LINE for bad input.
  virtual bool next(LevelSample& s) = 0;
  // The recording's time resolution in femtoseconds (a VCD's timescale; a CSV's finest time digit so far).
  virtual int64_t resolution_fs() const = 0;
  // The last time the file holds (a VCD's last #time, a CSV's last row), in femtoseconds; valid after next()
  // has returned false.
  virtual capture_i128 end_fs() const = 0;
  // "FILE:LINE" for messages; the file alone for line 0.
  virtual std::string place(uint64_t line) const = 0;
};

}  // namespace polarcam
