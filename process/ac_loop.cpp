#include "process/ac_loop.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "cam/error.hpp"
#include "cam/linalg.hpp"
#include "process/checks.hpp"

namespace polarcam::process {
namespace {

void require(bool ok, const char* message, const char* key) {
  if (!ok) throw InputError(message, key);
}

// The servo's state matrices for a loop gain divided by `div`; `open` true: the drive's speed command held at
// zero (strategy B), the motor coasting down on its own pole p1 + p2.
Discrete servo_matrices(const FeedServo& s, double dt, double div, bool open) {
  const double a = s.pole1 + s.pole2, b = open ? 0.0 : s.pole1 * s.pole2 / div, k = open ? 0.0 : s.gain / div;
  return discretise_zoh({0.0, 1.0, -b, -a}, {0.0, k}, 2, 1, dt);
}

}  // namespace

const char* strategy_name(ImpactStrategy s) {
  switch (s) {
    case ImpactStrategy::none: return "none";
    case ImpactStrategy::A: return "A";
    case ImpactStrategy::B: return "B";
  }
  return "none";
}

Discrete discretise_zoh(const std::vector<double>& A, const std::vector<double>& B, int n, int m, double dt) {
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n + m, n + m);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) M(i, j) = A[static_cast<size_t>(i * n + j)] * dt;
    for (int j = 0; j < m; ++j) M(i, n + j) = B[static_cast<size_t>(i * m + j)] * dt;
  }
  const Eigen::MatrixXd E = linalg::expm(M);
  Discrete d;
  d.n = n;
  d.m = m;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) d.Ad.push_back(E(i, j));
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) d.Bd.push_back(E(i, n + j));
  }
  return d;
}

void check(const AcLoopSettings& s) {
  require(positive(s.servo.gain) && positive(s.servo.pole1) && positive(s.servo.pole2), "must be positive", "servo");
  require(positive(s.dda_rate_hz) && s.dda_rate_hz <= 1e6, "must be a rate above 0 and at most 1 MHz", "dda.rate");
  require(positive(s.blu_m) && s.blu_m < 1e-2, "must be a length above 0 and below 10 mm", "dda.blu");
  const double dt = 1.0 / s.dda_rate_hz;
  const double ticks = s.control_period_s / dt;
  require(positive(s.control_period_s) && std::abs(ticks - std::round(ticks)) < 1e-6 && std::round(ticks) >= 1.0,
          "must be a whole number (1 or more) of DDA interrupt periods", "control.period");
  require(std::isfinite(s.K_ac) && s.K_ac >= 0.0, "must be 0 or more (mm/s^2)", "control.K_ac");
  require(std::isfinite(s.B) && s.B >= 0.0, "must be 0 or more (mm/s)", "control.B");
  require(positive(s.F_nom), "must be a positive force", "control.F_nom");
  require(positive(s.rapid_feed), "must be a positive speed", "control.rapid_feed");
  require(s.rapid_feed <= s.blu_m * s.dda_rate_hz * (1.0 + 1e-12),
          "is faster than the DDA can pulse (one basic length unit per interrupt): lower it or raise dda.rate",
          "control.rapid_feed");
  require(positive(s.impact_threshold), "must be a positive force", "control.impact_threshold");
  require(std::isfinite(s.slow_feed) && s.slow_feed >= 0.0 && s.slow_feed <= s.rapid_feed,
          "must be a speed from 0 to the rapid feed", "control.slow_feed");
  require(std::isfinite(s.slow_time) && s.slow_time >= 0.0, "must be a time of 0 or more", "control.slow_time");
  require(std::isfinite(s.hold_time) && s.hold_time >= 0.0, "must be a time of 0 or more", "control.hold_time");
  require(std::isfinite(s.reduced_gain_time) && s.reduced_gain_time >= 0.0, "must be a time of 0 or more",
          "control.reduced_gain_time");
  require(s.teeth >= 1 && s.teeth <= 100, "must be 1 to 100", "cut.teeth");
  require(positive(s.spindle_speed_rad_s), "must be a positive spindle speed", "cut.spindle_speed");
  require(positive(s.cutting_stiffness), "must be a positive stiffness (N/mm)", "cut.cutting_stiffness");
  if (s.spindle_stiffness) require(positive(*s.spindle_stiffness), "must be a positive stiffness (N/mm)", "cut.spindle_stiffness");
  require(std::isfinite(s.entry_distance) && s.entry_distance >= 0.0 && s.entry_distance < 10.0,
          "must be a length from 0 to 10 m", "cut.entry_distance");
  require(positive(s.duration_s), "must be a positive time", "simulation.duration");
  require(s.duration_s * s.dda_rate_hz <= 5e6, "is too long: at most 5 million DDA interrupts", "simulation.duration");
}

double ac_steady_feed(const AcLoopSettings& s) {
  const double tau = 2.0 * std::numbers::pi / (s.teeth * s.spindle_speed_rad_s);
  return s.F_nom / (s.cutting_stiffness * tau);
}

AcResult simulate_ac_loop(const AcLoopSettings& s) {
  check(s);
  const double dt = 1.0 / s.dda_rate_hz;
  const long n_steps = std::lround(std::floor(s.duration_s * s.dda_rate_hz + 1e-9)) + 1;
  const long ctrl_every = std::lround(s.control_period_s / dt);
  const double Tc = static_cast<double>(ctrl_every) * dt;
  const double tau = 2.0 * std::numbers::pi / (s.teeth * s.spindle_speed_rad_s);
  const double mu = s.spindle_stiffness ? s.cutting_stiffness / *s.spindle_stiffness : 0.0;
  const Discrete normal = servo_matrices(s.servo, dt, 1.0, false);
  const Discrete reduced = servo_matrices(s.servo, dt, 3.0, false);
  const Discrete coast = servo_matrices(s.servo, dt, 1.0, true);

  AcResult r;
  r.tooth_period_s = tau;
  r.series.reserve(static_cast<size_t>(n_steps));
  std::vector<double> tool(static_cast<size_t>(n_steps), 0.0);  // the tool's position against the workpiece
  // the tool's position tau ago, linearly between interrupts; before the start it stood at 0
  auto tool_at = [&](long k) {
    const double tb = static_cast<double>(k) * dt - tau;
    if (tb <= 0.0) return 0.0;
    const double f = tb / dt;
    const long i = static_cast<long>(std::floor(f));
    const double w = f - static_cast<double>(i);
    const double a = tool[static_cast<size_t>(i)];
    const double b = i + 1 < k ? tool[static_cast<size_t>(i + 1)] : a;
    return a + w * (b - a);
  };

  enum class Phase { approach, slow, hold, law };
  Phase phase = s.strategy == ImpactStrategy::none ? Phase::law : Phase::approach;
  double x = 0.0, v = 0.0, x_com = 0.0, acc = 0.0;
  double v_com = s.rapid_feed, e_prev = 1.0, T = 0.0;
  bool first_law = true;
  for (long k = 0; k < n_steps; ++k) {
    const double t = static_cast<double>(k) * dt;
    // the force: the chip is the tool's travel since the tooth before, into the workpiece beyond its wall
    const double m = std::max(tool_at(k), s.entry_distance);
    const double h = x - m;
    const double F = h > 0.0 ? s.cutting_stiffness * h / (1.0 + mu) : 0.0;
    tool[static_cast<size_t>(k)] = s.spindle_stiffness ? x - F / *s.spindle_stiffness : x;
    if (F > r.peak_force) {
      r.peak_force = F;
      r.peak_force_time_s = t;
    }

    if (k % ctrl_every == 0) {
      const double e = (s.F_nom - F) / s.F_nom;
      if (phase == Phase::approach && F > s.impact_threshold) {
        T = t;
        r.impact_time_s = t;
        if (s.strategy == ImpactStrategy::A) {
          phase = Phase::slow;
          v_com = s.slow_feed;
        } else {
          phase = Phase::hold;
          v_com = 0.0;
          acc = 0.0;
        }
      }
      if (phase == Phase::slow && t >= T + s.slow_time - 1e-12) phase = Phase::law;
      if (phase == Phase::hold && t >= T + s.hold_time - 1e-12) {
        phase = Phase::law;
        x_com = x;  // the pulses resume from where the table stands: the following error was cleared
      }
      if (phase == Phase::law) {
        if (first_law) {
          e_prev = e;  // no derivative kick at the switch
          first_law = false;
        }
        double next = v_com + s.K_ac * e * Tc + s.B * (e - e_prev);
        if (next < 0.0 || next > s.rapid_feed) {
          ++r.command_limited_samples;
          next = std::clamp(next, 0.0, s.rapid_feed);
        }
        v_com = next;
        e_prev = e;
      }
    }
    r.series.push_back({t, v, F, v_com});

    // the DDA: one basic length unit per overflow of the feed accumulator, at most one per interrupt
    const bool holding = phase == Phase::hold;
    if (!holding) {
      acc += v_com * dt / s.blu_m;
      if (acc >= 1.0) {
        acc -= 1.0;
        x_com += s.blu_m;
      }
    }
    const bool reduced_gain = s.strategy == ImpactStrategy::B && r.impact_time_s && phase == Phase::law &&
                              t < T + s.hold_time + s.reduced_gain_time - 1e-12;
    const Discrete& d = holding ? coast : reduced_gain ? reduced : normal;
    const double xn = d.Ad[0] * x + d.Ad[1] * v + d.Bd[0] * x_com;
    const double vn = d.Ad[2] * x + d.Ad[3] * v + d.Bd[1] * x_com;
    x = xn;
    v = vn;
  }
  const size_t n = r.series.size(), from = n - std::max<size_t>(1, n / 10);
  for (size_t i = from; i < n; ++i) {
    r.final_feed += r.series[i].feed;
    r.final_force += r.series[i].force;
  }
  r.final_feed /= static_cast<double>(n - from);
  r.final_force /= static_cast<double>(n - from);
  return r;
}

std::vector<std::complex<double>> closed_loop_poles(const Eq521& e) {
  if (!(positive(e.K_S) && positive(e.K_C_rate) && positive(e.F_nom) && positive(e.B) && std::isfinite(e.K_ac) && e.K_ac >= 0.0 &&
        positive(e.servo.gain) && positive(e.servo.pole1) && positive(e.servo.pole2)))
    throw InputError("Eq. 5.21 needs positive K_S, K'_C, F_nom, B, servo constants and K_ac of 0 or more",
                     "closed_loop_poles");
  // s (s + c)(s + p1)(s + p2) + k s + k K_ac/B, c = K_S/K'_C
  const double c = e.K_S / e.K_C_rate, k = e.servo.gain * e.B * e.K_S / e.F_nom;
  std::vector<double> p{1.0};  // highest power first
  for (double r : {0.0, c, e.servo.pole1, e.servo.pole2}) {
    std::vector<double> q(p.size() + 1, 0.0);
    for (size_t i = 0; i < p.size(); ++i) {
      q[i] += p[i];
      q[i + 1] += p[i] * r;
    }
    p = q;
  }
  p[3] += k;
  p[4] += k * e.K_ac / e.B;
  // the companion matrix of the monic quartic
  Eigen::Matrix4d C = Eigen::Matrix4d::Zero();
  for (int j = 0; j < 4; ++j) C(0, j) = -p[static_cast<size_t>(j + 1)];
  for (int i = 1; i < 4; ++i) C(i, i - 1) = 1.0;
  const Eigen::VectorXcd ev = linalg::eigenvalues(C);
  std::vector<std::complex<double>> roots;
  for (int i = 0; i < 4; ++i) roots.push_back(ev(i));
  std::sort(roots.begin(), roots.end(), [](const auto& a, const auto& b) {
    if (std::abs(a.real() - b.real()) > 1e-9 * (1.0 + std::abs(a.real()))) return a.real() > b.real();
    return a.imag() > b.imag();
  });
  return roots;
}

std::optional<Eq521> eq521_of(const AcLoopSettings& s) {
  if (!s.spindle_stiffness) return std::nullopt;
  Eq521 e;
  e.servo = s.servo;
  e.K_ac = s.K_ac;
  e.B = s.B;
  e.F_nom = s.F_nom;
  e.K_S = *s.spindle_stiffness;
  e.K_C_rate = s.cutting_stiffness * 2.0 * std::numbers::pi / (s.teeth * s.spindle_speed_rad_s);
  return e;
}

std::optional<double> dominant_damping(const std::vector<std::complex<double>>& poles) {
  for (const auto& p : poles)  // slowest first
    if (p.imag() > 1e-9 * std::abs(p)) return -p.real() / std::abs(p);
  return std::nullopt;
}

}  // namespace polarcam::process
