#include "capture/csv_levels.hpp"

#include <algorithm>

#include "cam/error.hpp"

namespace polarcam {
namespace {

std::string trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && (s[a] == ' ' || s[a] == '\t' || s[a] == '\r')) ++a;
  while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t' || s[b - 1] == '\r')) --b;
  return s.substr(a, b - a);
}

// A CSV line's fields, unquoted ("a ""b""" is a "b") and trimmed.
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string f;
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') f += '"', ++i;
      else if (c == '"') quoted = false;
      else f += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.push_back(trim(f));
      f.clear();
    } else {
      f += c;
    }
  }
  out.push_back(trim(f));
  return out;
}

std::string column_list(const std::vector<std::string>& names) {
  std::string s;
  for (size_t i = 0; i < names.size() && i < 12; ++i) s += (i ? ", " : "") + names[i];
  if (names.size() > 12) s += ", ...";
  return s;
}

}  // namespace

bool parse_decimal_seconds(const std::string& text, int64_t& mantissa, int& exp10) {
  size_t i = 0;
  bool negative = false;
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) negative = text[i++] == '-';
  int64_t m = 0;
  int digits = 0, significant = 0, frac = 0;
  bool point = false;
  for (; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '.' && !point) {
      point = true;
      continue;
    }
    if (c < '0' || c > '9') break;
    ++digits;
    if (point) ++frac;
    if (m == 0 && c == '0') continue;  // leading zeros carry no digits of the mantissa
    if (++significant > 18) return false;
    m = m * 10 + (c - '0');
  }
  if (digits == 0) return false;
  int e = 0;
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    bool eneg = false;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) eneg = text[i++] == '-';
    int ed = 0;
    for (; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i) {
      if (++ed > 4) return false;
      e = e * 10 + (text[i] - '0');
    }
    if (ed == 0) return false;
    if (eneg) e = -e;
  }
  if (i != text.size()) return false;
  mantissa = negative ? -m : m;
  exp10 = e - frac;
  return true;
}

CsvLevelReader::CsvLevelReader(std::istream& in, std::string file, const std::vector<std::string>& signals)
    : in_(in), file_(std::move(file)) {
  if (signals.empty() || signals.size() > static_cast<size_t>(kMaxLevelSignals))
    throw InputError("a CSV level reader reads 1 to 32 signals", file_);
  std::string line;
  std::vector<std::string> head;
  while (std::getline(in_, line)) {
    ++line_;
    const std::string t = trim(line);
    if (t.empty() || t[0] == ';' || t[0] == '#') continue;
    head = split(t);
    break;
  }
  if (head.empty())
    throw InputError("no header row: the first row names the columns, time_s and the levels (time_s,r_a,r_b,...)",
                     place(std::max<uint64_t>(line_, 1)));
  columns_ = head.size();
  auto col = [&](const std::string& name) {
    auto it = std::find(head.begin(), head.end(), name);
    if (it == head.end())
      throw InputError("no column '" + name + "' (the columns are " + column_list(head) +
                           "): the first row names the columns, time_s and the levels; map a level with --signals " +
                           (name == "time_s" ? std::string("r_a=COLUMN") : name + "=COLUMN"),
                       place(line_));
    return static_cast<size_t>(it - head.begin());
  };
  time_col_ = col("time_s");
  for (const std::string& s : signals) level_col_.push_back(col(s));
}

int64_t CsvLevelReader::resolution_fs() const {
  const int e = std::min(15 + (any_ ? min_exp_ : 0), 18);
  int64_t r = 1;
  for (int i = 0; i < e; ++i) r *= 10;
  return r;
}

bool CsvLevelReader::row(std::vector<std::string>& fields) {
  std::string line;
  while (std::getline(in_, line)) {
    ++line_;
    const std::string t = trim(line);
    if (t.empty() || t[0] == ';' || t[0] == '#') continue;
    fields = split(t);
    return true;
  }
  return false;
}

bool CsvLevelReader::next(LevelSample& s) {
  std::vector<std::string> f;
  while (row(f)) {
    if (f.size() != columns_)
      throw InputError("the row has " + std::to_string(f.size()) + " fields, the header names " +
                           std::to_string(columns_) + " columns: give every column on every row",
                       place(line_));
    int64_t m = 0;
    int e = 0;
    if (!parse_decimal_seconds(f[time_col_], m, e))
      throw InputError("time_s '" + f[time_col_].substr(0, 40) +
                           "' is not a decimal number of seconds (e.g. 0.000125 or 1.25e-4, at most 18 digits)",
                       place(line_));
    if (e < -15 && m != 0)
      throw InputError("time_s '" + f[time_col_].substr(0, 40) + "' has digits finer than 1 fs: round it to 1 fs",
                       place(line_));
    if (e > 3 && m != 0)
      throw InputError("time_s '" + f[time_col_].substr(0, 40) + "' is beyond 10^21 s: give seconds", place(line_));
    capture_i128 t = m;
    for (int i = 0; i < 15 + e; ++i) t *= 10;
    for (int i = 0; i < -(15 + e); ++i) t /= 10;  // only a zero mantissa gets here
    if (any_ && t < last_fs_)
      throw InputError("time_s " + f[time_col_].substr(0, 40) +
                           " goes back (the row before is later): rows must be in time order",
                       place(line_));
    uint32_t levels = 0;
    for (size_t i = 0; i < level_col_.size(); ++i) {
      const std::string& v = f[level_col_[i]];
      if (v == "1") levels |= uint32_t{1} << i;
      else if (v != "0")
        throw InputError("'" + v.substr(0, 40) + "' is not a level 0 or 1 (column " + std::to_string(level_col_[i] + 1) + ")",
                         place(line_));
    }
    const uint32_t all = level_col_.size() == 32 ? ~0u : (uint32_t{1} << level_col_.size()) - 1;
    const uint32_t changed = any_ ? (levels ^ levels_) : all;
    min_exp_ = any_ ? std::min(min_exp_, std::max(e, -15)) : std::max(e, -15);
    any_ = true;
    last_fs_ = t;
    levels_ = levels;
    if (!changed) continue;
    s.t_fs = t;
    s.levels = levels;
    s.known = all;
    s.changed = changed;
    s.line = line_;
    return true;
  }
  return false;
}

}  // namespace polarcam
