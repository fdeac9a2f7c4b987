#include "optimize/pole_objective.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "metrics/f1.hpp"

namespace polarcam {

const char* to_string(PoleObjective o) {
  switch (o) {
    case PoleObjective::area: return "area";
    case PoleObjective::f1: return "f1";
    case PoleObjective::balanced: return "balanced";
    case PoleObjective::torque: return "torque";
  }
  return "?";
}

bool is_torque_objective(PoleObjective o) { return o == PoleObjective::balanced || o == PoleObjective::torque; }

double torque_search_value(PoleObjective o, const TorqueValue& t) {
  constexpr double kCeiling = 1e3;
  const double v = o == PoleObjective::balanced ? t.balanced : t.worst;
  if (t.computed && v < kCeiling) return v;
  const double over = t.computed && std::isfinite(t.ratio_sum) ? std::min(t.ratio_sum, kCeiling) : kCeiling;
  return kCeiling + over;
}

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

class Translated final : public Curve {
 public:
  Translated(CurvePtr base, Vec2 off)
      : Curve(base->u_begin(), base->u_end(), base->closed(), base->name()), base_(std::move(base)), off_(off) {}
  CurvePoint eval(double u, int order) const override {
    CurvePoint c = base_->eval(u, order);
    c.p = c.p + off_;
    return c;
  }
  std::vector<double> breakpoints() const override { return base_->breakpoints(); }
  // As the digitizer's placed path (cam::ToolPath): the pole distance adds to the base's rounding scale.
  double rounding_scale() const override { return norm(off_) + base_->rounding_scale(); }

 private:
  CurvePtr base_;
  Vec2 off_;
};

}  // namespace

CurvePtr translated(CurvePtr base, Vec2 offset) { return std::make_shared<Translated>(std::move(base), offset); }

PoleProblem make_pole_problem(CurvePtr path0, const Grid& grid, StepRule rule, PoleObjective objective, int segments,
                              bool pole_outside) {
  PoleProblem p;
  p.path0 = std::move(path0);
  p.grid = grid;
  p.rule = rule;
  p.objective = objective;
  p.segments = segments;
  p.f1_points = segment_points(*p.path0, segments);
  p.polyline = segment_points(*p.path0, 4096);
  for (const Vec2& v : p.polyline) p.coordinate_scale = std::max(p.coordinate_scale, norm(v));
  for (size_t b = 0; b * kPolylineBlock + 1 < p.polyline.size(); ++b) {
    std::array<double, 4> box{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                              -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (size_t i = b * kPolylineBlock; i <= std::min((b + 1) * kPolylineBlock, p.polyline.size() - 1); ++i) {
      box[0] = std::min(box[0], p.polyline[i].x), box[1] = std::min(box[1], p.polyline[i].y);
      box[2] = std::max(box[2], p.polyline[i].x), box[3] = std::max(box[3], p.polyline[i].y);
    }
    p.polyline_blocks.push_back(box);
  }
  if (pole_outside) {
    if (!p.path0->closed()) throw InputError("the constraint 'pole outside the contour' needs a closed contour");
    // the polygon: the path sampled finely (chord error below a micrometre for radii of curvature above 1 cm)
    std::vector<Vec2> poly;
    const int n = 4096;
    for (int i = 0; i < n; ++i)
      poly.push_back(p.path0->eval(p.path0->u_begin() + (p.path0->u_end() - p.path0->u_begin()) * i / n, 0).p);
    p.keep_outside = std::make_shared<ContourInside>(std::move(poly));
  }
  return p;
}

double work_area_margin(const PolarTrack& tr, const Grid& g, std::string* why) {
  double m = std::numeric_limits<double>::infinity();
  auto take = [&](double v, const char* w) {
    if (v < m) {
      m = v;
      if (why) *why = w;
    }
  };
  const double rmin = tr.r_min().value, rmax = tr.r_max().value;
  if (g.r_min > 0.0) take(rmin - g.r_min, "r_min");
  if (g.r_max) take(*g.r_max - rmax, "r_max");
  if (g.theta_min) {
    // the whole turns that centre the path's angles in the range are the best branch
    const double lo = tr.theta_min().value, hi = tr.theta_max().value;
    const double kc = ((*g.theta_min + *g.theta_max) - (lo + hi)) / (2.0 * kTwoPi);
    double best = -std::numeric_limits<double>::infinity();
    for (double k : {std::floor(kc), std::ceil(kc)})
      best = std::max(best, std::min(lo + kTwoPi * k - *g.theta_min, *g.theta_max - hi - kTwoPi * k));
    take(best * rmax, "theta range");
  }
  return m;
}

PoleEvaluator::PoleEvaluator(const PoleProblem& p) : p_(p), unlimited_(p.grid) {
  unlimited_.r_min = 0.0;
  unlimited_.r_max.reset();
  unlimited_.theta_min.reset();
  unlimited_.theta_max.reset();
}

PoleValue PoleEvaluator::evaluate(Vec2 pole) { return run(pole, p_.objective == PoleObjective::area, true); }
PoleValue PoleEvaluator::evaluate_feasible(Vec2 pole) {
  return run(pole, p_.objective == PoleObjective::area, true, true);
}
PoleValue PoleEvaluator::area(Vec2 pole) { return run(pole, true, true); }
PoleValue PoleEvaluator::full(Vec2 pole) { return run(pole, true, true, false, true); }
PoleValue PoleEvaluator::margin(Vec2 pole) { return run(pole, false, false); }
PoleValue PoleEvaluator::geometry(Vec2 pole) { return run(pole, false, false, false, false, false); }

PoleValue PoleEvaluator::run(Vec2 pole, bool want_area, bool want_value, bool only_feasible, bool want_torque,
                             bool torque_check) {
  PoleValue out;
  if (!std::isfinite(pole.x) || !std::isfinite(pole.y)) {
    out.why = "not finite";
    return out;
  }
  if (!p_.polyline.empty()) {
    const double clear = kPoleClearance * (p_.coordinate_scale + norm(pole));
    double d2 = std::numeric_limits<double>::infinity();
    auto segments = [&](size_t i0, size_t i1) {
      for (size_t i = i0; i < i1; ++i) {
        const Vec2 a = p_.polyline[i] - pole, d = p_.polyline[i + 1] - p_.polyline[i];
        const double l2 = dot(d, d), s = l2 > 0.0 ? std::clamp(-dot(a, d) / l2, 0.0, 1.0) : 0.0;
        const Vec2 q = a + s * d;
        d2 = std::min(d2, dot(q, q));
      }
    };
    const size_t n = p_.polyline.size() - 1;
    if (p_.polyline_blocks.size() == (n + kPolylineBlock - 1) / kPolylineBlock) {
      // a run whose box lies beyond the clearance (with room for rounding) holds no segment within it: the least
      // distance, where it is below the clearance, is the same as over every segment
      const double reach2 = clear * clear * (1.0 + 1e-9);
      for (size_t b = 0; b < p_.polyline_blocks.size(); ++b) {
        const auto& box = p_.polyline_blocks[b];
        const double dx = std::max({box[0] - pole.x, 0.0, pole.x - box[2]});
        const double dy = std::max({box[1] - pole.y, 0.0, pole.y - box[3]});
        if (dx * dx + dy * dy > reach2) continue;
        segments(b * kPolylineBlock, std::min((b + 1) * kPolylineBlock, n));
      }
    } else {
      segments(0, n);
    }
    if (d2 < clear * clear) {
      out.why = "the path passes within " + significant(std::sqrt(d2) * 1e3, 6) + " mm of the machine pole";
      return out;
    }
  }
  CurvePtr path = translated(p_.path0, -pole);
  PolarTrack tr;
  try {
    tr = PolarTrack::build(*path);
  } catch (const InputError&) {
    out.why = "the path runs through the machine pole";
    return out;
  }
  out.margin = work_area_margin(tr, p_.grid, &out.why);
  if (p_.keep_outside) {
    const double d = p_.keep_outside->boundary_distance(pole);
    const double m = p_.keep_outside->inside(pole) ? -d : d;
    if (m < out.margin) {
      out.margin = m;
      out.why = "pole outside the contour";
    }
  }
  out.geometry_margin = out.margin;
  if (only_feasible && !(out.margin >= 0.0)) {
    out.computed = true;
    return out;
  }
  const bool torque_objective = is_torque_objective(p_.objective);
  if (p_.torque && (want_torque || (torque_check && p_.torque_limit) || (want_value && torque_objective))) {
    out.torque = evaluate_torques(*p_.torque, *path, tr);
    out.torque_computed = true;
    if (torque_check && p_.torque_limit) {
      // relative excess over the limits (> 0 infeasible), capped so that the margin stays finite
      const TorqueValue& t = out.torque;
      double excess = t.computed ? t.worst / *p_.torque_limit - 1.0 : 10.0;
      const char* why = "torque ratio";
      if (t.computed && t.rate_over - 1.0 > excess) {
        excess = t.rate_over - 1.0;
        why = "step rate";
      }
      if (!(excess <= 10.0)) excess = 10.0;
      const double m = -excess * kTorqueMarginLength;
      if (m < out.margin) {
        out.margin = m;
        out.why = why;
      }
    }
  }
  if (only_feasible && !(out.margin >= 0.0)) {
    out.computed = true;
    return out;
  }
  if (want_area) {
    meter_.reset(tr, unlimited_);
    AreaErrorResult a;
    bool implied = false;
    if (p_.rule == StepRule::nearest) {
      // the nearest rule's staircase read off the meter's own walk of the path, where every decision is clear of
      // the levels (the same staircase as the digitizer's); the digitizer otherwise
      const std::array<int64_t, 2> n0 = start_node(tr, unlimited_, p_.rule);
      implied = meter_.imply_nearest(n0[0], n0[1]);
      if (implied) a = meter_.finish(n0[0], n0[1]);
    }
    if (!implied) {
      meter_.reset(tr, unlimited_);
      auto prof = make_constant_speed(1.0, tr.length());  // step times do not matter here
      const DigitizeResult d = digitize(tr, unlimited_, p_.rule, *prof, &meter_);
      a = meter_.finish(d.start_n, d.start_m);
    }
    out.area_m2 = a.area_m2;
    out.steps = a.rise_steps + a.run_steps;
  }
  out.computed = true;
  if (want_value) {
    if (p_.objective == PoleObjective::area)
      out.value = out.area_m2;
    else if (p_.objective == PoleObjective::f1)
      out.value = f1_chords(p_.f1_points, pole, p_.grid.dr, p_.grid.dtheta).F1;
    else
      out.value = out.torque_computed ? torque_search_value(p_.objective, out.torque) : 0.0;
  }
  return out;
}

}  // namespace polarcam
