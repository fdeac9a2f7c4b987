#include "process/milling_path.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include "cam/error.hpp"

namespace polarcam::process {

namespace {

// Whether the path's centre of curvature lies on the material's side: the contour is convex towards the tool.
bool convex(double kappa_c, bool material_left) { return (kappa_c > 0.0) == material_left; }
}  // namespace

double engaged_angle(double R, double a, double kappa_c, bool material_left) {
  if (!(a > 0.0)) return 0.0;
  if (!std::isfinite(kappa_c) || std::abs(kappa_c) * R < 1e-12) return straight_engaged_angle(a, R);
  const double rc = 1.0 / std::abs(kappa_c);
  double c;
  if (convex(kappa_c, material_left)) {
    const double rho = std::max(0.0, rc - R);
    c = (rc * rc + R * R - (rho + a) * (rho + a)) / (2.0 * rc * R);
  } else {
    const double rho = rc + R;
    if (a >= rho) return std::numbers::pi;
    c = ((rho - a) * (rho - a) - rc * rc - R * R) / (2.0 * rc * R);
  }
  return std::acos(std::clamp(c, -1.0, 1.0));
}

double edge_feed_scale(double R, double a, double kappa_c, bool material_left) {
  if (!std::isfinite(kappa_c) || std::abs(kappa_c) * R < 1e-12) return 1.0;
  const double rc = 1.0 / std::abs(kappa_c);
  if (convex(kappa_c, material_left)) return (std::max(0.0, rc - R) + 0.5 * a) / rc;
  return std::max(0.0, rc + R - 0.5 * a) / rc;
}

MillingMode milling_mode(bool material_left, bool clockwise) {
  return material_left == clockwise ? MillingMode::up : MillingMode::down;
}

void check_milling_path_spec(const MillingPathSpec& s) {
  check_slice_cutter(s.cutter);
  if (!(s.radial_width_m > 0.0) || !std::isfinite(s.radial_width_m))
    throw InputError("must be a positive length", "radial_width");
  if (s.radial_width_m > 2.0 * s.cutter.radius_m)
    throw InputError("is wider than the cutter's diameter: at most the diameter (a slot)", "radial_width");
  if (!(s.spindle_speed_rad_s > 0.0) || !std::isfinite(s.spindle_speed_rad_s))
    throw InputError("must be a positive speed", "spindle_speed");
  if (s.tool_side != 1 && s.tool_side != -1) throw InputError("must be +1 or -1", "tool_side");
  if (s.stations < 2 || s.stations > 1000000) throw InputError("must be from 2 to 1000000", "stations");
}

MillingPath::MillingPath(const Curve& path, const MillingPathSpec& spec) : spec_(spec) {
  check_milling_path_spec(spec);
  const bool material_left = spec.tool_side < 0;
  mode_ = milling_mode(material_left, spec.clockwise);
  const double R = spec.cutter.radius_m, a = spec.radial_width_m;

  std::vector<double> knots{path.u_begin()};
  for (double b : path.breakpoints()) knots.push_back(b);
  knots.push_back(path.u_end());
  std::vector<double> lengths;
  for (size_t i = 0; i + 1 < knots.size(); ++i) {
    lengths.push_back(arc_length(path, knots[i], knots[i + 1]));
    length_ += lengths.back();
  }
  if (!(length_ > 0.0)) throw InputError("the tool path has no length", "path");

  std::map<std::pair<double, double>, std::pair<CutterForce, ForcePeaks>> cache;
  double s0 = 0.0;
  for (size_t p = 0; p + 1 < knots.size(); ++p) {
    const double ua = knots[p], ub = knots[p + 1];
    const int m = std::max(2, static_cast<int>(std::ceil(spec.stations * lengths[p] / length_)));
    const double nudge = 1e-9 * (ub - ua);  // the ends of a piece are evaluated just inside it
    double s = s0, u_prev = ua;
    for (int k = 0; k <= m; ++k) {
      const double u = k == m ? ub : ua + (ub - ua) * k / m;
      if (k > 0) s += arc_length(path, u_prev, u);
      u_prev = u;
      const double ue = std::clamp(u, ua + nudge, ub - nudge);
      MillingStation st;
      st.s = k == m ? s0 + lengths[p] : s;
      st.u = u;
      st.curvature = curvature(path.eval(ue, 2));
      st.engaged_angle = engaged_angle(R, a, st.curvature, material_left);
      st.feed_scale = edge_feed_scale(R, a, st.curvature, material_left);
      st.immersion = immersion_for(mode_, st.engaged_angle);
      auto key = std::make_pair(st.immersion.entry, st.immersion.exit);
      auto it = cache.find(key);
      if (it == cache.end())
        it = cache.emplace(key, std::make_pair(mean_force(spec.cutter, st.immersion, 1.0),
                                               force_peaks(spec.cutter, st.immersion, 1.0)))
                 .first;
      const double f = st.feed_scale;
      const CutterForce& mu = it->second.first;
      const ForcePeaks& pk = it->second.second;
      st.mean = {mu.x * f, mu.y * f, mu.z * f};
      st.peaks = {pk.resultant * f, pk.tooth * f, pk.normal * f, pk.axial * f};
      stations_.push_back(st);
    }
    s0 += lengths[p];
  }
}

double MillingPath::feed_per_tooth(double V) const {
  return V * 2.0 * std::numbers::pi / (spec_.cutter.teeth * spec_.spindle_speed_rad_s);
}

double MillingPath::speed_for_feed_per_tooth(double f_t) const {
  return f_t * spec_.cutter.teeth * spec_.spindle_speed_rad_s / (2.0 * std::numbers::pi);
}

MillingForceAt MillingPath::from(const CutterForce& mean, const ForcePeaks& peaks, double engaged, double V) const {
  MillingForceAt r;
  r.feed_per_tooth_m = feed_per_tooth(V);
  const double f = r.feed_per_tooth_m;
  r.engaged_angle_rad = engaged;
  r.feed_force_N = -mean.x * f;
  // the material is on +y (up milling) or -y (down milling) of milling_force.hpp's frame
  r.normal_force_N = (mode_ == MillingMode::up ? -mean.y : mean.y) * f;
  r.axial_force_N = mean.z * f;
  r.mean_resultant_N = std::hypot(mean.x, mean.y) * f;
  r.peak_resultant_N = peaks.resultant * f;
  r.peak_tooth_N = peaks.tooth * f;
  r.peak_normal_N = peaks.normal * f;
  return r;
}

MillingForceAt MillingPath::at_station(size_t i, double V) const {
  const MillingStation& st = stations_.at(i);
  return from(st.mean, st.peaks, st.engaged_angle, V);
}

MillingForceAt MillingPath::at(double s, double V) const {
  if (s <= stations_.front().s) return at_station(0, V);
  if (s >= stations_.back().s) return at_station(stations_.size() - 1, V);
  // the first station beyond s; its predecessor is at or before s
  const auto it = std::upper_bound(stations_.begin(), stations_.end(), s,
                                   [](double x, const MillingStation& st) { return x < st.s; });
  const MillingStation& b = *it;
  const MillingStation& a = *(it - 1);
  const double h = b.s - a.s;
  const double w = h > 0.0 ? (s - a.s) / h : 1.0;
  auto lerp = [w](double x, double y) { return x + w * (y - x); };
  const CutterForce mean{lerp(a.mean.x, b.mean.x), lerp(a.mean.y, b.mean.y), lerp(a.mean.z, b.mean.z)};
  const ForcePeaks peaks{lerp(a.peaks.resultant, b.peaks.resultant), lerp(a.peaks.tooth, b.peaks.tooth),
                         lerp(a.peaks.normal, b.peaks.normal), lerp(a.peaks.axial, b.peaks.axial)};
  return from(mean, peaks, lerp(a.engaged_angle, b.engaged_angle), V);
}

}  // namespace polarcam::process
