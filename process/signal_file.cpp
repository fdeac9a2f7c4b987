// Process signal files (docs/monitoring.md): see signal_file.hpp.
#include "process/signal_file.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "cam/error.hpp"
#include "cam/input_file.hpp"

namespace polarcam::process {
namespace {

// The fields of a line split at commas, spaces trimmed, a trailing '\r' dropped.
std::vector<std::string> fields(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  std::vector<std::string> out;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    std::string_view f = line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    while (!f.empty() && (f.front() == ' ' || f.front() == '\t')) f.remove_prefix(1);
    while (!f.empty() && (f.back() == ' ' || f.back() == '\t')) f.remove_suffix(1);
    out.emplace_back(f);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

bool valid_name(const std::string& s) {
  if (s.empty() || s.size() > 64) return false;
  for (char c : s)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_')) return false;
  return true;
}

std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s.substr(0, 40)) out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? '?' : c;
  if (s.size() > 40) out += "...";
  return out + "'";
}

}  // namespace

const std::vector<double>* SignalRecord::find(const std::string& name) const {
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return &columns[i];
  return nullptr;
}

SignalRecord parse_signal_csv(const std::string& text, const std::string& file) {
  std::string_view rest(text);
  int lineno = 0;
  auto next_line = [&](std::string_view& line) {
    while (!rest.empty()) {
      const size_t nl = rest.find('\n');
      line = rest.substr(0, nl);
      rest = nl == std::string_view::npos ? std::string_view() : rest.substr(nl + 1);
      ++lineno;
      std::string_view t = line;
      while (!t.empty() && (t.front() == ' ' || t.front() == '\t' || t.front() == '\r')) t.remove_prefix(1);
      if (t.empty() || t.front() == '#') continue;
      return true;
    }
    return false;
  };
  auto at = [&] { return file + ":" + std::to_string(lineno); };
  std::string_view line;
  if (!next_line(line)) throw InputError("is empty: it needs a header `time_s,<signal columns>` and samples", file);
  SignalRecord r;
  const auto head = fields(line);
  if (head.front() != "time_s")
    throw InputError("the header must start with time_s, then the signal columns (e.g. time_s,force_N), not " +
                         quoted(head.front()),
                     at());
  if (head.size() < 2) throw InputError("the header names no signal column after time_s (e.g. force_N)", at());
  for (size_t i = 1; i < head.size(); ++i) {
    if (!valid_name(head[i]))
      throw InputError("column " + std::to_string(i + 1) + ": " + quoted(head[i]) +
                           " is not a column name (letters, digits and '_', e.g. force_N)",
                       at());
    for (size_t k = 0; k < r.names.size(); ++k)
      if (r.names[k] == head[i]) throw InputError("column " + head[i] + " is named twice", at());
    r.names.push_back(head[i]);
  }
  r.columns.resize(r.names.size());
  std::vector<double> t;
  double first_dt = 0.0;
  while (next_line(line)) {
    const auto cells = fields(line);
    if (cells.size() != head.size())
      throw InputError("has " + std::to_string(cells.size()) + " fields, the header " + std::to_string(head.size()),
                       at());
    if (t.size() >= kMaxSignalSamples)
      throw InputError("more than " + std::to_string(kMaxSignalSamples) + " samples", at());
    for (size_t i = 0; i < cells.size(); ++i) {
      const std::string& s = cells[i];
      double v = 0.0;
      const char* b = s.data();
      const char* e = s.data() + s.size();
      if (b != e && *b == '+') ++b;
      const auto [p, ec] = std::from_chars(b, e, v);
      if (s.empty() || ec != std::errc() || p != e || !std::isfinite(v))
        throw InputError("column " + head[i] + ": " + quoted(s) + " is not a finite number", at());
      // a signal's squares and their sums over millions of samples must stay finite (the RMS, the spectra): no
      // force, power or current measured on a machine comes near 1e15 in any unit
      if (i > 0 && std::abs(v) > 1e15)
        throw InputError("column " + head[i] + ": " + quoted(s) + " is beyond 1e15 in magnitude (check the column's unit)",
                         at());
      if (i == 0)
        t.push_back(v);
      else
        r.columns[i - 1].push_back(v);
    }
    if (t.size() >= 2) {
      const double dt = t[t.size() - 1] - t[t.size() - 2];
      if (t.size() == 2) {
        if (!(dt > 0.0)) throw InputError("column time_s: the time must increase", at());
        first_dt = dt;
      } else if (!(std::abs(dt - first_dt) <= 1e-3 * first_dt)) {
        throw InputError("column time_s: the samples must be evenly spaced (" + std::to_string(first_dt) +
                             " s at the start, " + std::to_string(dt) + " s here)",
                         at());
      }
    }
  }
  if (t.size() < 2) throw InputError("needs at least two samples", file);
  r.start_s = t.front();
  r.period_s = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  if (!(r.period_s > 0.0 && std::isfinite(r.period_s))) throw InputError("the time must increase", file);
  return r;
}

SignalRecord read_signal_csv(const std::string& path) {
  return parse_signal_csv(read_input_file(path), path);
}

std::string format_signal_csv(const SignalRecord& r, int digits) {
  std::string out = "time_s";
  for (const auto& n : r.names) out += "," + n;
  out += "\n";
  char buf[64];
  for (size_t k = 0; k < r.samples(); ++k) {
    std::snprintf(buf, sizeof buf, "%.9f", r.start_s + static_cast<double>(k) * r.period_s);
    out += buf;
    for (const auto& c : r.columns) {
      std::snprintf(buf, sizeof buf, ",%.*g", digits, c[k] == 0.0 ? 0.0 : c[k]);
      out += buf;
    }
    out += "\n";
  }
  return out;
}

}  // namespace polarcam::process
