#include "process/identify.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <sstream>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "cam/input_file.hpp"

namespace polarcam::process {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream ss(line);
  while (std::getline(ss, cell, ',')) {
    while (!cell.empty() && (cell.back() == ' ' || cell.back() == '\r' || cell.back() == '\t')) cell.pop_back();
    size_t b = 0;
    while (b < cell.size() && (cell[b] == ' ' || cell[b] == '\t')) ++b;
    out.push_back(cell.substr(b));
  }
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

double rms(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return v.empty() ? 0.0 : std::sqrt(s / static_cast<double>(v.size()));
}

void check_series(const std::vector<double>& m, const std::vector<double>& c) {
  if (m.size() != c.size()) throw InputError("force and displacement differ in length", "identify");
  if (c.size() < 8) throw InputError("needs at least 8 samples of force and displacement", "identify");
  if (!(rms(m) > 0.0) || !(rms(c) > 0.0))
    throw InputError("needs a force and a displacement that are not zero throughout", "identify");
}

}  // namespace

Response parse_response_csv(const std::string& text, const std::string& name) {
  std::istringstream in(text);
  std::string line;
  int lineno = 0;
  int it = -1, ix = -1, iF = -1;
  size_t columns = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty() || line[0] == '#') continue;
    const auto head = split(line);
    columns = head.size();
    for (size_t i = 0; i < head.size(); ++i) {
      if (head[i] == "t_s") it = static_cast<int>(i);
      if (head[i] == "displacement_m") ix = static_cast<int>(i);
      if (head[i] == "force_N") iF = static_cast<int>(i);
    }
    break;
  }
  const std::string hl = name + ":" + std::to_string(lineno);
  if (it < 0 || ix < 0)
    throw InputError("the header must name the columns t_s and displacement_m (and force_N when recorded)", hl);
  Response r;
  std::vector<double> t;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty() || line == "\r" || line[0] == '#') continue;
    const auto cells = split(line);
    const std::string at = name + ":" + std::to_string(lineno);
    if (cells.size() != columns)
      throw InputError("has " + std::to_string(cells.size()) + " fields, the header " + std::to_string(columns), at);
    auto num = [&](int i, const char* col) {
      const std::string& s = cells[static_cast<size_t>(i)];
      char* end = nullptr;
      const double v = std::strtod(s.c_str(), &end);
      if (s.empty() || *end != '\0' || !std::isfinite(v))
        throw InputError(std::string("column ") + col + ": '" + s + "' is not a finite number", at);
      return v;
    };
    t.push_back(num(it, "t_s"));
    r.displacement.push_back(num(ix, "displacement_m"));
    if (iF >= 0) r.force.push_back(num(iF, "force_N"));
    if (t.size() >= 2) {
      const double dt = t[t.size() - 1] - t[t.size() - 2];
      if (t.size() == 2) {
        if (!(dt > 0.0)) throw InputError("t_s must increase", at);
        r.period = dt;
      } else if (!(std::abs(dt - r.period) <= 1e-6 * r.period + 1e-9 * std::abs(t.back()))) {
        throw InputError("t_s must be evenly spaced (" + std::to_string(r.period) + " s before, " + std::to_string(dt) +
                             " s here)",
                         at);
      }
    }
    if (t.size() > 50000000) throw InputError("more than 50 million samples", at);
  }
  if (t.size() < 8) throw InputError("needs at least 8 samples", name);
  // the period from the whole record (fewer rounding errors than one difference)
  r.period = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  return r;
}

Response read_response_csv(const std::string& path) {
  return parse_response_csv(read_input_file(path), path);
}

std::optional<Decrement> log_decrement(const std::vector<double>& x, double period, double floor) {
  // one peak between successive upward zero crossings
  std::vector<double> pt, pv;
  size_t start = 0;
  bool armed = false;
  for (size_t i = 1; i < x.size(); ++i) {
    if (x[i - 1] < 0.0 && x[i] >= 0.0) {
      if (armed) {
        size_t k = start;
        for (size_t j = start; j < i; ++j)
          if (x[j] > x[k]) k = j;
        double tk = static_cast<double>(k), vk = x[k];
        if (k > 0 && k + 1 < x.size()) {  // parabola through the peak and its neighbours
          const double a = x[k - 1], b = x[k], c = x[k + 1], den = a - 2.0 * b + c;
          if (den < 0.0) {
            const double d = 0.5 * (a - c) / den;
            tk += d;
            vk = b - 0.25 * (a - c) * d;
          }
        }
        if (vk > 0.0) {
          pt.push_back(tk * period);
          pv.push_back(vk);
        }
      }
      armed = true;
      start = i;
    }
  }
  // down to floor times the first peak
  size_t n = 0;
  while (n < pv.size() && pv[n] >= floor * pv.front()) ++n;
  if (n < 3) return std::nullopt;
  // least-squares line through (i, ln peak_i) and (i, t_i)
  double si = 0, sl = 0, st = 0, sii = 0, sil = 0, sit = 0;
  for (size_t i = 0; i < n; ++i) {
    const double fi = static_cast<double>(i), l = std::log(pv[i]);
    si += fi;
    sl += l;
    st += pt[i];
    sii += fi * fi;
    sil += fi * l;
    sit += fi * pt[i];
  }
  const double N = static_cast<double>(n), d = N * sii - si * si;
  Decrement r;
  r.delta = -(N * sil - si * sl) / d;
  const double Td = (N * sit - si * st) / d;
  r.zeta = r.delta / std::sqrt(4.0 * std::numbers::pi * std::numbers::pi + r.delta * r.delta);
  r.omega_d = 2.0 * std::numbers::pi / Td;
  r.omega_n = r.omega_d / std::sqrt(1.0 - r.zeta * r.zeta);
  r.peaks = static_cast<int>(n);
  return r;
}

DiscreteModel batch_least_squares(const std::vector<double>& m, const std::vector<double>& c) {
  check_series(m, c);
  const double sm = rms(m), sc = rms(c);
  const Eigen::Index n = static_cast<Eigen::Index>(c.size()) - 2;
  Eigen::MatrixXd X(n, 4);
  Eigen::VectorXd y(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const size_t i = static_cast<size_t>(k) + 2;
    X(k, 0) = m[i - 1] / sm;
    X(k, 1) = m[i - 2] / sm;
    X(k, 2) = -c[i - 1] / sc;
    X(k, 3) = -c[i - 2] / sc;
    y(k) = c[i] / sc;
  }
  const Eigen::VectorXd th = X.colPivHouseholderQr().solve(y);
  return {th(0) * sc / sm, th(1) * sc / sm, th(2), th(3)};
}

DiscreteModel recursive_least_squares(const std::vector<double>& m, const std::vector<double>& c, const RlsOptions& o) {
  check_series(m, c);
  if (!(o.forgetting > 0.0 && o.forgetting <= 1.0)) throw InputError("must be in (0, 1]", "forgetting factor");
  if (!(o.initial_covariance > 0.0 && std::isfinite(o.initial_covariance)))
    throw InputError("must be positive", "initial covariance");
  const double sm = rms(m), sc = rms(c);
  Eigen::Vector4d th = Eigen::Vector4d::Zero();
  Eigen::Matrix4d P = Eigen::Matrix4d::Identity() * o.initial_covariance;
  for (size_t i = 2; i < c.size(); ++i) {
    const Eigen::Vector4d phi(m[i - 1] / sm, m[i - 2] / sm, -c[i - 1] / sc, -c[i - 2] / sc);
    const Eigen::Vector4d Pphi = P * phi;
    const double denom = o.forgetting + phi.dot(Pphi);
    const Eigen::Vector4d gain = Pphi / denom;
    th += gain * (c[i] / sc - phi.dot(th));
    P = (P - gain * Pphi.transpose()) / o.forgetting;
    P = 0.5 * (P + P.transpose());  // kept symmetric against rounding
    // a forgetting factor well below 1 inflates P by 1 / lambda a sample wherever the record holds little new
    // information: refused by name rather than returned as NaN
    if (!th.allFinite() || !P.allFinite())
      throw InputError("the recursive estimate diverged at sample " + std::to_string(i + 1) + " of " +
                           std::to_string(c.size()) + " with forgetting factor " + significant(o.forgetting, 6) +
                           ": use a factor nearer 1 (0.95 to 1 suits most records)",
                       "forgetting factor");
  }
  return {th(0) * sc / sm, th(1) * sc / sm, th(2), th(3)};
}

SecondOrder to_second_order(const DiscreteModel& d, double T) {
  if (!(d.B2 > 0.0 && d.B2 < 1.0))
    throw InputError("the identified model is not a damped oscillation (B2 = " + significant(d.B2, 6) +
                         ", needs 0 < B2 < 1): the record may hold no vibration, or too much noise",
                     "identify");
  const double sigma = std::log(1.0 / d.B2) / (2.0 * T);         // Eq. 4.8: w_n zeta
  const double arg = -d.B1 * std::exp(sigma * T) / 2.0;
  if (!(arg > -1.0 && arg < 1.0))
    throw InputError("the identified model is not an underdamped oscillation (B1 = " + significant(d.B1, 6) + ")",
                     "identify");
  const double wd = std::acos(arg) / T;                           // Eq. 4.9: w_n sqrt(1 - zeta^2)
  SecondOrder s;
  s.omega_n = std::hypot(sigma, wd);
  s.zeta = sigma / s.omega_n;
  s.gain = (d.A1 + d.A2) / (1.0 + d.B1 + d.B2);
  return s;
}

}  // namespace polarcam::process
