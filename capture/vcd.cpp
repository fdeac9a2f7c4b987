#include "capture/vcd.hpp"

#include <algorithm>

#include "cam/error.hpp"

namespace polarcam {
namespace {

constexpr size_t kMaxWord = size_t{1} << 16;  // a longer word is not VCD (and would only cost memory)

// A non-negative decimal integer, or -1 when `s` is not one or does not fit.
int64_t parse_count(const std::string& s, size_t from = 0) {
  if (from >= s.size() || s.size() - from > 18) return -1;
  int64_t v = 0;
  for (size_t i = from; i < s.size(); ++i) {
    if (s[i] < '0' || s[i] > '9') return -1;
    v = v * 10 + (s[i] - '0');
  }
  return v;
}

// "1ns", "10 ps", "100us": femtoseconds, or 0 when not a timescale.
int64_t timescale_fs(const std::string& text) {
  size_t i = 0;
  while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
  const int64_t n = parse_count(text.substr(0, i));
  if (n <= 0 || n > 1000) return 0;
  const std::string unit = text.substr(i);
  int64_t fs = 0;
  if (unit == "s") fs = 1000000000000000;
  else if (unit == "ms") fs = 1000000000000;
  else if (unit == "us") fs = 1000000000;
  else if (unit == "ns") fs = 1000000;
  else if (unit == "ps") fs = 1000;
  else if (unit == "fs") fs = 1;
  else return 0;
  return n * fs;
}

std::string list_names(const std::vector<std::string>& names) {
  std::string s;
  for (size_t i = 0; i < names.size() && i < 12; ++i) s += (i ? ", " : "") + names[i];
  if (names.size() > 12) s += ", ... (" + std::to_string(names.size()) + " in all)";
  return s.empty() ? "none" : s;
}

}  // namespace

VcdReader::VcdReader(std::istream& in, std::string file, const std::vector<std::string>& signals,
                     uint32_t may_be_unknown)
    : in_(in), file_(std::move(file)), may_be_unknown_(may_be_unknown) {
  if (signals.empty() || signals.size() > static_cast<size_t>(kMaxLevelSignals))
    throw InputError("a VCD reader reads 1 to 32 signals", file_);
  read_header(signals);
}

bool VcdReader::token(std::string& t) {
  t.clear();
  std::streambuf* b = in_.rdbuf();
  if (!b) return false;
  int c;
  for (;;) {
    c = b->sbumpc();
    if (c == std::char_traits<char>::eof()) return false;
    if (c == '\n') ++line_;
    if (c != ' ' && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v') break;
  }
  tok_line_ = line_;
  for (;;) {
    t.push_back(static_cast<char>(c));
    if (t.size() > kMaxWord) fail_at(tok_line_, "a word of more than 65536 characters: this is not a VCD file");
    c = b->sgetc();
    if (c == std::char_traits<char>::eof() || c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' ||
        c == '\v')
      return true;
    b->sbumpc();
  }
}

void VcdReader::fail(const std::string& what) const { fail_at(tok_line_, what); }

void VcdReader::fail_at(uint64_t line, const std::string& what) const {
  throw InputError(what, place(line));
}

void VcdReader::skip_section(const std::string& what) {
  const uint64_t start = tok_line_;
  std::string t;
  while (token(t))
    if (t == "$end") return;
  fail_at(start, what + " has no $end: the file is truncated");
}

void VcdReader::read_header(const std::vector<std::string>& signals) {
  std::vector<Var> vars;
  std::vector<std::string> scopes;
  std::string t;
  bool defined = false;
  uint64_t end_line = 1;
  while (!defined && token(t)) {
    const uint64_t at = tok_line_;
    auto words = [&](const std::string& what) {
      std::vector<std::string> w;
      std::string x;
      for (;;) {
        if (!token(x)) fail_at(at, what + " has no $end: the file is truncated");
        if (x == "$end") return w;
        if (w.size() > 64) fail_at(at, what + " is too long: is $end missing?");
        w.push_back(x);
      }
    };
    if (t == "$timescale") {
      std::string text;
      for (const std::string& w : words("$timescale")) text += w;
      unit_fs_ = timescale_fs(text);
      if (unit_fs_ == 0)
        fail_at(at, "timescale '" + text + "' is not 1, 10 or 100 of s, ms, us, ns, ps or fs (e.g. \"1 ns\")");
    } else if (t == "$scope") {
      std::vector<std::string> w = words("$scope");
      scopes.push_back(w.empty() ? std::string() : w.back());
    } else if (t == "$upscope") {
      words("$upscope");
      if (scopes.empty()) fail_at(at, "$upscope without a $scope");
      scopes.pop_back();
    } else if (t == "$var") {
      std::vector<std::string> w = words("$var");
      if (w.size() < 4) fail_at(at, "$var needs a type, a width, an identifier and a name ($var wire 1 ! r_a $end)");
      Var v;
      v.width = parse_count(w[1]);
      if (v.width <= 0) fail_at(at, "$var width '" + w[1] + "' is not a positive whole number");
      v.id = w[2];
      v.name = w[3];
      for (const std::string& s : scopes) v.full += s + ".";
      v.full += v.name;
      v.line = at;
      vars.push_back(std::move(v));
    } else if (t == "$enddefinitions") {
      words("$enddefinitions");
      defined = true;
      end_line = at;
    } else if (!t.empty() && t[0] == '$') {
      skip_section(t);
    } else {
      fail_at(at, "'" + t.substr(0, 40) + "' in the header: a VCD header holds $commands ... $end (is this a VCD file?)");
    }
  }
  if (!defined) fail_at(line_, "no $enddefinitions: the file is not a VCD file, or it is truncated");

  // the signals asked for
  std::vector<std::string> all;
  for (const Var& v : vars) all.push_back(v.full);
  for (size_t i = 0; i < signals.size(); ++i) {
    const std::string& want = signals[i];
    std::vector<const Var*> hit;
    for (const Var& v : vars)
      if (v.full == want) hit.push_back(&v);
    if (hit.empty())
      for (const Var& v : vars)
        if (v.name == want) hit.push_back(&v);
    if (hit.empty())
      fail_at(end_line, "no signal named '" + want + "'; the file's signals are " + list_names(all) +
                            ": name the one to read (--signals " + want + "=NAME)");
    for (const Var* v : hit)
      if (v->id != hit.front()->id)
        fail_at(end_line, "signal name '" + want + "' is ambiguous (" + hit.front()->full + ", " + v->full +
                              "): give its full name with its scopes");
    const Var& v = *hit.front();
    if (v.width != 1)
      fail_at(v.line, "signal '" + v.full + "' is " + std::to_string(v.width) +
                          " bits wide: a level is one bit; name a 1-bit signal");
    matched_.push_back(v.full);
    auto it = std::find_if(ids_.begin(), ids_.end(), [&](const auto& p) { return p.first == v.id; });
    if (it == ids_.end()) ids_.emplace_back(v.id, 0u);
    it = std::find_if(ids_.begin(), ids_.end(), [&](const auto& p) { return p.first == v.id; });
    it->second |= uint32_t{1} << i;
  }
}

bool VcdReader::next(LevelSample& s) {
  if (eof_) return false;
  auto sample = [&] {
    LevelSample x;
    x.t_fs = static_cast<capture_i128>(now_) * unit_fs_;
    x.levels = levels_;
    x.known = known_;
    x.changed = changed_;
    x.line = last_line_;
    changed_ = 0;
    return x;
  };
  std::string t, id;
  while (token(t)) {
    const char c = t[0];
    if (c == '#') {
      const int64_t n = parse_count(t, 1);
      if (n < 0) fail("timestamp '" + t.substr(0, 40) + "' is not # and a whole number of timescale units (e.g. #1500)");
      if (timed_ && n < now_)
        fail("time #" + std::to_string(n) + " goes back (after #" + std::to_string(now_) +
             "): the times of a VCD must not decrease");
      timed_ = true;
      if (n != now_ && changed_) {
        s = sample();
        now_ = n;
        return true;
      }
      now_ = n;
      continue;
    }
    if (c == '$') {
      if (t == "$dumpoff") dumpoff_ = true;
      else if (t == "$end") dumpoff_ = false;
      else if (t == "$comment") skip_section(t);
      else if (t != "$dumpvars" && t != "$dumpall" && t != "$dumpon")
        fail("'" + t.substr(0, 40) + "' among the value changes: expected $dumpvars, $dumpall, $dumpon, $dumpoff, "
             "$comment or $end");
      continue;
    }
    char level = 0;
    uint32_t bits = 0;
    auto lookup = [&](const std::string& key) {
      for (const auto& p : ids_)
        if (p.first == key) return p.second;
      return 0u;
    };
    if (c == '0' || c == '1' || c == 'x' || c == 'X' || c == 'z' || c == 'Z') {
      if (t.size() < 2) fail("value change '" + t + "' has no identifier (e.g. 1! sets signal ! to 1)");
      bits = lookup(t.substr(1));
      level = static_cast<char>(c | 0x20);  // lower case
    } else if (c == 'b' || c == 'B') {
      if (t.size() < 2) fail("vector value 'b' has no digits (e.g. b1 !)");
      if (!token(id)) fail("vector value '" + t.substr(0, 40) + "' has no identifier: the file is truncated");
      bits = lookup(id);
      if (!bits) continue;
      for (size_t i = 1; i + 1 < t.size(); ++i)
        if (t[i] != '0') fail("value '" + t.substr(0, 40) + "' of a 1-bit signal has more than one bit");
      level = static_cast<char>(t.back() | 0x20);
      if (level != '0' && level != '1' && level != 'x' && level != 'z')
        fail("value '" + t.substr(0, 40) + "' is not a binary level (b0, b1, bx, bz)");
    } else if (c == 'r' || c == 'R') {
      if (!token(id)) fail("real value '" + t.substr(0, 40) + "' has no identifier: the file is truncated");
      if (lookup(id)) fail("a real value for 1-bit signal '" + id + "': a level is 0 or 1");
      continue;
    } else {
      fail("'" + t.substr(0, 40) + "' is not a timestamp (#TIME), a value change (0ID, 1ID, bVALUE ID) or a $command");
    }
    if (!bits || dumpoff_) continue;
    if (level == 'x' || level == 'z') {
      const uint32_t lost = known_ & bits;  // the signals that had a level
      if (!lost) continue;
      if (lost & ~may_be_unknown_)
        fail(std::string("signal goes to ") + level + " (unknown) at #" + std::to_string(now_) +
             ": once a signal has a level, a capture must hold 0 or 1");
      bool emit = false;
      if (changed_ & lost) {  // a second change at one time: the sample so far comes first
        s = sample();
        emit = true;
      }
      levels_ &= ~lost;
      known_ &= ~lost;
      changed_ |= lost;
      last_line_ = tok_line_;
      if (emit) return true;
      continue;
    }
    const uint32_t v = level == '1' ? bits : 0u;
    const uint32_t diff = ((levels_ & bits) ^ v) | (bits & ~known_);
    if (!diff) continue;
    bool emit = false;
    if (changed_ & diff) {  // a second change of a signal at one time: the sample so far comes first
      s = sample();
      emit = true;
    }
    levels_ = (levels_ & ~bits) | v;
    known_ |= bits;
    changed_ |= diff;
    last_line_ = tok_line_;
    if (emit) return true;
  }
  eof_ = true;
  if (changed_) {
    s = sample();
    return true;
  }
  return false;
}

}  // namespace polarcam
