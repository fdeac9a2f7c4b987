#include "digitizer/template_speed.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "digitizer/axis_track.hpp"

namespace polarcam {

double template_v_star_curvature(double c, double rr_star) { return 2.0 * (1.0 - rr_star * c) / (2.0 + c); }

double template_v_star_slope(double c, double rr_star) {
  return -2.0 * (2.0 * rr_star + 1.0) / ((2.0 + c) * (2.0 + c));
}

double template_v_star(double rho_star, double rr_star, CurvatureSide side) {
  if (std::isinf(rho_star)) return 1.0;
  // Eq. 3.3a / 3.3b with the factor 2 of Eq. 3.2
  return side == CurvatureSide::roller ? 2.0 * (rho_star - rr_star) / (2.0 * rho_star + 1.0)
                                       : 2.0 * (rho_star + rr_star) / (2.0 * rho_star - 1.0);
}

double template_c_min(double rr_star) { return -1.0 / (1.0 + rr_star); }
double template_c_max(double rr_star) { return 1.0 / rr_star; }

namespace {

constexpr int kDeg = 16;
constexpr int kMaxDepth = 48;
constexpr double kTail = 1e-14;

std::string mm(double v) { return significant(v * 1e3, 6) + " mm"; }
std::string at(Vec2 p) { return "at (" + significant(p.x * 1e3, 6) + ", " + significant(p.y * 1e3, 6) + ") mm"; }

struct Builder {
  const Curve& path;
  double offset, v_t;
  TemplateSpec spec;
  double rr_star;

  struct Sample {
    Vec2 p;
    double g = 0, c = 0;  // |P'| and H kappa (+ toward G)
  };

  Sample sample(double u) const {
    const CurvePoint cp = path.eval(u, 2);
    Sample s;
    s.p = cp.p;
    s.g = norm(cp.d1);
    const double kq = curvature(cp);  // the path's curvature, + turning left
    const double den = 1.0 + offset * kq;
    if (!(den > 1e-12) || !std::isfinite(kq))
      throw InputError("the template has a corner " + at(cp.p) + ": the roller pair cannot follow it; round it with "
                       "an arc of radius at least " + mm(spec.thickness + spec.roller_radius));
    s.c = spec.roller_sign * spec.thickness * kq / den;
    return s;
  }

  void check(const Sample& s) const {
    const double H = spec.thickness;
    if (!(s.c < template_c_max(rr_star)))
      throw InputError("the template's radius of curvature " + mm(H / s.c) + " " + at(s.p) +
                       " on the driven roller's side is not larger than the roller radius " + mm(spec.roller_radius) +
                       ": the roller stops there (Eq. 3.3a); use a smaller roller_radius or a gentler template");
    if (!(s.c >= template_c_min(rr_star)))
      throw InputError("the template's radius of curvature " + mm(-H / s.c) + " " + at(s.p) +
                       " leaves less than the roller radius " + mm(spec.roller_radius) +
                       " on its concave face, where the pressure roller runs (it needs at least thickness + "
                       "roller_radius = " + mm(H + spec.roller_radius) + "); use a smaller roller_radius or thickness");
  }

  double v_of(double c) const { return v_t * template_v_star_curvature(c, rr_star); }

  std::vector<TemplateSpeed::Piece> pieces;
  std::vector<double> piece_u0;  // parameter at each piece start
  std::vector<bool> at_break;    // piece starts at a breakpoint of the path
  TemplateSpeedRange range;
  bool have_range = false;

  void note(const TemplatePoint& q) {
    if (!have_range) {
      range.slowest = range.fastest = range.worst = q;
      have_range = true;
      return;
    }
    if (q.v_star < range.slowest.v_star) range.slowest = q;
    if (q.v_star > range.fastest.v_star) range.fastest = q;
    if (std::abs(q.v_star - 1.0) > std::abs(range.worst.v_star - 1.0)) range.worst = q;
  }

  // Fits [ua, ub]; appends the pieces in order (s0, t0 relative, fixed up by the caller).
  void fit(double ua, double ub, int depth, bool first_at_break) {
    const auto& pts = cheb_points();
    const double mid = 0.5 * (ua + ub), half = 0.5 * (ub - ua);
    double g[kDeg + 1], h[kDeg + 1], c[kDeg + 1];
    for (int j = 0; j <= kDeg; ++j) {
      const Sample s = sample(mid + half * pts[j]);
      check(s);
      g[j] = s.g * half;
      c[j] = s.c;
      h[j] = g[j] / v_of(s.c);
    }
    Cheb G = cheb_fit(g, kDeg), Hc = cheb_fit(h, kDeg), C = cheb_fit(c, kDeg);
    const double tg = kTail * G.max_abs() + 1e-300, th = kTail * Hc.max_abs() + 1e-300;
    const double tc = 1e-12 * (C.max_abs() + 1.0);
    const bool ok = cheb_tail(G) <= tg && cheb_tail(Hc) <= th && cheb_tail(C) <= tc;
    if (!ok && depth < kMaxDepth && mid > ua && mid < ub) {
      fit(ua, mid, depth + 1, first_at_break);
      fit(mid, ub, depth + 1, false);
      return;
    }
    if (!ok)
      throw InputError("the template speed cannot be resolved " + at(path.eval(mid, 0).p) +
                       ": the template's curvature changes too abruptly there");
    cheb_chop(G, tg);
    cheb_chop(Hc, th);
    cheb_chop(C, tc);
    TemplateSpeed::Piece pc;
    pc.G = G;
    pc.C = C;
    pc.S = G.integral();
    pc.T = Hc.integral();
    pc.len = pc.S(1.0);
    // the extremes of c on the piece: its ends and the roots of dc/dt, evaluated exactly
    std::vector<double> ts{-1.0, 1.0};
    cheb_sign_changes(C.derivative(), ts);
    for (double t : ts) {
      const Sample s = sample(mid + half * t);
      check(s);
      TemplatePoint q;
      q.s = pc.S(t);  // relative to the piece; fixed up below
      q.p = s.p;
      q.c = s.c;
      q.radius_m = s.c == 0.0 ? std::numeric_limits<double>::infinity() : spec.thickness / std::abs(s.c);
      q.side = s.c >= 0.0 ? CurvatureSide::roller : CurvatureSide::other;
      q.v_star = template_v_star_curvature(s.c, rr_star);
      q.speed_mps = v_t * q.v_star;
      pending.push_back({pieces.size(), q});
    }
    pieces.push_back(pc);
    piece_u0.push_back(ua);
    at_break.push_back(first_at_break);
  }
  struct Pending {
    size_t piece;
    TemplatePoint q;
  };
  std::vector<Pending> pending;
};

}  // namespace

TemplateSpeed::TemplateSpeed(std::vector<Piece> pieces, std::vector<double> kinks, TemplateSpeedRange range,
                             double v_t, double rr_star, double own_length, double length)
    : SpeedProfile(length), pieces_(std::move(pieces)), kinks_(std::move(kinks)), range_(range), v_t_(v_t),
      rr_star_(rr_star), scale_(length > 0.0 ? own_length / length : 1.0) {}

std::pair<size_t, double> TemplateSpeed::locate(double s) const {
  const double own = std::clamp(s * scale_, 0.0, pieces_.back().s0 + pieces_.back().len);
  auto it = std::upper_bound(pieces_.begin(), pieces_.end(), own, [](double x, const Piece& p) { return x < p.s0; });
  const size_t i = it == pieces_.begin() ? 0 : static_cast<size_t>(it - pieces_.begin()) - 1;
  const Piece& p = pieces_[i];
  const double y = std::clamp(own - p.s0, 0.0, p.len);
  const double t = cheb_solve(p.S, y, -1.0, 1.0, -y, p.len - y);
  return {i, t};
}

double TemplateSpeed::time_at(double s) const {
  if (s <= 0.0) return 0.0;
  const auto [i, t] = locate(s);
  return pieces_[i].t0 + pieces_[i].T(t);
}

double TemplateSpeed::speed_at(double s) const {
  const auto [i, t] = locate(s);
  return v_t_ * template_v_star_curvature(pieces_[i].C(t), rr_star_);
}

double TemplateSpeed::accel_at(double s) const {
  const auto [i, t] = locate(s);
  const Piece& p = pieces_[i];
  double c, dc;
  p.C.eval2(t, c, dc);
  const double v = v_t_ * template_v_star_curvature(c, rr_star_);
  const double ds_dt = p.G(t);
  if (!(ds_dt > 0.0)) return 0.0;
  return v * v_t_ * template_v_star_slope(c, rr_star_) * dc / ds_dt;  // V dV/ds
}

std::shared_ptr<const TemplateSpeed> make_template_speed(const Curve& path, double offset, double v_t,
                                                         const TemplateSpec& spec, double length) {
  if (!(v_t > 0.0) || !std::isfinite(v_t)) throw InputError("the template's set speed V_t must be positive");
  if (!(spec.thickness > 0.0) || !std::isfinite(spec.thickness))
    throw InputError("the template thickness must be a positive length");
  if (!(spec.roller_radius > 0.0) || !std::isfinite(spec.roller_radius))
    throw InputError("the roller radius must be a positive length");
  Builder b{path, offset, v_t, spec, spec.roller_radius / spec.thickness, {}, {}, {}, {}, false, {}};
  std::vector<double> cuts{path.u_begin()};
  for (double u : path.breakpoints()) cuts.push_back(u);
  cuts.push_back(path.u_end());
  // a corner (the tangent turns at a joint) cannot be tracked: the roller would have to turn on the spot
  const size_t n = cuts.size();
  for (size_t k = path.closed() ? 0 : 1; k + 1 < n; ++k) {
    // joint k between the pieces ending and starting at cuts[k] (k = 0: a closed path's seam)
    const double before = k == 0 ? cuts[n - 1] : cuts[k], after = cuts[k];
    const double du = 1e-9 * std::max(cuts[k + 1] - after, k == 0 ? cuts[n - 1] - cuts[n - 2] : before - cuts[k - 1]);
    const double u = after;
    const CurvePoint a = path.eval(before - du, 1), c = path.eval(after + du, 1);
    const double turn = std::atan2(cross(a.d1, c.d1), dot(a.d1, c.d1));
    if (std::abs(turn) > 1e-6)
      throw InputError("the template has a corner " + at(path.eval(u, 0).p) + " (the path turns by " +
                       significant(turn, 3) + " rad): the roller pair cannot follow it; round it with an arc of "
                       "radius at least " + mm(spec.thickness + spec.roller_radius));
  }
  for (size_t k = 0; k + 1 < cuts.size(); ++k) b.fit(cuts[k], cuts[k + 1], 0, k > 0);
  // cumulative arc length and time
  double s = 0.0, t = 0.0;
  std::vector<double> kinks;
  for (size_t i = 0; i < b.pieces.size(); ++i) {
    TemplateSpeed::Piece& p = b.pieces[i];
    p.s0 = s;
    p.t0 = t;
    if (b.at_break[i]) kinks.push_back(s);
    s += p.len;
    t += p.T(1.0);
  }
  for (auto& pd : b.pending) {
    pd.q.s = (pd.q.s + b.pieces[pd.piece].s0) * (length > 0.0 && s > 0.0 ? length / s : 1.0);
    b.note(pd.q);
  }
  for (double& k : kinks) k *= length > 0.0 && s > 0.0 ? length / s : 1.0;
  auto prof = std::make_shared<const TemplateSpeed>(std::move(b.pieces), std::move(kinks), b.range, v_t,
                                                    b.rr_star, s, length);
  const double T = prof->total_time();
  if (!(T * 1e9 <= kMaxDurationNs))
    throw InputError("the path of " + significant(length) + " m takes " + significant(T, 3) +
                     " s with the template speed, longer than a tape can time (2^62 ns, about 146 years): raise the "
                     "speed");
  return prof;
}

}  // namespace polarcam
