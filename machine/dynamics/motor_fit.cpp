// The only translation unit that includes Ceres.
#include "machine/dynamics/motor_fit.hpp"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include "cam/error.hpp"

namespace polarcam {

std::optional<RobustLoss> parse_robust_loss(const std::string& s) {
  if (s == "none") return RobustLoss::none;
  if (s == "huber") return RobustLoss::huber;
  if (s == "cauchy") return RobustLoss::cauchy;
  return std::nullopt;
}

const char* to_string(RobustLoss l) {
  static constexpr const char* kNames[] = {"none", "huber", "cauchy"};  // in the order of the enum
  return kNames[static_cast<int>(l)];
}

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// The model's pieces at one point: T = K_T a - (K_T K_V) b for a given L_a.
struct Basis {
  double a, b;
};
Basis basis(double w, double L, double c1V, double R, double Ns) {
  const double z2 = R * R + w * w * L * L;
  return {c1V / std::sqrt(z2), w * R / (Ns * z2)};
}

struct Residual {
  double w, torque, c1V, R, Ns, sKT, sKV, sL;
  template <class T>
  bool operator()(const T* const x, T* r) const {
    const T KT = x[0] * sKT, KV = x[1] * sKV, L = x[2] * sL;
    const T z2 = T(R * R) + T(w * w) * L * L;
    r[0] = T(c1V) * KT / ceres::sqrt(z2) - KV * KT * T(w * R / Ns) / z2 - T(torque);
    return true;
  }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double mad_sigma(const std::vector<double>& r) {
  const double m = median(r);
  std::vector<double> d;
  for (double x : r) d.push_back(std::abs(x - m));
  return 1.4826 * median(d);
}

}  // namespace

MotorFitResult fit_electrical_motor(const std::vector<PulloutPoint>& pts, const ElectricalMotor& known,
                                    const MotorFitOptions& opt) {
  {
    ElectricalMotor probe = known;
    probe.K_T = 1.0;
    probe.K_V = 0.0;
    probe.L_a = 0.0;
    probe.validate();  // supply voltage, R_a, N_s
  }
  if (pts.size() < 4) throw InputError("a motor fit needs at least four points, got " + std::to_string(pts.size()));
  std::set<double> distinct;
  double tmax = 0.0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const std::string row = "point " + std::to_string(i + 1) + ": ";
    if (!(pts[i].rate_hz >= 0.0) || !std::isfinite(pts[i].rate_hz))
      throw InputError(row + "the step rate must be zero or positive");
    if (!(pts[i].torque > 0.0) || !std::isfinite(pts[i].torque)) throw InputError(row + "the torque must be positive");
    distinct.insert(pts[i].rate_hz);
    tmax = std::max(tmax, pts[i].torque);
  }
  if (distinct.size() < 3) throw InputError("a motor fit needs at least three different step rates");
  if (opt.loss_scale && !(*opt.loss_scale > 0.0)) throw InputError("the loss scale must be positive");

  const double R = known.R_a, Ns = known.rotor_teeth;
  const double c1V = pullout_coefficient(known.energisation) * known.supply_voltage;
  const double spr = known.steps_per_rev();
  std::vector<double> w(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) w[i] = kTwoPi * Ns * pts[i].rate_hz / spr;

  // start: scan L_a over 1e-7 .. 10 H, solving K_T and P = K_T K_V (>= 0) by least squares for each
  double best_sse = std::numeric_limits<double>::infinity(), KT0 = 0, P0 = 0, L0 = 0;
  for (int k = 0; k <= 320; ++k) {
    const double L = std::pow(10.0, -7.0 + 8.0 * k / 320.0);
    Eigen::MatrixXd A(pts.size(), 2);
    Eigen::VectorXd y(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) {
      Basis b = basis(w[i], L, c1V, R, Ns);
      A(static_cast<Eigen::Index>(i), 0) = b.a;
      A(static_cast<Eigen::Index>(i), 1) = -b.b;
      y(static_cast<Eigen::Index>(i)) = pts[i].torque;
    }
    Eigen::Vector2d x = A.colPivHouseholderQr().solve(y);
    if (!(x(1) >= 0.0)) {  // back-emf term cannot help: K_V = 0
      x(1) = 0.0;
      x(0) = A.col(0).dot(y) / A.col(0).squaredNorm();
    }
    if (!(x(0) > 0.0)) continue;
    const double sse = (A * x - y).squaredNorm();
    if (sse < best_sse) {
      best_sse = sse;
      KT0 = x(0);
      P0 = x(1);
      L0 = L;
    }
  }
  if (!(KT0 > 0.0)) throw InputError("the points do not fit the pull-out model at all (no positive torque constant)");
  const double KV0 = P0 / KT0;

  MotorFitResult res;
  res.loss = opt.loss;
  std::vector<double> r0(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    Basis b = basis(w[i], L0, c1V, R, Ns);
    r0[i] = KT0 * b.a - P0 * b.b - pts[i].torque;
  }
  res.loss_scale = opt.loss_scale.value_or(std::max(2.5 * mad_sigma(r0), 1e-3 * tmax));

  // refine with Ceres; parameters scaled to order one. Without a given loss scale, the scale is re-estimated from
  // the robust fit's own residuals and the fit repeated (the starting fit's residuals are inflated by the very
  // outliers the loss is meant to discount).
  const double sKT = KT0, sKV = KT0, sL = L0;
  double x[3] = {1.0, KV0 / sKV, 1.0};
  const int rounds = (opt.loss == RobustLoss::none || opt.loss_scale) ? 1 : 3;
  for (int round = 0; round < rounds; ++round) {
    if (round > 0) {
      std::vector<double> rr(pts.size());
      for (size_t i = 0; i < pts.size(); ++i) {
        Basis b = basis(w[i], x[2] * sL, c1V, R, Ns);
        rr[i] = x[0] * sKT * b.a - x[0] * sKT * x[1] * sKV * b.b - pts[i].torque;
      }
      res.loss_scale = std::max(2.5 * mad_sigma(rr), 1e-3 * tmax);
    }
    ceres::Problem::Options popt;
    popt.loss_function_ownership = ceres::TAKE_OWNERSHIP;
    ceres::Problem problem(popt);
    for (size_t i = 0; i < pts.size(); ++i) {
      ceres::LossFunction* loss = nullptr;
      if (opt.loss == RobustLoss::huber) loss = new ceres::HuberLoss(res.loss_scale);
      if (opt.loss == RobustLoss::cauchy) loss = new ceres::CauchyLoss(res.loss_scale);
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<Residual, 1, 3>(new Residual{w[i], pts[i].torque, c1V, R, Ns, sKT, sKV, sL}),
          loss, x);
    }
    problem.SetParameterLowerBound(x, 0, 1e-9);
    problem.SetParameterLowerBound(x, 1, 0.0);
    problem.SetParameterLowerBound(x, 2, 1e-9);
    ceres::Solver::Options sopt;
    sopt.linear_solver_type = ceres::DENSE_QR;
    sopt.max_num_iterations = 500;
    sopt.function_tolerance = 1e-15;
    sopt.gradient_tolerance = 1e-16;
    sopt.parameter_tolerance = 1e-14;
    sopt.num_threads = 1;
    sopt.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(sopt, &problem, &summary);
    if (!summary.IsSolutionUsable()) throw InputError("the motor fit failed: " + summary.message);
    if (round == 0) res.initial_cost = summary.initial_cost;
    res.report = summary.BriefReport();
    res.final_cost = summary.final_cost;
    res.iterations += static_cast<int>(summary.iterations.size());
    res.converged = summary.termination_type == ceres::CONVERGENCE;
  }

  res.motor = known;
  res.motor.K_T = x[0] * sKT;
  res.motor.K_V = x[1] * sKV;
  res.motor.L_a = x[2] * sL;

  // residuals, outliers (beyond outlier_sigmas robust standard deviations), statistics over the inliers
  for (size_t i = 0; i < pts.size(); ++i) res.residuals.push_back(res.motor.pullout(w[i]) - pts[i].torque);
  const double sigma = std::max(mad_sigma(res.residuals), 1e-4 * tmax);
  double ss = 0.0;
  size_t n_in = 0;
  for (double r : res.residuals) {
    const bool out = std::abs(r) > opt.outlier_sigmas * sigma;
    res.outlier.push_back(out);
    if (!out) {
      ss += r * r;
      ++n_in;
      res.max_abs_residual = std::max(res.max_abs_residual, std::abs(r));
    }
  }
  res.rms = n_in ? std::sqrt(ss / static_cast<double>(n_in)) : 0.0;

  // standard errors from the inliers' Jacobian (plain least squares at the solution), when determined
  if (n_in > 3) {
    double xc[3] = {x[0], x[1], x[2]};
    ceres::Problem cp;
    for (size_t i = 0; i < pts.size(); ++i)
      if (!res.outlier[i])
        cp.AddResidualBlock(new ceres::AutoDiffCostFunction<Residual, 1, 3>(
                                new Residual{w[i], pts[i].torque, c1V, R, Ns, sKT, sKV, sL}),
                            nullptr, xc);
    ceres::Covariance::Options copt;
    copt.algorithm_type = ceres::DENSE_SVD;
    copt.null_space_rank = -1;
    copt.min_reciprocal_condition_number = 1e-14;
    copt.num_threads = 1;
    ceres::Covariance cov(copt);
    std::vector<std::pair<const double*, const double*>> blocks{{xc, xc}};
    if (cov.Compute(blocks, &cp)) {
      double C[9];
      if (cov.GetCovarianceBlock(xc, xc, C)) {
        const double s2 = ss / static_cast<double>(n_in - 3);
        auto sd = [&](int k, double scale) -> std::optional<double> {
          const double v = C[4 * k] * s2;
          if (!(v >= 0.0) || !std::isfinite(v)) return std::nullopt;
          return std::sqrt(v) * scale;
        };
        res.K_T_sd = sd(0, sKT);
        res.K_V_sd = sd(1, sKV);
        res.L_a_sd = sd(2, sL);
      }
    }
  }
  return res;
}

}  // namespace polarcam
