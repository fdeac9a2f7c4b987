#include "cam/thr_file.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <istream>
#include <ostream>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "cam/input_file.hpp"

namespace polarcam {
namespace {

// Splits one line (comment removed) into numbers; returns the number of fields, or -1 when a field is not a
// number (its text in `bad`).
int split_numbers(const std::string& line, double out[2], std::string& bad) {
  int n = 0;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == ',' || line[i] == '\r')) ++i;
    if (i >= line.size()) break;
    size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != ',' && line[j] != '\r') ++j;
    const char* b = line.data() + i;
    const char* e = line.data() + j;
    if (*b == '+' && e - b > 1) ++b;
    double v = 0;
    auto [p, ec] = std::from_chars(b, e, v);
    if (ec != std::errc() || p != e || !std::isfinite(v)) {
      bad.assign(line.data() + i, j - i);
      return -1;
    }
    if (n < 2) out[n] = v;
    ++n;
    i = j;
  }
  return n;
}

}  // namespace

ThrPattern parse_thr(std::istream& in, const std::string& place) {
  ThrPattern p;
  std::string line;
  while (std::getline(in, line)) {
    ++p.lines;
    if (p.lines == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark
    const std::string where = place + ":" + std::to_string(p.lines);
    size_t cut = line.find('#');
    size_t slashes = line.find("//");
    cut = std::min(cut, slashes);
    if (cut != std::string::npos) line.erase(cut);
    double v[2];
    std::string bad;
    const int n = split_numbers(line, v, bad);
    if (n == 0) continue;
    if (n < 0) throw InputError("'" + bad.substr(0, 40) + "' is not a number (expected \"theta rho\")", where);
    if (n != 2) throw InputError("expected two numbers \"theta rho\", got " + std::to_string(n), where);
    if (!(v[1] >= 0.0 && v[1] <= 1.0))
      throw InputError("rho " + significant(v[1], 12) + " is outside 0..1 (rho is a fraction of the table radius)", where);
    ++p.points;
    if (!p.vertices.empty() && p.vertices.back().theta == v[0] && p.vertices.back().rho == v[1]) {
      ++p.merged;
      continue;
    }
    p.vertices.push_back({v[0], v[1]});
    p.line_of.push_back(p.lines);
  }
  if (in.bad()) throw DeviceError("cannot read the pattern", place);
  if (p.vertices.empty()) throw InputError("no points in the pattern (expected lines of \"theta rho\")", place);
  if (p.vertices.size() < 2) throw InputError("the pattern has one distinct point; a path needs two", place);
  return p;
}

ThrPattern read_thr(const std::string& path) {
  std::ifstream in = open_input_file(path, "cannot open the theta-rho file");
  return parse_thr(in, path);
}

ThrStats thr_stats(const std::vector<ThetaRho>& v) {
  ThrStats s;
  s.vertices = v.size();
  if (v.empty()) return s;
  s.theta_min = s.theta_max = v[0].theta;
  s.rho_min = s.rho_max = v[0].rho;
  for (size_t i = 0; i < v.size(); ++i) {
    s.theta_min = std::min(s.theta_min, v[i].theta);
    s.theta_max = std::max(s.theta_max, v[i].theta);
    s.rho_min = std::min(s.rho_min, v[i].rho);
    s.rho_max = std::max(s.rho_max, v[i].rho);
    if (i > 0 && i + 1 < v.size() && v[i].rho == 0.0) ++s.centre_touches;
    if (i > 0) s.length += theta_rho_segment_length(v[i - 1], v[i]);
  }
  s.start_rho = v.front().rho;
  s.end_rho = v.back().rho;
  return s;
}

void write_thr(std::ostream& out, const std::vector<ThetaRho>& v, const std::vector<std::string>& comment) {
  for (const std::string& c : comment) out << "# " << c << "\n";
  char buf[64];
  for (const ThetaRho& p : v) {
    auto r1 = std::to_chars(buf, buf + 32, p.theta);
    *r1.ptr++ = ' ';
    auto r2 = std::to_chars(r1.ptr, buf + 64, p.rho);
    *r2.ptr++ = '\n';
    out.write(buf, r2.ptr - buf);
  }
}

}  // namespace polarcam
