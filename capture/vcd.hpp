#pragma once
// A reader of Value Change Dump files (IEEE 1364-2005, Sec. 18: the format sigrok/PulseView, simulators and
// simavr write) for 1-bit signals chosen by name.
//
// Header: $timescale (1, 10 or 100 of s, ms, us, ns, ps, fs), $scope/$upscope, $var TYPE SIZE ID NAME [BITS]
// $end; $date, $version, $comment and unknown header sections are skipped. A signal is asked for by its name
// ("r_a", matching a $var of that name in any scope, when only one wire has it) or by its full name with its
// scopes ("top.encoder.r_a"); it must be 1 bit wide. Several $vars may share an identifier (aliases).
// Body: #TIME (non-decreasing), scalar changes 0ID 1ID xID zID, vectors bVALUE ID of width 1 (b0, b1; leading
// zeros allowed), reals rVALUE ID of other signals (skipped); $dumpvars, $dumpall, $dumpon and their $end are
// transparent, the x values inside $dumpoff ... $end are ignored, $comment ... $end is skipped.
// x and z: a signal is unknown until its first 0 or 1; an x or z after that is refused (a capture must hold
// levels), naming the line, unless the signal is one of those the reader was told may become unknown again (a
// step/dir decoder reports a step edge met by an unknown direction itself): then the level is unknown again
// (its `known` bit cleared, `changed` set) until the next 0 or 1.
// Every failure is an InputError naming FILE:LINE and what to change.
#include <istream>
#include <string>
#include <vector>

#include "capture/levels.hpp"

namespace polarcam {

class VcdReader final : public LevelSource {
 public:
  // Reads the header from `in` (which must outlive the reader); `file` names it in messages. `signals` are the
  // names asked for, signal i being bit i of the samples. InputError for a bad header or a signal not found.
  // `may_be_unknown`: bits of the signals that may go back to x or z after a level (default none).
  VcdReader(std::istream& in, std::string file, const std::vector<std::string>& signals,
            uint32_t may_be_unknown = 0);

  bool next(LevelSample& s) override;
  int64_t resolution_fs() const override { return unit_fs_; }
  capture_i128 end_fs() const override { return static_cast<capture_i128>(now_) * unit_fs_; }
  std::string place(uint64_t line) const override { return line ? file_ + ":" + std::to_string(line) : file_; }

  // The full names of the $vars matched to the signals asked for (for reports).
  const std::vector<std::string>& matched() const { return matched_; }

 private:
  struct Var {
    std::string id, name, full;
    int64_t width = 0;
    uint64_t line = 0;
  };
  bool token(std::string& t);             // next whitespace-separated word; false at the end
  void skip_section(const std::string& what);  // words up to $end
  [[noreturn]] void fail(const std::string& what) const;
  [[noreturn]] void fail_at(uint64_t line, const std::string& what) const;
  void read_header(const std::vector<std::string>& signals);

  std::istream& in_;
  std::string file_;
  uint64_t line_ = 1, tok_line_ = 1;
  int64_t unit_fs_ = 1000000;  // VCD's default: 1 ns
  int64_t now_ = 0;
  bool timed_ = false;         // a #time has been read
  bool dumpoff_ = false;
  bool eof_ = false;
  std::vector<std::pair<std::string, uint32_t>> ids_;  // identifier -> bits of the signals asked for (sorted)
  std::vector<std::string> matched_;
  uint32_t levels_ = 0, known_ = 0, changed_ = 0;
  uint32_t may_be_unknown_ = 0;
  uint64_t last_line_ = 0;
};

}  // namespace polarcam
