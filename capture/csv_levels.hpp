#pragma once
// Levels from a CSV file: a header row naming the columns, one of them `time_s` (seconds, a decimal number, with
// an exponent or not: 0.000125, 1.25e-4, negative before a trigger), the others levels 0 or 1; columns not asked
// for are ignored. Blank lines and lines starting with ';' or '#' (sigrok's comments) are skipped; fields may be
// quoted and padded with spaces. Rows are in time order (equal times allowed); a row that changes no level asked
// for is no sample. The resolution is the finest time digit seen (10^-k s for a time with k decimals), at most
// 1 fs. Every failure is an InputError naming FILE:LINE and what to change.
#include <istream>
#include <string>
#include <vector>

#include "capture/levels.hpp"

namespace polarcam {

class CsvLevelReader final : public LevelSource {
 public:
  // Reads the header row from `in` (which must outlive the reader); `file` names it in messages; `signals` are
  // the level columns asked for, column signals[i] being bit i of the samples.
  CsvLevelReader(std::istream& in, std::string file, const std::vector<std::string>& signals);

  bool next(LevelSample& s) override;
  int64_t resolution_fs() const override;
  capture_i128 end_fs() const override { return last_fs_; }
  std::string place(uint64_t line) const override { return line ? file_ + ":" + std::to_string(line) : file_; }

 private:
  bool row(std::vector<std::string>& fields);  // next data row; false at the end
  std::istream& in_;
  std::string file_;
  uint64_t line_ = 0;
  size_t time_col_ = 0, columns_ = 0;
  std::vector<size_t> level_col_;
  int min_exp_ = 0;  // the finest time digit: 10^min_exp_ s
  bool any_ = false;
  capture_i128 last_fs_ = 0;
  uint32_t levels_ = 0;
};

// `text` ("-1.25e-4", "0.000125") as an exact count of 10^exp10 seconds: mantissa * 10^exp10. False when it is
// not a decimal number or has more than 18 significant digits.
bool parse_decimal_seconds(const std::string& text, int64_t& mantissa, int& exp10);

}  // namespace polarcam
