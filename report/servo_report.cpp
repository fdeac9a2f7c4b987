#include "report/servo_report.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "cam/format.hpp"
#include "io/output.hpp"

namespace polarcam {
namespace {


bool rotary(const ServoAnalysis& a, int i) { return a.drives.axis[i].rotary; }

nlohmann::ordered_json axis_json(const ServoAnalysis& a, int i) {
  const servo::SteadyError& s = a.result.steady[i];
  nlohmann::ordered_json j;
  j["axis"] = a.drives.axis[i].name;
  const double unit = rotary(a, i) ? 1.0 : 1e3;  // rad, or mm
  const std::string u = rotary(a, i) ? "_rad" : "_mm";
  if (s.found) {
    j["following_error" + u] = s.error * unit;
    j["following_error_counts"] = s.error_counts;
    j["speed" + u + "_per_s"] = s.speed * unit;
    j["steady_from_s"] = s.t_begin;
    j["steady_to_s"] = s.t_end;
  } else {
    j["following_error" + u] = nullptr;  // no stretch at steady speed long enough to settle
  }
  j["max_current_A"] = a.result.max_current[i];
  if (a.drives.axis[i].peak_current > 0.0) {
    j["peak_current_A"] = a.drives.axis[i].peak_current;
    j["within_peak_current"] = a.result.max_current[i] <= a.drives.axis[i].peak_current;
  }
  return j;
}

}  // namespace

nlohmann::ordered_json servo_json(const ServoAnalysis& a) {
  const servo::ContourResult& c = a.result;
  nlohmann::ordered_json j;
  j["input"] = a.input;
  j["drives"] = a.drives_file;
  j["machine"] = a.drives.polar ? "polar" : "cartesian";
  j["sample_period_s"] = c.T;
  j["duration_s"] = c.t.empty() ? 0.0 : c.t.back();
  j["path_length_mm"] = c.s.empty() ? 0.0 : c.s.back() * 1e3;
  j["path_is_staircase"] = a.staircase;
  j["axes"] = nlohmann::ordered_json::array({axis_json(a, 0), axis_json(a, 1)});
  j["max_contour_error_mm"] = c.max_abs_contour_error * 1e3;
  j["max_contour_error_at"] = {{"t_s", c.max_at_t}, {"s_mm", c.max_at_s * 1e3}, {"x_mm", c.max_at_x * 1e3},
                               {"y_mm", c.max_at_y * 1e3}};
  if (c.steady_contour_found)
    j["steady_contour_error_mm"] = c.steady_contour_error * 1e3;
  else
    j["steady_contour_error_mm"] = nullptr;
  j["tolerance_mm"] = c.tolerance * 1e3;
  j["within_tolerance"] = c.within_tolerance();
  nlohmann::ordered_json iv = nlohmann::ordered_json::array();
  for (const servo::Interval& i : c.out_of_tolerance)
    iv.push_back({{"t_begin_s", i.t_begin}, {"t_end_s", i.t_end}, {"s_begin_mm", i.s_begin * 1e3},
                  {"s_end_mm", i.s_end * 1e3}, {"max_contour_error_mm", i.max_abs_error * 1e3}});
  j["out_of_tolerance"] = iv;
  if (!a.corners.empty()) {
    nlohmann::ordered_json cs = nlohmann::ordered_json::array();
    for (const servo::CornerSpline& k : a.corners) {
      nlohmann::ordered_json segs = nlohmann::ordered_json::array();
      for (const servo::SplineSegment& g : k.segments) {
        nlohmann::ordered_json A = nlohmann::ordered_json::array();
        for (const auto& row : g.A) A.push_back({row[0] * 1e3, row[1] * 1e3, row[2] * 1e3, row[3] * 1e3});
        segs.push_back({{"dt_s", g.dt}, {"A_mm", A}});
      }
      cs.push_back({{"corner_mm", {k.corner[0] * 1e3, k.corner[1] * 1e3}}, {"segments", segs}});
    }
    j["corner_splines"] = cs;  // A* of Eq. 4.132: rows x, y; columns s^3, s^2, s, 1
  }
  return j;
}

std::string servo_text(const ServoAnalysis& a) {
  const servo::ContourResult& c = a.result;
  std::ostringstream o;
  o << "servo feed drives (" << (a.drives.polar ? "polar" : "Cartesian") << "), " << a.input << ", drives "
    << a.drives_file << "\n";
  o << "  " << significant(c.t.empty() ? 0.0 : c.t.back(), 6) << " s, path " << significant(c.s.empty() ? 0.0 : c.s.back() * 1e3, 6)
    << " mm" << (a.staircase ? " along the staircase of steps (longer than the contour)" : "") << ", sampled every "
    << significant(c.T * 1e3, 6) << " ms\n";
  for (int i = 0; i < 2; ++i) {
    const servo::SteadyError& s = c.steady[i];
    const bool rot = rotary(a, i);
    o << "  axis " << a.drives.axis[i].name << ": following error ";
    if (s.found)
      o << significant(s.error * (rot ? 1.0 : 1e3), 5) << (rot ? " rad" : " mm") << " ("
        << significant(s.error_counts, 5) << " counts) at " << significant(s.speed * (rot ? 1.0 : 1e3), 5)
        << (rot ? " rad/s" : " mm/s");
    else
      o << "- (never at a steady speed long enough to settle)";
    o << ", largest current " << significant(c.max_current[i], 4) << " A";
    if (a.drives.axis[i].peak_current > 0.0 && c.max_current[i] > a.drives.axis[i].peak_current)
      o << " (above the amplifier's peak " << significant(a.drives.axis[i].peak_current, 4)
        << " A, which the linear model does not clip)";
    o << "\n";
  }
  o << "  largest contour error " << significant(c.max_abs_contour_error * 1e3, 5) << " mm at t = "
    << significant(c.max_at_t, 6) << " s, s = " << significant(c.max_at_s * 1e3, 6) << " mm\n";
  if (c.steady_contour_found)
    o << "  contour error at steady speed " << significant(c.steady_contour_error * 1e3, 5) << " mm\n";
  o << "  tolerance " << significant(c.tolerance * 1e3, 4) << " mm: ";
  if (c.within_tolerance()) {
    o << "within it (GO)\n";
  } else {
    o << "left " << c.out_of_tolerance.size() << " time" << (c.out_of_tolerance.size() == 1 ? "" : "s") << " (NO-GO)\n";
    size_t shown = 0;
    for (const servo::Interval& i : c.out_of_tolerance) {
      if (++shown > 20) {
        o << "    ... " << c.out_of_tolerance.size() - 20 << " more (--json lists them all)\n";
        break;
      }
      o << "    t " << significant(i.t_begin, 6) << " to " << significant(i.t_end, 6) << " s, s "
        << significant(i.s_begin * 1e3, 6) << " to " << significant(i.s_end * 1e3, 6) << " mm, up to "
        << significant(i.max_abs_error * 1e3, 4) << " mm\n";
    }
  }
  return o.str();
}

std::string servo_csv(const ServoAnalysis& a) {
  const servo::ContourResult& c = a.result;
  std::ostringstream o;
  o.precision(10);
  auto col = [&](int i) { return a.drives.axis[i].name + (rotary(a, i) ? "_rad" : "_mm"); };
  o << "t_s,ref_" << col(0) << ",ref_" << col(1) << ",act_" << col(0) << ",act_" << col(1) << ",contour_error_mm\n";
  const double u0 = rotary(a, 0) ? 1.0 : 1e3, u1 = rotary(a, 1) ? 1.0 : 1e3;
  for (size_t k = 0; k < c.t.size(); ++k)
    o << c.t[k] << "," << c.ref[0][k] * u0 << "," << c.ref[1][k] * u1 << "," << c.act[0][k] * u0 << ","
      << c.act[1][k] * u1 << "," << c.e_c[k] * 1e3 << "\n";
  return o.str();
}

plot::Figure servo_figure(const ServoAnalysis& a) {
  const servo::ContourResult& c = a.result;
  plot::Figure fig = plot::figure(1400, 650);
  fig.cols = 2;
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (size_t k = 0; k < c.t.size(); ++k) {
    xmin = std::min(xmin, c.ref_xy[0][k]);
    xmax = std::max(xmax, c.ref_xy[0][k]);
    ymin = std::min(ymin, c.ref_xy[1][k]);
    ymax = std::max(ymax, c.ref_xy[1][k]);
  }
  const double size = std::max(xmax - xmin, ymax - ymin);
  const double gain = c.max_abs_contour_error > 0.0 ? std::max(1.0, size / 20.0 / c.max_abs_contour_error) : 1.0;
  plot::Panel p = plot::panel("tool path: reference and actual (deviation x" + significant(gain, 3) + ")", "x (mm)",
                              "y (mm)", true);
  plot::Series ref, act;
  ref.label = "reference";
  act.label = "actual";
  act.color = plot::palette(5);
  const size_t stride = std::max<size_t>(1, c.t.size() / 20000);
  for (size_t k = 0; k < c.t.size(); k += stride) {
    ref.x.push_back(c.ref_xy[0][k] * 1e3);
    ref.y.push_back(c.ref_xy[1][k] * 1e3);
    act.x.push_back((c.ref_xy[0][k] + gain * (c.act_xy[0][k] - c.ref_xy[0][k])) * 1e3);
    act.y.push_back((c.ref_xy[1][k] + gain * (c.act_xy[1][k] - c.ref_xy[1][k])) * 1e3);
  }
  p.series.push_back(std::move(ref));
  p.series.push_back(std::move(act));
  fig.panels.push_back(std::move(p));
  plot::Panel e = plot::panel("contour error (+ right of the motion)", "t (s)", "e_c (mm)");
  plot::Series s;
  s.label = "contour error";
  for (size_t k = 0; k < c.t.size(); k += stride) {
    s.x.push_back(c.t[k]);
    s.y.push_back(c.e_c[k] * 1e3);
  }
  e.series.push_back(std::move(s));
  e.hlines = {c.tolerance * 1e3, -c.tolerance * 1e3};
  fig.panels.push_back(std::move(e));
  return fig;
}

nlohmann::ordered_json servo_model_json(const servo::Drives& d, const servo::ModelReport r[2]) {
  nlohmann::ordered_json axes = nlohmann::ordered_json::array();
  for (int i = 0; i < 2; ++i) {
    const servo::ModelReport& m = r[i];
    nlohmann::ordered_json j;
    j["axis"] = d.axis[i].name;
    j["K1"] = m.velocity.K1;
    j["K2"] = m.velocity.K2;
    j["K3"] = m.velocity.K3;
    j["omega_n_rad_per_s"] = m.omega_n;
    j["zeta"] = m.zeta;
    j["K_p_prime"] = m.K_p_prime;
    j["a_prime_per_s"] = m.a_prime;
    j["b_prime_per_s"] = m.b_prime;
    j["G"] = m.model.G;
    j["Gamma"] = m.model.Gamma;
    j["spectral_radius"] = m.model.spectral_radius;
    j["settling_time_s"] = m.model.settling_time;
    j["following_error_s"] = m.following_error_per_speed;  // error per speed: counts per count/s, mm per mm/s
    j["counts_per_Nm"] = m.counts_per_Nm;
    const double per = d.axis[i].per_count();
    if (d.axis[i].rotary)
      j["rad_per_Nm"] = m.counts_per_Nm * per;
    else
      j["mm_per_Nm"] = m.counts_per_Nm * per * 1e3;
    j["current_sensor_bandwidth_Hz"] = m.current_bandwidth_Hz;
    j["current_sensor_bandwidth_sampled_Hz"] = m.current_bandwidth_discrete_Hz;
    axes.push_back(j);
  }
  nlohmann::ordered_json j;
  j["machine"] = d.polar ? "polar" : "cartesian";
  j["axes"] = axes;
  return j;
}

std::string servo_model_text(const servo::Drives& d, const servo::ModelReport r[2]) {
  std::ostringstream o;
  for (int i = 0; i < 2; ++i) {
    const servo::ModelReport& m = r[i];
    o << "axis " << d.axis[i].name << "\n";
    o << "  velocity loop K1 " << significant(m.velocity.K1, 6) << ", K2 " << significant(m.velocity.K2, 6) << ", K3 "
      << significant(m.velocity.K3, 6) << " (omega_n " << significant(m.omega_n, 5) << " rad/s, zeta "
      << significant(m.zeta, 4) << ")\n";
    o << "  filter's continuous equivalent K_p' " << significant(m.K_p_prime, 6) << ", a' " << significant(m.a_prime, 6)
      << " 1/s, b' " << significant(m.b_prime, 6) << " 1/s\n";
    o << "  G (rows):";
    for (const auto& row : m.model.G) {
      o << " [";
      for (size_t k = 0; k < row.size(); ++k) o << (k ? " " : "") << significant(row[k], 5);
      o << "]";
    }
    o << "\n  largest |pole| " << significant(m.model.spectral_radius, 6) << ", settles in "
      << significant(m.model.settling_time, 4) << " s\n";
    o << "  following error " << significant(m.following_error_per_speed, 6) << " s of lag (mm per mm/s of feed)\n";
    o << "  yield under cutting torque " << significant(m.counts_per_Nm, 6) << " counts/N m\n";
    o << "  current sensor bandwidth " << significant(m.current_bandwidth_Hz, 5) << " Hz (continuous, Eq. 3.64), "
      << significant(m.current_bandwidth_discrete_Hz, 5) << " Hz (sampled)\n";
  }
  return o.str();
}

}  // namespace polarcam
