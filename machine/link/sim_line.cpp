#include "machine/link/sim_line.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "cam/error.hpp"

namespace polarcam {

FaultSpec parse_faults(const std::string& spec) {
  FaultSpec f;
  std::stringstream ss(spec);
  std::string item;
  auto number = [&](const std::string& v, const std::string& key) {
    size_t used = 0;
    double d = 0;
    try {
      d = std::stod(v, &used);
    } catch (...) {
      used = 0;
    }
    if (used != v.size() || !std::isfinite(d) || d < 0)
      throw InputError("--faults: '" + key + "' needs a non-negative number, got '" + v + "'");
    return d;
  };
  auto fraction = [&](const std::string& v, const std::string& key) {
    double d = number(v, key);
    if (d > 1) throw InputError("--faults: '" + key + "' is a fraction of bytes, at most 1, got '" + v + "'");
    return d;
  };
  auto at = [&](const std::string& v, const std::string& key, double& dur, double& when) {
    auto p = v.find('@');
    if (p == std::string::npos) throw InputError("--faults: '" + key + "' needs DURATION@TIME (seconds), got '" + v + "'");
    dur = number(v.substr(0, p), key);
    when = number(v.substr(p + 1), key);
  };
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    if (item.rfind("reset@", 0) == 0) {
      f.reset_at = number(item.substr(6), "reset");
      continue;
    }
    auto eq = item.find('=');
    if (eq == std::string::npos) throw InputError("--faults: '" + item + "' is not KEY=VALUE");
    const std::string k = item.substr(0, eq), v = item.substr(eq + 1);
    if (k == "drop") f.drop = fraction(v, k);
    else if (k == "corrupt") f.corrupt = fraction(v, k);
    else if (k == "delay") f.delay = fraction(v, k);
    else if (k == "delay_ms") f.delay_s = number(v, k) * 1e-3;
    else if (k == "stall") at(v, k, f.stall_s, f.stall_at);
    else if (k == "disconnect") at(v, k, f.disconnect_s, f.disconnect_at);
    else if (k == "seed") f.seed = static_cast<uint64_t>(number(v, k));
    else
      throw InputError("--faults: unknown fault '" + k + "' (known: drop, corrupt, delay, delay_ms, stall, disconnect, reset, seed)");
  }
  return f;
}

std::string to_string(const FaultSpec& f) {
  std::ostringstream o;
  o << "drop=" << f.drop << ",corrupt=" << f.corrupt << ",delay=" << f.delay << ",delay_ms=" << f.delay_s * 1e3;
  if (f.stall_at >= 0) o << ",stall=" << f.stall_s << "@" << f.stall_at;
  if (f.disconnect_at >= 0) o << ",disconnect=" << f.disconnect_s << "@" << f.disconnect_at;
  if (f.reset_at >= 0) o << ",reset@" << f.reset_at;
  o << ",seed=" << f.seed;
  return o.str();
}

LineDirection::LineDirection(double baud, const FaultSpec& faults, uint64_t seed)
    : byte_s_(10.0 / baud), f_(faults), rng_(seed) {}

void LineDirection::send(const uint8_t* data, size_t n, double now) {
  for (size_t i = 0; i < n; ++i) {
    double t = std::max(now, last_) + byte_s_;
    if (f_.delay > 0 && u_(rng_) < f_.delay) {
      t += f_.delay_s;
      ++delayed;
    }
    last_ = t;
    if (down_ || (f_.drop > 0 && u_(rng_) < f_.drop)) {
      ++dropped;
      continue;
    }
    uint8_t b = data[i];
    if (f_.corrupt > 0 && u_(rng_) < f_.corrupt) {
      b ^= static_cast<uint8_t>(1u << (rng_() % 8));
      ++corrupted;
    }
    q_.emplace_back(t, b);
  }
}

std::string LineDirection::deliver(double now) {
  std::string out;
  while (!q_.empty() && q_.front().first <= now) {
    if (!down_) {
      out.push_back(static_cast<char>(q_.front().second));
      ++carried;
    } else {
      ++dropped;
    }
    q_.pop_front();
  }
  return out;
}

double LineDirection::next_arrival() const {
  return q_.empty() ? std::numeric_limits<double>::infinity() : q_.front().first;
}

}  // namespace polarcam
