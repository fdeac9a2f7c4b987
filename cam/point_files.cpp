#include "cam/point_files.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "cam/error.hpp"
#include "cam/input_file.hpp"

namespace polarcam {
namespace {

// Splits a line into numeric fields; returns false when a field is not a number. A field may be in double quotes, as
// spreadsheets write them: a separator inside the quotes is part of the field ("1,5" is not a number, not 1 and 5).
bool parse_numbers(const std::string& line, std::vector<double>& out) {
  out.clear();
  std::string cur;
  bool quoted = false;
  auto flush = [&]() -> bool {
    if (cur.empty()) return true;
    double v = 0.0;
    const char* b = cur.data();
    const char* e = cur.data() + cur.size();
    if (*b == '+') ++b;
    auto [p, ec] = std::from_chars(b, e, v);
    if (ec != std::errc() || p != e) return false;
    out.push_back(v);
    cur.clear();
    return true;
  };
  for (char c : line) {
    if (c == '"') {
      quoted = !quoted;
    } else if (!quoted && (c == ',' || c == ';' || c == '\t' || c == ' ' || c == '\r')) {
      if (!flush()) return false;
    } else {
      cur.push_back(c);
    }
  }
  return !quoted && flush();
}

template <class F>
std::vector<Vec2> read_pairs(const std::string& path, const char* kind, F convert) {
  std::ifstream in = open_input_file(path, "cannot open the " + std::string(kind) + " file");
  std::vector<Vec2> pts;
  std::vector<double> nums;
  std::string line;
  size_t lineno = 0;
  bool header_allowed = true;
  while (std::getline(in, line)) {
    ++lineno;
    auto hash = line.find_first_of("#/");
    if (hash != std::string::npos && (line[hash] == '#' || (hash + 1 < line.size() && line[hash + 1] == '/')))
      line.erase(hash);
    if (line.find_first_not_of(" \t\r,;") == std::string::npos) continue;
    if (!parse_numbers(line, nums)) {
      if (header_allowed) {
        header_allowed = false;
        continue;
      }
      throw InputError("expected two numbers, got '" + line + "'", path + ":" + std::to_string(lineno));
    }
    header_allowed = false;
    if (nums.size() != 2)
      throw InputError("expected two numbers, got " + std::to_string(nums.size()), path + ":" + std::to_string(lineno));
    if (!std::isfinite(nums[0]) || !std::isfinite(nums[1]))
      throw InputError("not a finite number", path + ":" + std::to_string(lineno));
    pts.push_back(convert(nums[0], nums[1]));
  }
  if (pts.empty()) throw InputError("no points in the file", path);
  return pts;
}

}  // namespace

std::vector<Vec2> read_points_csv(const std::string& path, double unit_m) {
  return read_pairs(path, "CSV", [unit_m](double x, double y) { return Vec2{x * unit_m, y * unit_m}; });
}
}  // namespace polarcam
