#include "digitizer/speed_profile.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "cam/error.hpp"
#include "cam/format.hpp"

namespace polarcam {
namespace {

// A table's speed is monotone between stations (linear in s or in V^2) and held beyond its ends: its least value
// over [sa, sb] is at one of the ends (speeds va, vb there) or at a station inside.
double least_speed(const std::vector<SpeedStation>& st, double sa, double sb, double va, double vb) {
  double m = std::min(va, vb);
  for (const auto& p : st)
    if (p.s > sa && p.s < sb) m = std::min(m, p.v);
  return m;
}

class Constant final : public SpeedProfile {
 public:
  Constant(double v, double L) : SpeedProfile(L), v_(v) {}
  double time_at(double s) const override { return s / v_; }
  double speed_at(double) const override { return v_; }
  double accel_at(double) const override { return 0.0; }
  double min_speed(double, double) const override { return v_; }

 private:
  double v_;
};

class Trapezoid final : public SpeedProfile {
 public:
  Trapezoid(double v, double a, double L) : SpeedProfile(L), a_(a) {
    sa_ = v * v / (2.0 * a);
    if (2.0 * sa_ > L) {  // triangle
      sa_ = 0.5 * L;
      v = std::sqrt(a * L);
    }
    v_ = v;
    ta_ = v / a;
    tc_ = (L - 2.0 * sa_) / v;
  }
  double time_at(double s) const override {
    const double L = length();
    if (s <= sa_) return std::sqrt(2.0 * std::max(s, 0.0) / a_);
    if (s <= L - sa_) return ta_ + (s - sa_) / v_;
    return 2.0 * ta_ + tc_ - std::sqrt(2.0 * std::max(L - s, 0.0) / a_);
  }
  double speed_at(double s) const override {
    const double L = length();
    if (s <= sa_) return std::sqrt(2.0 * a_ * std::max(s, 0.0));
    if (s <= L - sa_) return v_;
    return std::sqrt(2.0 * a_ * std::max(L - s, 0.0));
  }
  double accel_at(double s) const override {
    const double L = length();
    if (s < sa_) return a_;
    return s < L - sa_ ? 0.0 : -a_;
  }
  // the speed rises, holds and falls: its least value over an interval is at one of the ends
  double min_speed(double sa, double sb) const override { return std::min(speed_at(sa), speed_at(sb)); }
  std::vector<double> kinks() const override {
    const double L = length();
    std::vector<double> k;
    if (sa_ > 0.0 && sa_ < L) k.push_back(sa_);
    if (L - sa_ > sa_ && L - sa_ < L) k.push_back(L - sa_);
    return k;
  }

 private:
  double a_, v_, sa_, ta_, tc_;
};

class Table final : public SpeedProfile {
 public:
  Table(std::vector<SpeedStation> st, double L) : SpeedProfile(L), st_(std::move(st)) {
    cum_.assign(st_.size(), 0.0);
    t0_ = st_.front().s > 0 ? st_.front().s / st_.front().v : 0.0;
    for (size_t i = 1; i < st_.size(); ++i) cum_[i] = cum_[i - 1] + seg_time(i - 1, st_[i].s);
  }
  double time_at(double s) const override {
    if (s <= st_.front().s) return s / st_.front().v;
    if (s >= st_.back().s) return t0_ + cum_.back() + (s - st_.back().s) / st_.back().v;
    size_t i = seg(s);
    return t0_ + cum_[i] + seg_time(i, s);
  }
  double speed_at(double s) const override {
    if (s <= st_.front().s) return st_.front().v;
    if (s >= st_.back().s) return st_.back().v;
    size_t i = seg(s);
    double f = (s - st_[i].s) / (st_[i + 1].s - st_[i].s);
    return st_[i].v + f * (st_[i + 1].v - st_[i].v);
  }
  double accel_at(double s) const override {
    if (s < st_.front().s || s >= st_.back().s) return 0.0;
    size_t i = seg(s);
    return speed_at(s) * (st_[i + 1].v - st_[i].v) / (st_[i + 1].s - st_[i].s);
  }
  double min_speed(double sa, double sb) const override { return least_speed(st_, sa, sb, speed_at(sa), speed_at(sb)); }
  std::vector<double> kinks() const override {
    std::vector<double> k;
    for (const auto& p : st_)
      if (p.s > 0.0 && p.s < length()) k.push_back(p.s);
    return k;
  }

 private:
  size_t seg(double s) const {
    auto it = std::upper_bound(st_.begin(), st_.end(), s, [](double v, const SpeedStation& p) { return v < p.s; });
    return std::min(static_cast<size_t>(it - st_.begin()) - 1, st_.size() - 2);
  }
  // time from station i to s inside segment i
  double seg_time(size_t i, double s) const {
    double ds = s - st_[i].s, h = st_[i + 1].s - st_[i].s;
    double k = (st_[i + 1].v - st_[i].v) / h, v0 = st_[i].v;
    double x = k * ds / v0;
    if (std::abs(x) < 1e-8) return ds / v0 * (1.0 - 0.5 * x + x * x / 3.0);
    return std::log1p(x) / k;
  }
  std::vector<SpeedStation> st_;
  std::vector<double> cum_;
  double t0_ = 0.0;
};

// V^2 linear in s between stations: constant acceleration on each interval.
class SquaredTable final : public SpeedProfile {
 public:
  SquaredTable(std::vector<SpeedStation> st, double L) : SpeedProfile(L), st_(std::move(st)) {
    cum_.assign(st_.size(), 0.0);
    for (size_t i = 1; i < st_.size(); ++i)
      cum_[i] = cum_[i - 1] + 2.0 * (st_[i].s - st_[i - 1].s) / (st_[i].v + st_[i - 1].v);
  }
  double time_at(double s) const override {
    if (s <= st_.front().s) return 0.0;
    if (s >= st_.back().s) return cum_.back();
    const size_t i = seg(s);
    const double ds = s - st_[i].s;
    if (!(ds > 0.0)) return cum_[i];
    return cum_[i] + 2.0 * ds / (st_[i].v + speed_at(s));
  }
  double speed_at(double s) const override {
    if (s <= st_.front().s) return st_.front().v;
    if (s >= st_.back().s) return st_.back().v;
    const size_t i = seg(s);
    const double x0 = st_[i].v * st_[i].v, x1 = st_[i + 1].v * st_[i + 1].v;
    const double f = (s - st_[i].s) / (st_[i + 1].s - st_[i].s);
    return std::sqrt(std::max(0.0, x0 + f * (x1 - x0)));
  }
  double accel_at(double s) const override {
    if (s < st_.front().s || s >= st_.back().s) return 0.0;
    const size_t i = seg(s);
    return (st_[i + 1].v * st_[i + 1].v - st_[i].v * st_[i].v) / (2.0 * (st_[i + 1].s - st_[i].s));
  }
  double min_speed(double sa, double sb) const override { return least_speed(st_, sa, sb, speed_at(sa), speed_at(sb)); }
  std::vector<double> kinks() const override {
    std::vector<double> k;
    for (const auto& p : st_)
      if (p.s > 0.0 && p.s < length()) k.push_back(p.s);
    return k;
  }

 private:
  size_t seg(double s) const {
    auto it = std::upper_bound(st_.begin(), st_.end(), s, [](double v, const SpeedStation& p) { return v < p.s; });
    return std::min(static_cast<size_t>(it - st_.begin()) - 1, st_.size() - 2);
  }
  std::vector<SpeedStation> st_;
  std::vector<double> cum_;
};

void check_speed(double v, const char* what) {
  if (!(v > 0.0) || !std::isfinite(v)) throw InputError(std::string(what) + " must be a positive speed");
}

// x rounded up to 3 significant digits, so that a suggested bound is on the right side of it
std::string round_up3(double x) {
  if (!(x > 0) || !std::isfinite(x)) return significant(x, 3);
  const double e = std::pow(10.0, std::floor(std::log10(x)) - 2);
  return significant(std::ceil(x / e * (1 - 1e-12)) * e, 3);
}

// A tape times steps in whole nanoseconds in 64-bit integers; a path whose duration exceeds 2^62 ns (about 146
// years) cannot be timed (every later sum or difference of ticks could overflow). `slowest` is the profile's
// lowest speed: scaling every speed by T / T_max brings the duration within the bound.
SpeedProfilePtr checked(SpeedProfilePtr p, double slowest) {
  const double T = p->total_time();
  if (!(T * 1e9 <= kMaxDurationNs))
    throw InputError("the path of " + significant(p->length()) + " m takes " + significant(T, 3) +
                     " s at this speed, longer than a tape can time (2^62 ns, about 146 years): the lowest speed that "
                     "fits is " + round_up3(slowest * T / (kMaxDurationNs * 1e-9)) + " m/s");
  return p;
}

}  // namespace

SpeedProfilePtr make_constant_speed(double v, double length) {
  check_speed(v, "the speed");
  return checked(std::make_shared<Constant>(v, length), v);
}

SpeedProfilePtr make_trapezoid_speed(double v, double accel, double length) {
  check_speed(v, "the speed");
  if (!(accel > 0.0) || !std::isfinite(accel)) throw InputError("the acceleration limit must be positive");
  return checked(std::make_shared<Trapezoid>(v, accel, length), v);
}

SpeedProfilePtr make_table_speed(std::vector<SpeedStation> st, double length) {
  if (st.empty()) throw InputError("the speed table is empty");
  for (size_t i = 0; i < st.size(); ++i) {
    if (!std::isfinite(st[i].s) || st[i].s < 0.0)
      throw InputError("speed table row " + std::to_string(i + 1) + ": the arc length must be zero or positive");
    check_speed(st[i].v, ("speed table row " + std::to_string(i + 1) + ": the speed").c_str());
    if (i > 0 && !(st[i].s > st[i - 1].s))
      throw InputError("speed table row " + std::to_string(i + 1) + ": arc lengths must increase");
  }
  if (st.size() == 1) return make_constant_speed(st[0].v, length);
  double slowest = st[0].v;
  for (const auto& x : st) slowest = std::min(slowest, x.v);
  return checked(std::make_shared<Table>(std::move(st), length), slowest);
}

}  // namespace polarcam

namespace polarcam {

SpeedProfilePtr make_table_speed_sq(std::vector<SpeedStation> st, double length) {
  if (st.size() < 2) throw InputError("a squared-speed table needs at least two stations");
  if (!(std::abs(st.front().s) == 0.0) || !(st.back().s == length))
    throw InputError("a squared-speed table must run from arc length 0 to the path's length");
  for (size_t i = 0; i < st.size(); ++i) {
    const std::string row = "squared-speed table station " + std::to_string(i + 1);
    if (!std::isfinite(st[i].s)) throw InputError(row + ": the arc length is not finite");
    if (!(st[i].v >= 0.0) || !std::isfinite(st[i].v)) throw InputError(row + ": the speed must be zero or positive");
    if (i > 0 && !(st[i].s > st[i - 1].s)) throw InputError(row + ": arc lengths must increase");
    if (i > 0 && !(st[i].v + st[i - 1].v > 0.0)) throw InputError(row + ": two neighbouring stations at rest");
  }
  double slowest = 0.0;
  for (size_t i = 1; i < st.size(); ++i) {
    const double m = 0.5 * (st[i].v + st[i - 1].v);
    if (slowest == 0.0 || m < slowest) slowest = m;
  }
  return checked(std::make_shared<SquaredTable>(std::move(st), length), slowest);
}

}  // namespace polarcam
