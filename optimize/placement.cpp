// The three placement methods (Hooke-Jeeves, NLopt stages, sampling) and the pole surveys. One file of over 500
// lines on purpose: the methods share the evaluation cache, the penalty and the stage bookkeeping, and split apart
// each part would carry half of that machinery.
#include "optimize/placement.hpp"

#include <nlopt.hpp>
#include <utility>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>
#include <sstream>
#include <thread>

#include "cam/error.hpp"
#include "metrics/f1.hpp"
#include "optimize/hooke_jeeves.hpp"

namespace polarcam {

const char* to_string(PoleMethod m) {
  switch (m) {
    case PoleMethod::nlopt: return "nlopt";
    case PoleMethod::hooke_jeeves: return "hooke-jeeves";
    default: return "automatic";
  }
}
const char* to_string(PoleHold h) {
  switch (h) {
    case PoleHold::C: return "C";
    case PoleHold::beta: return "beta";
    default: return "none";
  }
}

int default_threads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n > 0 ? static_cast<int>(n) : 1;
}

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kBig = 1e6;     // objective where nothing can be evaluated, before any value is known
constexpr double kLambda = 1.0;  // penalty per mm outside the work area (mm^2 of area, or F1)
constexpr int kStencil = 2;      // evaluations averaged per smoothed area value
constexpr size_t kVertices = 1;  // area: vertex centres searched (vertex_centres)
constexpr int kStarts = 2;       // area: local searches from the best separated cells of the coarse map
// area: default budget, digitized steps in all. At 2.7e6 (193 evaluations) the serpentine's optimum moved between
// basins 4 % apart (1.067 and 1.108 mm^2) when the area error changed by rounding alone; at 5.4e6 five such
// variants all ended within 1.062-1.076 mm^2 (docs/area-error.md, "Methods").
constexpr double kAreaBudgetSteps = 5.4e6;

std::string mm(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v * 1e3 << " mm";
  return os.str();
}

// Runs fn(i, evaluator) for i in [0, n) on a fixed number of threads, each with its own evaluator; a result
// depends only on its index, so the scheduling does not matter.
class Workers {
 public:
  Workers(const PoleProblem& p, int threads) : n_(std::max(1, threads)) {
    for (int t = 0; t < n_; ++t) ev_.push_back(std::make_unique<PoleEvaluator>(p));
  }
  // `progress`: the share of the items done, after each one (an item is a pole: far more work than a call), in
  // increasing order whichever thread finishes.
  template <class Fn>
  void run(size_t count, Fn fn, const Progress& progress = {}) {
    const size_t T = std::min(static_cast<size_t>(n_), count);
    std::mutex pm;
    size_t done = 0;
    auto one = [&](size_t i, PoleEvaluator& ev) {
      fn(i, ev);
      if (!progress) return;
      std::lock_guard<std::mutex> lk(pm);
      progress(static_cast<double>(++done) / static_cast<double>(count));
    };
    if (T <= 1) {
      for (size_t i = 0; i < count; ++i) one(i, *ev_[0]);
      return;
    }
    std::exception_ptr err;
    std::mutex m;
    auto part = [&](size_t t) {
      try {
        for (size_t i = t; i < count; i += T) one(i, *ev_[t]);
      } catch (...) {
        std::lock_guard<std::mutex> lk(m);
        if (!err) err = std::current_exception();
      }
    };
    std::vector<std::thread> th;
    for (size_t t = 1; t < T; ++t) th.emplace_back(part, t);
    part(0);
    for (auto& x : th) x.join();
    if (err) std::rethrow_exception(err);
  }

 private:
  int n_;
  std::vector<std::unique_ptr<PoleEvaluator>> ev_;
};

// Search coordinates: (x, y) of the pole, or beta alone (C held), or C alone (beta held).
struct Param {
  PoleHold hold = PoleHold::none;
  double C = 0, beta = 0;
  std::vector<double> lo, hi;
  int dim() const { return hold == PoleHold::none ? 2 : 1; }
  Vec2 pole(const std::vector<double>& t) const {
    switch (hold) {
      case PoleHold::C: return {C * std::cos(t[0]), C * std::sin(t[0])};
      case PoleHold::beta: return {t[0] * std::cos(beta), t[0] * std::sin(beta)};
      default: return {t[0], t[1]};
    }
  }
  // a length along the search coordinates, in their units
  double scale(double len) const { return hold == PoleHold::C ? len / C : len; }
};

Param make_param(const PoleProblem& p, const Placement& start, PoleHold hold, int threads,
                 const std::optional<SearchBox>& known) {
  Param q;
  q.hold = hold;
  q.C = start.C;
  q.beta = start.beta;
  SearchBox b = search_box(p);
  // the global stage searches where the constraints can be met (found from margins alone, without digitizing)
  if (hold == PoleHold::none) b = known ? *known : feasible_box(p, b, 41, threads);
  if (hold == PoleHold::none) {
    q.lo = {b.x0, b.y0};
    q.hi = {b.x1, b.y1};
  } else if (hold == PoleHold::C) {
    if (!(start.C > 0.0)) throw InputError("holding C = 0 leaves nothing to optimise (beta does not move the pole)");
    q.lo = {start.beta - kPi};
    q.hi = {start.beta + kPi};
  } else {
    // the part of the ray from O1 at angle beta inside the box
    const double ux = std::cos(start.beta), uy = std::sin(start.beta);
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    auto clip = [&](double u, double a, double b2) {
      if (std::abs(u) < 1e-15) {
        if (0.0 < a || 0.0 > b2) t1 = -1.0;
        return;
      }
      double s0 = a / u, s1 = b2 / u;
      if (s0 > s1) std::swap(s0, s1);
      t0 = std::max(t0, s0);
      t1 = std::min(t1, s1);
    };
    clip(ux, b.x0, b.x1);
    clip(uy, b.y0, b.y1);
    if (!(t1 > t0)) throw InputError("with beta held at " + std::to_string(start.beta) + " rad no pole position can keep "
                                     "the path within r_max");
    q.lo = {t0};
    q.hi = {t1};
  }
  return q;
}

struct Candidate {
  std::vector<double> t;
  Vec2 pole;
  PoleValue v;
};

class Search {
 public:
  Search(const PoleProblem& p, const Param& q, int threads) : p_(p), q_(q), threads_(threads), workers_(p, threads) {}

  // exact evaluations of several points, in parallel; offered as candidates in index order
  std::vector<PoleValue> exact(const std::vector<std::vector<double>>& ts) {
    std::vector<PoleValue> out(ts.size());
    workers_.run(ts.size(), [&](size_t i, PoleEvaluator& ev) { out[i] = ev.evaluate(q_.pole(ts[i])); });
    for (size_t i = 0; i < ts.size(); ++i) offer({ts[i], q_.pole(ts[i]), out[i]});
    count(ts.size());
    return out;
  }
  // The same for the stages that keep only a point better than the best so far (the sampling disc, the compass
  // polish): with a torque limit, first the area error alone (on the problem without the limit), then the full
  // evaluation only where it is below the best feasible area at the start of the batch. A point above it cannot become
  // the best whatever its torques (the limit decides nothing there): it counts as an evaluation, is not offered, and
  // comes back as not computed. The best point found is the same as exact()'s.
  std::vector<PoleValue> exact_improving(const std::vector<std::vector<double>>& ts) {
    if (!p_.torque_limit || p_.objective != PoleObjective::area || !have_) return exact(ts);
    if (!area_only_) {
      unlimited_ = p_;
      unlimited_.torque_limit.reset();
      area_only_ = std::make_unique<Workers>(unlimited_, threads_);
    }
    const double below = best_.v.value;
    std::vector<PoleValue> out(ts.size());
    area_only_->run(ts.size(), [&](size_t i, PoleEvaluator& ev) { out[i] = ev.evaluate(q_.pole(ts[i])); });
    std::vector<size_t> full;
    for (size_t i = 0; i < ts.size(); ++i) {
      if (out[i].computed && !(out[i].area_m2 < below)) {
        out[i] = PoleValue{};
        out[i].why = "above the best area error so far (the torque limit not checked)";
      } else {
        full.push_back(i);
      }
    }
    workers_.run(full.size(), [&](size_t k, PoleEvaluator& ev) { out[full[k]] = ev.evaluate(q_.pole(ts[full[k]])); });
    for (size_t i : full) offer({ts[i], q_.pole(ts[i]), out[i]});
    count(ts.size());
    return out;
  }
  // Progress reported as the share of `budget` evaluations spent (a stage may stop early or overrun a little).
  void set_progress(const Progress& p) { progress_ = p; }
  void set_budget(int budget) { budget_ = std::max(budget_, static_cast<double>(budget)); }
  void count(size_t n) {
    evaluations_ += static_cast<int>(n);
    if (progress_ && budget_ > 0) {  // the share of the budget, short of 1 until the search ends
      const double f = std::min(0.99, static_cast<double>(evaluations_) / budget_);
      if (f > reported_) progress_(reported_ = f);
    }
  }

  // objective in search units: area in mm^2 or F1; margin in mm
  static double scaled(const PoleProblem& p, const PoleValue& v) {
    return p.objective == PoleObjective::area ? v.value * 1e6 : v.value;
  }

  // the smoothed value (mean of the stencil for the area) and mean margin (mm); false if not computable
  // Where nothing can be evaluated (the path too close to the machine pole), the global stage sees twice the mean of
  // the values seen so far: a huge constant there would hide the basin around it from DIRECT (the box's centre is
  // often such a point: the pole on the contour).
  double unevaluable() const { return ref_n_ > 0 ? 2.0 * ref_sum_ / ref_n_ : kBig; }
  void seed_reference(double v) {
    ref_sum_ += v;
    ++ref_n_;
  }

  bool smoothed(const std::vector<double>& t, double& S, double& M) {
    std::vector<std::vector<double>> ts;
    if (p_.objective == PoleObjective::area) {
      const double h = q_.scale(0.5 * p_.grid.dr);
      for (int s : {-1, 1}) {
        std::vector<double> x = t;
        if (q_.dim() == 2) {
          x[0] += s * h * std::numbers::sqrt2 / 2;
          x[1] += s * h * std::numbers::sqrt2 / 2;
        } else {
          x[0] += s * h;
        }
        ts.push_back(x);
      }
    } else {
      ts.push_back(t);
    }
    const std::vector<PoleValue> v = exact(ts);
    S = 0.0;
    M = 0.0;
    for (const PoleValue& x : v) {
      if (!x.computed) return false;
      S += scaled(p_, x);
      M += std::isfinite(x.margin) ? x.margin * 1e3 : 1e9;
    }
    S /= static_cast<double>(v.size());
    M /= static_cast<double>(v.size());
    ref_sum_ += S;
    ++ref_n_;
    return true;
  }

  void offer(const Candidate& c) {
    if (keep_seen_ && c.v.feasible()) seen_.push_back(c);
    if (!c.v.feasible()) {
      if (c.v.computed && (!have_any_ || c.v.margin > tightest_.margin)) {
        tightest_ = c.v;
        have_any_ = true;
      }
      return;
    }
    if (!have_ || c.v.value < best_.v.value) {
      best_ = c;
      have_ = true;
    }
  }

  bool have() const { return have_; }
  const Candidate& best() const { return best_; }
  int evaluations() const { return evaluations_; }
  const PoleValue& tightest() const { return tightest_; }
  Workers& workers() { return workers_; }
  // every feasible evaluation so far, in order (kept when keep_seen(true))
  void keep_seen(bool k) { keep_seen_ = k; }
  const std::vector<Candidate>& feasible_seen() const { return seen_; }

 private:
  const PoleProblem& p_;
  const Param& q_;
  int threads_;
  Workers workers_;
  PoleProblem unlimited_;               // p_ without its torque limit (exact_improving's first look)
  std::unique_ptr<Workers> area_only_;  // on unlimited_, made when first needed
  Candidate best_;
  bool have_ = false, have_any_ = false;
  PoleValue tightest_;
  int evaluations_ = 0;
  Progress progress_;
  double budget_ = 0.0, reported_ = 0.0;
  double ref_sum_ = 0.0;
  int ref_n_ = 0;
  bool keep_seen_ = false;
  std::vector<Candidate> seen_;
};

struct NloptCtx {
  Search* s;
  const PoleProblem* p;
  bool penalised;
  std::vector<double> last_t;
  double last_S = 0, last_M = 0;
  bool last_ok = false;
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> best_t;

  void eval(const std::vector<double>& t) {
    if (t == last_t) return;
    last_t = t;
    last_ok = s->smoothed(t, last_S, last_M);
  }
  double objective(const std::vector<double>& t) {
    eval(t);
    const double g = last_ok ? last_S + (penalised ? kLambda * std::max(0.0, -last_M) : 0.0) : s->unevaluable();
    const double rank = last_ok ? last_S + kLambda * std::max(0.0, -last_M) : kBig;
    if (rank < best) {
      best = rank;
      best_t = t;
    }
    return g;
  }
  double constraint(const std::vector<double>& t) {
    eval(t);
    return last_ok ? -last_M : 1.0;  // 1 mm outside: a path too close to the pole
  }
};

double nlopt_objective(const std::vector<double>& t, std::vector<double>&, void* d) {
  return static_cast<NloptCtx*>(d)->objective(t);
}
double nlopt_constraint(const std::vector<double>& t, std::vector<double>&, void* d) {
  return static_cast<NloptCtx*>(d)->constraint(t);
}

void run_nlopt(nlopt::opt& opt, std::vector<double>& t) {
  double f = 0.0;
  try {
    opt.optimize(t, f);
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception&) {
    // roundoff or a stop: the best point seen is kept by the context
  }
}

double normal_angle(double b) {
  b = std::fmod(b, 2.0 * kPi);
  if (b < 0.0) b += 2.0 * kPi;
  if (b >= 2.0 * kPi) b = 0.0;
  return b;
}

Placement to_placement(Vec2 pole, const Param& q) {
  Placement pl;
  pl.C = q.hold == PoleHold::C ? q.C : norm(pole);
  pl.beta = q.hold == PoleHold::beta ? normal_angle(q.beta) : (pl.C > 0.0 ? normal_angle(std::atan2(pole.y, pole.x)) : 0.0);
  return pl;
}

std::vector<double> start_t(const Param& q, const Placement& start) {
  if (q.hold == PoleHold::C) return {start.beta};
  if (q.hold == PoleHold::beta) return {std::clamp(start.C, q.lo[0], q.hi[0])};
  const Vec2 s = start.pole();
  return {s.x, s.y};
}

// The index of the feasible value in v smaller than `below` and than every other, or -1 when there is none.
int best_feasible(const std::vector<PoleValue>& v, double below = std::numeric_limits<double>::infinity()) {
  int bi = -1;
  for (size_t i = 0; i < v.size(); ++i)
    if (v[i].feasible() && v[i].value < below && (bi < 0 || v[i].value < v[static_cast<size_t>(bi)].value))
      bi = static_cast<int>(i);
  return bi;
}

// Where the contour osculates a circle best: at a vertex (a local extremum of the curvature, or a stretch of
// constant curvature: an arc), the contour agrees with its circle of curvature to the fourth order. With the
// machine pole at that circle's centre a long stretch of contour runs at one radius, the staircase draws it as
// one arc, and the area error there depends on where that radius falls between two radial levels (period DeltaR
// as the pole moves along the normal): the deepest pits of the area error lie near these centres, far narrower
// than a global search's cells. Returns (centre, unit normal from the centre to the vertex) of up to `most`
// vertices, the centres at least 1 mm apart, inside `box`, the longest contact first.
std::vector<std::pair<Vec2, Vec2>> vertex_centres(const Curve& c, const SearchBox& box, size_t most) {
  const int n = 2048;
  const double u0 = c.u_begin(), u1 = c.u_end();
  std::vector<double> k(n + 1);
  std::vector<CurvePoint> pt(n + 1);
  for (int i = 0; i <= n; ++i) {
    pt[static_cast<size_t>(i)] = c.eval(u0 + (u1 - u0) * i / n, 2);
    const CurvePoint& q = pt[static_cast<size_t>(i)];
    const double sp = norm(q.d1);
    k[static_cast<size_t>(i)] = sp > 0.0 ? (q.d1.x * q.d2.y - q.d1.y * q.d2.x) / (sp * sp * sp) : 0.0;
  }
  struct V {
    double score;
    Vec2 centre, normal;
  };
  std::vector<V> vs;
  const double tol = 1e-9;
  for (int i = 0; i <= n; ++i) {
    const size_t I = static_cast<size_t>(i);
    const int ip = i > 0 ? i - 1 : (c.closed() ? n - 1 : -1), in = i < n ? i + 1 : (c.closed() ? 1 : -1);
    if (ip < 0 || in < 0) continue;
    const double kp = k[static_cast<size_t>(ip)], kn = k[static_cast<size_t>(in)], ki = k[I];
    if (!(std::abs(ki) > 0.0)) continue;
    const double rel = tol * std::abs(ki);
    const bool ext = (ki >= kp - rel && ki >= kn - rel) || (ki <= kp + rel && ki <= kn + rel);
    if (!ext) continue;
    const CurvePoint& q = pt[I];
    const double sp = norm(q.d1);
    const Vec2 nl{-q.d1.y / sp, q.d1.x / sp};  // left normal; the centre is at p + nl / kappa
    const Vec2 centre = q.p + (1.0 / ki) * nl;
    if (!(centre.x >= box.x0 && centre.x <= box.x1 && centre.y >= box.y0 && centre.y <= box.y1)) continue;
    // the curvature's second derivative along the arc length over kappa^3: the smaller, the longer the contour
    // stays on its circle of curvature
    const double ds = sp * (u1 - u0) / n;
    const double kss = std::abs(kp + kn - 2.0 * ki) / (ds * ds);
    vs.push_back({kss / std::abs(ki * ki * ki), centre, (1.0 / norm(q.p - centre)) * (q.p - centre)});
  }
  std::stable_sort(vs.begin(), vs.end(), [](const V& a, const V& b) { return a.score < b.score; });
  std::vector<std::pair<Vec2, Vec2>> out;
  for (const V& v : vs) {
    if (out.size() >= most) break;
    bool apart = true;
    for (const auto& o : out) apart = apart && norm(o.first - v.centre) >= 1e-3;
    if (apart) out.push_back({v.centre, v.normal});
  }
  return out;
}

}  // namespace

SearchBox search_box(const PoleProblem& p) {
  std::vector<Vec2> pts = segment_points(*p.path0, 2048);
  double x0 = pts[0].x, x1 = x0, y0 = pts[0].y, y1 = y0;
  for (const Vec2& v : pts) {
    x0 = std::min(x0, v.x), x1 = std::max(x1, v.x), y0 = std::min(y0, v.y), y1 = std::max(y1, v.y);
  }
  // a pole farther from the contour than its size only makes the error larger (the angular step covers more
  // length there): the contour's bounding box and its size again on every side, within r_max of all of it
  const double s = std::max({x1 - x0, y1 - y0, 1e-3});
  SearchBox b{x0 - s, x1 + s, y0 - s, y1 + s};
  if (p.grid.r_max) {
    const double R = *p.grid.r_max;
    const SearchBox w{x1 - R, x0 + R, y1 - R, y0 + R};
    if (!(w.x1 > w.x0) || !(w.y1 > w.y0))
      throw InputError("the contour cannot fit in the work area: it spans " + mm(x1 - x0) + " by " + mm(y1 - y0) +
                       ", more than twice r_max = " + mm(R));
    // (the torque objectives keep the whole work area: a far pole can balance the drives better)
    b = is_torque_objective(p.objective)
            ? w
            : SearchBox{std::max(b.x0, w.x0), std::min(b.x1, w.x1), std::max(b.y0, w.y0), std::min(b.y1, w.y1)};
  }
  return b;
}

namespace {

// The balanced-torque and worst-ratio objectives: smooth in the large and without the area error's fine structure,
// but a maximum along the path (kinks where the place of the maximum jumps) whose minimum often lies on the
// work area's boundary. Stages: a lattice over the search box (no basin wider than two cells is missed), DIRECT-L
// with the penalty, COBYLA with the margin as constraint from the three best separated points, and a pattern
// search (axes and diagonals, so that it can slide along a curved boundary) from the best point down to 1 um.
void torque_search(Search& s, const Param& q, const PoleProblem& p, const std::vector<double>& t0,
                   const PlacementOptions& o, PlacementResult& res) {
  const size_t dim = static_cast<size_t>(q.dim());
  const int E = o.max_evaluations > 0 ? o.max_evaluations : (dim == 2 ? 2000 : 400);
  s.set_budget(E);
  const bool local = !o.local_starts.empty();
  // 1. lattice, a third of the budget (local: its spacing only, that of a 24 x 24 survey, for the steps)
  const int n = local ? 24
                      : (dim == 2 ? std::max(4, static_cast<int>(std::floor(std::sqrt(E / 3.0)))) : std::max(8, E / 3));
  std::vector<double> cell(dim);
  for (size_t i = 0; i < dim; ++i) cell[i] = (q.hi[i] - q.lo[i]) / n;
  std::vector<std::vector<double>> starts;
  if (local) {
    for (const Placement& pl : o.local_starts) starts.push_back(start_t(q, pl));
  } else {
    std::vector<std::vector<double>> lat;
    if (dim == 2) {
      for (int iy = 0; iy < n; ++iy)
        for (int ix = 0; ix < n; ++ix) lat.push_back({q.lo[0] + cell[0] * (ix + 0.5), q.lo[1] + cell[1] * (iy + 0.5)});
    } else {
      for (int i = 0; i < n; ++i) lat.push_back({q.lo[0] + cell[0] * (i + 0.5)});
    }
    {
      const int before = s.evaluations();
      s.exact(lat);
      res.stages.push_back({"lattice (" + std::to_string(n) + (dim == 2 ? " x " + std::to_string(n) : "") + ")",
                            s.evaluations() - before, s.have() ? s.best().v.value : 0.0});
    }
    std::vector<Candidate> ranked = s.feasible_seen();
    // 2. global: DIRECT-L on the penalised objective
    NloptCtx g{&s, &p, true, {}, 0, 0, false, std::numeric_limits<double>::infinity(), {}};
    {
      nlopt::opt opt(nlopt::GN_DIRECT_L, static_cast<unsigned>(dim));
      opt.set_lower_bounds(q.lo);
      opt.set_upper_bounds(q.hi);
      opt.set_min_objective(nlopt_objective, &g);
      opt.set_maxeval(std::max(10, E / 4));
      std::vector<double> t(dim);
      for (size_t i = 0; i < dim; ++i) t[i] = 0.5 * (q.lo[i] + q.hi[i]);
      const int before = s.evaluations();
      run_nlopt(opt, t);
      res.stages.push_back({"DIRECT-L (global)", s.evaluations() - before, g.best});
    }
    // local starts: the best feasible points seen, at least two lattice cells apart
    ranked = s.feasible_seen();
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](const Candidate& a, const Candidate& b) { return a.v.value < b.v.value; });
    for (const Candidate& c : ranked) {
      bool apart = true;
      for (const auto& st : starts) {
        bool near = true;
        for (size_t i = 0; i < dim; ++i) near = near && std::abs(c.t[i] - st[i]) < 2.0 * cell[i];
        if (near) apart = false;
      }
      if (apart) starts.push_back(c.t);
      if (starts.size() == 3) break;
    }
  }
  if (starts.empty()) starts.push_back(t0);
  // 3. local: COBYLA from each start, the margin as constraint
  const double hmin = q.scale(1e-6);
  for (size_t k = 0; k < starts.size(); ++k) {
    NloptCtx l{&s, &p, false, {}, 0, 0, false, std::numeric_limits<double>::infinity(), {}};
    nlopt::opt opt(nlopt::LN_COBYLA, static_cast<unsigned>(dim));
    opt.set_lower_bounds(q.lo);
    opt.set_upper_bounds(q.hi);
    opt.set_min_objective(nlopt_objective, &l);
    opt.add_inequality_constraint(nlopt_constraint, &l, 0.0);
    opt.set_maxeval(std::max(10, local ? E / (2 * static_cast<int>(starts.size())) : E / 10));
    opt.set_initial_step(cell);
    opt.set_xtol_abs(std::vector<double>(dim, hmin));
    std::vector<double> t = starts[k];
    for (size_t i = 0; i < dim; ++i) t[i] = std::clamp(t[i], q.lo[i], q.hi[i]);
    const int before = s.evaluations();
    run_nlopt(opt, t);
    res.stages.push_back({"COBYLA (local, start " + std::to_string(k + 1) + ")", s.evaluations() - before, l.best});
  }
  // 4. polish: pattern search from the best point (axes and diagonals), steps halved down to 1 um
  if (s.have()) {
    std::vector<std::vector<double>> dirs;
    if (dim == 2) {
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          if (dx != 0 || dy != 0) dirs.push_back({static_cast<double>(dx), static_cast<double>(dy)});
    } else {
      dirs = {{-1.0}, {1.0}};
    }
    std::vector<double> t = s.best().t, h(dim);
    double f = s.best().v.value;
    for (size_t i = 0; i < dim; ++i) h[i] = 0.5 * cell[i];
    const int before = s.evaluations(), nd = static_cast<int>(dirs.size());
    const int stop = before + std::max(E - before, 24 * nd);  // at least 24 polls
    auto coarse = [&] {
      for (size_t i = 0; i < dim; ++i)
        if (h[i] >= hmin) return true;
      return false;
    };
    while (coarse() && s.evaluations() + nd <= stop) {
      std::vector<std::vector<double>> ts;
      for (const auto& d : dirs) {
        std::vector<double> x = t;
        for (size_t i = 0; i < dim; ++i) x[i] += d[i] * h[i];
        ts.push_back(x);
      }
      const std::vector<PoleValue> v = s.exact(ts);
      const int bi = best_feasible(v, f);
      if (bi >= 0) {
        t = ts[static_cast<size_t>(bi)];
        f = v[static_cast<size_t>(bi)].value;
      } else {
        for (double& x : h) x *= 0.5;
      }
    }
    res.stages.push_back({"pattern polish", s.evaluations() - before, s.best().v.value});
  }
}

}  // namespace

PlacementResult optimize_placement(const PoleProblem& p, const Placement& start, const PlacementOptions& o,
                                   const Progress& progress) {
  PlacementResult res;
  res.method = o.method != PoleMethod::automatic
                   ? o.method
                   : (p.objective == PoleObjective::f1 ? PoleMethod::hooke_jeeves : PoleMethod::nlopt);
  const bool area = p.objective == PoleObjective::area;
  const bool torque = is_torque_objective(p.objective);
  if ((torque || p.torque_limit) && !p.torque)
    throw InputError(std::string("the ") + (torque ? to_string(p.objective) : "torque-limited") +
                     " pole placement needs the machine's dynamics and the job's load");
  const int threads = o.threads > 0 ? o.threads : default_threads();
  const Param q = make_param(p, start, o.hold, threads, o.box);
  Search s(p, q, threads);
  s.set_progress(progress);
  s.keep_seen(torque);
  const double dr = p.grid.dr;

  // the job's own placement is a candidate too
  const std::vector<double> t0 = start_t(q, start);
  res.start = s.exact({t0})[0];
  if (res.start.computed) s.seed_reference(Search::scaled(p, res.start));

  if (res.method == PoleMethod::hooke_jeeves) {
    const int budget = o.max_evaluations > 0 ? o.max_evaluations : 400;
    s.set_budget(budget);
    std::vector<double> x0 = t0;
    if (!res.start.feasible()) {
      // a feasible start: the best point of a 7 x 7 (or 49-point) lattice over the search range
      std::vector<std::vector<double>> ts;
      for (int i = 0; i < 49; ++i) {
        if (q.dim() == 2)
          ts.push_back({q.lo[0] + (q.hi[0] - q.lo[0]) * ((i % 7) + 0.5) / 7, q.lo[1] + (q.hi[1] - q.lo[1]) * ((i / 7) + 0.5) / 7});
        else
          ts.push_back({q.lo[0] + (q.hi[0] - q.lo[0]) * (i + 0.5) / 49});
      }
      const auto v = s.exact(ts);
      const int bi = best_feasible(v);
      if (bi >= 0) x0 = ts[static_cast<size_t>(bi)];
      res.stages.push_back({"feasible start (7 x 7 lattice)", 49, bi >= 0 ? Search::scaled(p, v[static_cast<size_t>(bi)]) : 0.0});
    }
    HookeJeevesOptions hj;
    hj.step.assign(static_cast<size_t>(q.dim()), q.scale(o.hj_step));
    hj.min_step.assign(static_cast<size_t>(q.dim()), q.scale(o.hj_min_step));
    hj.reduction = o.hj_reduction;
    hj.acceleration = o.hj_acceleration;
    hj.max_evaluations = budget;
    auto f = [&](const std::vector<double>& t) {
      const PoleValue v = s.exact({t})[0];
      return v.feasible() ? Search::scaled(p, v) : std::numeric_limits<double>::infinity();
    };
    const HookeJeevesResult r = hooke_jeeves(f, x0, hj);
    for (const auto& b : r.bases) res.path.push_back(q.pole(b));
    res.stages.push_back({"Hooke-Jeeves", r.evaluations, r.f});
  } else if (torque) {
    torque_search(s, q, p, t0, o, res);
  } else {
    // default budget: about 1.6e7 digitized steps in all (deterministic: it depends on the job only)
    int E = o.max_evaluations;
    if (E <= 0) {
      E = area ? 240 : 600;
      if (area && res.start.computed && res.start.steps > 0)
        E = static_cast<int>(std::clamp(kAreaBudgetSteps / static_cast<double>(res.start.steps), 120.0, 4000.0));
    }
    s.set_budget(E);
    const int k = area ? kStencil : 1;
    const int n1 = std::max(10, static_cast<int>(std::lround((area ? 0.30 : 0.6) * E / k)));
    const int n2 = std::max(5, static_cast<int>(std::lround((area ? 0.15 : 0.4) * E / k)));
    const size_t dim = static_cast<size_t>(q.dim());

    // global: for the area, a coarse map of the exact area over the box, then the local stage from its best
    // separated cells (a multistart: the area's basins are a few cells wide and DIRECT-L, on a large box, can
    // settle in the wrong one); for F1, DIRECT-L on the smoothed, penalised objective
    NloptCtx g{&s, &p, true, {}, 0, 0, false, std::numeric_limits<double>::infinity(), {}};
    std::vector<std::vector<double>> starts;
    std::vector<double> cell(dim, 0.0);
    if (!o.local_starts.empty()) {
      for (const Placement& pl : o.local_starts) starts.push_back(start_t(q, pl));
    } else if (area) {
      const int G = dim == 2 ? std::clamp(static_cast<int>(std::sqrt(0.25 * E)), 3, 9)
                             : std::clamp(static_cast<int>(0.3 * E), 3, 24);
      for (size_t i = 0; i < dim; ++i) cell[i] = (q.hi[i] - q.lo[i]) / G;
      std::vector<std::vector<double>> ts;
      const int cells = dim == 2 ? G * G : G;
      for (int c = 0; c < cells; ++c) {
        if (dim == 2)
          ts.push_back({q.lo[0] + cell[0] * ((c % G) + 0.5), q.lo[1] + cell[1] * ((c / G) + 0.5)});
        else
          ts.push_back({q.lo[0] + cell[0] * (c + 0.5)});
      }
      const int before = s.evaluations();
      std::vector<PoleValue> v;  // row by row, so that the progress moves
      for (size_t r0 = 0; r0 < ts.size(); r0 += static_cast<size_t>(G)) {
        const size_t r1 = std::min(ts.size(), r0 + static_cast<size_t>(G));
        const std::vector<PoleValue> row = s.exact({ts.begin() + static_cast<std::ptrdiff_t>(r0), ts.begin() + static_cast<std::ptrdiff_t>(r1)});
        v.insert(v.end(), row.begin(), row.end());
      }
      // cells in increasing order of area (feasible ones), index as the tie-break
      std::vector<int> order;
      for (int c = 0; c < cells; ++c)
        if (v[static_cast<size_t>(c)].feasible()) order.push_back(c);
      std::sort(order.begin(), order.end(), [&](int a, int b) {
        const double va = v[static_cast<size_t>(a)].value, vb = v[static_cast<size_t>(b)].value;
        return va != vb ? va < vb : a < b;
      });
      // up to kStarts starts, each more than one cell from the others
      for (int c : order) {
        if (static_cast<int>(starts.size()) >= kStarts) break;
        bool apart = true;
        for (const auto& t : starts) {
          bool near = true;
          for (size_t i = 0; i < dim; ++i)
            near = near && std::abs(t[i] - ts[static_cast<size_t>(c)][i]) < 1.5 * cell[i];
          if (near) apart = false;
        }
        if (apart) starts.push_back(ts[static_cast<size_t>(c)]);
      }
      res.stages.push_back({"coarse map (" + std::to_string(cells) + " cells)", s.evaluations() - before,
                            order.empty() ? 0.0 : Search::scaled(p, v[static_cast<size_t>(order.front())])});
      if (starts.empty()) starts.push_back(t0);
    } else {
      nlopt::opt opt(nlopt::GN_DIRECT_L, static_cast<unsigned>(dim));
      opt.set_lower_bounds(q.lo);
      opt.set_upper_bounds(q.hi);
      opt.set_min_objective(nlopt_objective, &g);
      opt.set_maxeval(n1);
      std::vector<double> t(dim);
      for (size_t i = 0; i < dim; ++i) t[i] = 0.5 * (q.lo[i] + q.hi[i]);
      const int before = s.evaluations();
      run_nlopt(opt, t);
      res.stages.push_back({"DIRECT-L (global)", s.evaluations() - before, g.best});
      if (g.best_t.empty()) g.best_t = t0;
      starts.push_back(g.best_t);
    }

    // local: COBYLA from each start, the margin as constraint; the best point of all of them goes on
    std::vector<double> tl = starts.front();
    {
      double diag = 0.0;
      for (size_t i = 0; i < dim; ++i) diag += (q.hi[i] - q.lo[i]) * (q.hi[i] - q.lo[i]);
      diag = std::sqrt(diag);
      double step = q.hold == PoleHold::C ? std::clamp(diag / 30, q.scale(1e-3), q.scale(1e-2))
                                          : std::clamp(diag / 30, 1e-3, 1e-2);
      const bool local = !o.local_starts.empty();
      if (area && !local) step = std::min(step, 0.5 * *std::min_element(cell.begin(), cell.end()));
      const int per = std::max(5, (local ? (E - s.evaluations()) / (2 * k) : n2) / static_cast<int>(starts.size()));
      double best = std::numeric_limits<double>::infinity();
      const int before = s.evaluations();
      for (const std::vector<double>& st : starts) {
        NloptCtx l{&s, &p, false, {}, 0, 0, false, std::numeric_limits<double>::infinity(), {}};
        std::vector<double> t = st;
        nlopt::opt opt(nlopt::LN_COBYLA, static_cast<unsigned>(dim));
        opt.set_lower_bounds(q.lo);
        opt.set_upper_bounds(q.hi);
        opt.set_min_objective(nlopt_objective, &l);
        opt.add_inequality_constraint(nlopt_constraint, &l, 0.0);
        opt.set_maxeval(per);
        opt.set_initial_step(std::vector<double>(dim, step));
        opt.set_xtol_abs(std::vector<double>(dim, q.scale(dr)));
        for (size_t i = 0; i < dim; ++i) t[i] = std::clamp(t[i], q.lo[i], q.hi[i]);
        run_nlopt(opt, t);
        if (!l.best_t.empty() && l.best < best) {
          best = l.best;
          tl = l.best_t;
        }
      }
      res.stages.push_back({starts.size() > 1 ? "COBYLA (local, " + std::to_string(starts.size()) + " starts)"
                                              : std::string("COBYLA (local)"),
                            s.evaluations() - before, best});
    }

    if (area && dim == 2 && o.local_starts.empty()) {
      // the centres of curvature of the contour's vertices (vertex_centres): along each one's normal, 11 groups of
      // 4 points DeltaR / 4 apart, 0.1 mm from group to group; then 8 points over +-DeltaR / 4 about the best
      // point of them all and a compass search along its normal down to DeltaR / 1024
      const SearchBox box{q.lo[0], q.hi[0], q.lo[1], q.hi[1]};
      const std::vector<std::pair<Vec2, Vec2>> vc = vertex_centres(*p.path0, box, kVertices);
      if (!vc.empty() && E - s.evaluations() >= 40) {
        const int before = s.evaluations();
        std::vector<std::vector<double>> ts;
        std::vector<std::pair<size_t, double>> where;
        for (size_t v = 0; v < vc.size(); ++v)
          for (int i = -5; i <= 5; ++i)
            for (int ph = 0; ph < 4; ++ph) {
              const double t = 0.1e-3 * i + 0.25 * dr * ph;
              ts.push_back({vc[v].first.x + t * vc[v].second.x, vc[v].first.y + t * vc[v].second.y});
              where.push_back({v, t});
            }
        const std::vector<PoleValue> val = s.exact(ts);
        const int bi = best_feasible(val);
        if (bi >= 0) {
          const Vec2 c = vc[where[static_cast<size_t>(bi)].first].first, u = vc[where[static_cast<size_t>(bi)].first].second;
          double bt = where[static_cast<size_t>(bi)].second, bv = val[static_cast<size_t>(bi)].value;
          auto at = [&](double t) { return std::vector<double>{c.x + t * u.x, c.y + t * u.y}; };
          {
            std::vector<std::vector<double>> fs;
            std::vector<double> ss;
            for (int i = 0; i < 8; ++i) {
              ss.push_back(bt + 0.5 * dr * ((i + 0.5) / 8 - 0.5));
              fs.push_back(at(ss.back()));
            }
            const std::vector<PoleValue> fv = s.exact(fs);
            const int fi = best_feasible(fv, bv);
            if (fi >= 0) {
              bt = ss[static_cast<size_t>(fi)];
              bv = fv[static_cast<size_t>(fi)].value;
            }
          }
          double h = dr / 64.0;
          while (h >= dr / 1024.0 && E - s.evaluations() >= 2) {
            const std::vector<PoleValue> v = s.exact({at(bt - h), at(bt + h)});
            const int k2 = best_feasible(v, bv);
            if (k2 >= 0) {
              bt += k2 == 0 ? -h : h;
              bv = v[static_cast<size_t>(k2)].value;
            } else {
              h *= 0.5;
            }
          }
        }
        res.stages.push_back({"vertex centres (" + std::to_string(vc.size()) + ")", s.evaluations() - before,
                              s.have() ? Search::scaled(p, s.best().v) : 0.0});
        if (s.have()) tl = s.best().t;
      }
    }

    if (area) {
      // sampling: a fixed pattern of points in a disc of 20 DeltaR about the local optimum
      const int left = E - s.evaluations();
      const int ns = std::max(0, left * 2 / 3);
      if (ns > 0) {
        const double rho = q.scale(20.0 * dr);
        std::vector<std::vector<double>> ts;
        const double golden = kPi * (3.0 - std::sqrt(5.0));
        for (int i = 0; i < ns; ++i) {
          if (dim == 2) {
            const double r = rho * std::sqrt((i + 0.5) / ns), a = golden * i;
            ts.push_back({tl[0] + r * std::cos(a), tl[1] + r * std::sin(a)});
          } else {
            ts.push_back({tl[0] + rho * (2.0 * (i + 0.5) / ns - 1.0)});
          }
        }
        const int before = s.evaluations();
        s.exact_improving(ts);
        res.stages.push_back({"sampling (disc of 20 dR)", s.evaluations() - before,
                              s.have() ? Search::scaled(p, s.best().v) : 0.0});
      }
      // polish: compass search on the exact area from the best point, all 2 x dim polls at once
      if (s.have()) {
        std::vector<double> t = s.best().t;
        double f = s.best().v.value;
        double h = q.scale(0.5 * dr);
        const double hmin = q.scale(dr / 1024.0);
        const int before = s.evaluations();
        while (h >= hmin && E - s.evaluations() >= static_cast<int>(2 * dim)) {
          std::vector<std::vector<double>> ts;
          for (size_t i = 0; i < dim; ++i)
            for (int sg : {-1, 1}) {
              std::vector<double> x = t;
              x[i] += sg * h;
              ts.push_back(x);
            }
          const std::vector<PoleValue> v = s.exact_improving(ts);  // f is the best so far
          const int bi = best_feasible(v, f);
          if (bi >= 0) {
            t = ts[static_cast<size_t>(bi)];
            f = v[static_cast<size_t>(bi)].value;
          } else {
            h *= 0.5;
          }
        }
        res.stages.push_back({"compass polish", s.evaluations() - before, Search::scaled(p, s.best().v)});
      }
    }
  }

  if (!s.have() && s.tightest().torque_computed && p.torque_limit &&
      (s.tightest().why == "torque ratio" || s.tightest().why == "step rate")) {
    const PoleValue& t = s.tightest();
    std::ostringstream os;
    os.precision(4);
    os << "no pole position found that keeps every torque ratio within " << *p.torque_limit
       << " and every motor within its step-rate limit (at best: worst torque ratio " << t.torque.worst
       << ", step rate " << t.torque.rate_over << " times the limit): lower the speed or the load "
       << "(polarcam capacity gives the largest that pass)";
    throw InputError(os.str());
  }
  if (!s.have()) {
    std::string why = s.tightest().why.empty() ? "the path runs through the machine pole" : s.tightest().why;
    throw InputError("no pole position found that keeps the path inside the work area (the tightest constraint, " +
                     why + ", is missed by " + mm(-s.tightest().margin) + " at best)");
  }
  res.pole = s.best().pole;
  res.placement = to_placement(res.pole, q);
  res.at = s.best().v;
  res.evaluations = s.evaluations();
  if (!area) {
    PoleEvaluator ev(p);
    const PoleValue a = ev.area(res.pole);
    res.at.area_m2 = a.area_m2;
    res.at.steps = a.steps;
  }
  res.f1 = f1_chords(p.f1_points, res.pole, p.grid.dr, p.grid.dtheta).F1;
  report_progress(progress, 1.0);
  return res;
}

SearchBox feasible_box(const PoleProblem& p, const SearchBox& box, int n, int threads, const Progress& progress) {
  n = std::max(n, 2);
  std::vector<char> ok(static_cast<size_t>(n) * static_cast<size_t>(n), 0);
  Workers w(p, threads > 0 ? threads : default_threads());
  auto at = [&](int ix, int iy) {
    return Vec2{box.x0 + (box.x1 - box.x0) * ix / (n - 1), box.y0 + (box.y1 - box.y0) * iy / (n - 1)};
  };
  w.run(ok.size(), [&](size_t i, PoleEvaluator& ev) {
    const int ix = static_cast<int>(i % static_cast<size_t>(n)), iy = static_cast<int>(i / static_cast<size_t>(n));
    ok[i] = ev.geometry(at(ix, iy)).feasible() ? 1 : 0;
  }, progress);
  int x0 = n, x1 = -1, y0 = n, y1 = -1;
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix)
      if (ok[static_cast<size_t>(iy) * static_cast<size_t>(n) + static_cast<size_t>(ix)]) {
        x0 = std::min(x0, ix), x1 = std::max(x1, ix), y0 = std::min(y0, iy), y1 = std::max(y1, iy);
      }
  if (x1 < 0) return box;
  const Vec2 a = at(std::max(x0 - 1, 0), std::max(y0 - 1, 0)), b = at(std::min(x1 + 1, n - 1), std::min(y1 + 1, n - 1));
  return {a.x, b.x, a.y, b.y};
}

ObjectiveMap objective_map(const PoleProblem& p, const SearchBox& box, int nx, int ny, int threads,
                           const Progress& progress) {
  if (nx < 2 || ny < 2) throw InputError("a map needs at least 2 x 2 points");
  ObjectiveMap m;
  m.box = box;
  m.nx = nx;
  m.ny = ny;
  const size_t n = static_cast<size_t>(nx) * static_cast<size_t>(ny);
  m.value.assign(n, std::numeric_limits<double>::quiet_NaN());
  m.area.assign(n, std::numeric_limits<double>::quiet_NaN());
  m.margin.assign(n, std::numeric_limits<double>::quiet_NaN());
  Workers w(p, threads > 0 ? threads : default_threads());
  w.run(n, [&](size_t i, PoleEvaluator& ev) {
    const int ix = static_cast<int>(i % static_cast<size_t>(nx)), iy = static_cast<int>(i / static_cast<size_t>(nx));
    const Vec2 pole{box.x0 + (box.x1 - box.x0) * ix / (nx - 1), box.y0 + (box.y1 - box.y0) * iy / (ny - 1)};
    const PoleValue v = ev.evaluate_feasible(pole);
    if (!v.computed) return;
    m.margin[i] = v.margin;
    if (v.area_m2 >= 0.0) m.area[i] = v.area_m2;
    if (v.feasible()) m.value[i] = v.value;
  }, progress);
  return m;
}

Vec2 PoleSurvey::pole(int ix, int iy) const {
  return {box.x0 + (box.x1 - box.x0) * ix / std::max(1, nx - 1), box.y0 + (box.y1 - box.y0) * iy / std::max(1, ny - 1)};
}

PoleSurvey survey_poles(const PoleProblem& p, const SearchBox& box, int nx, int ny, int threads,
                        const Progress& progress) {
  if (nx < 2 || ny < 2) throw InputError("a survey needs at least 2 x 2 points");
  PoleSurvey sv;
  sv.box = box;
  sv.nx = nx;
  sv.ny = ny;
  sv.cells.resize(static_cast<size_t>(nx) * static_cast<size_t>(ny));
  Workers w(p, threads > 0 ? threads : default_threads());
  w.run(sv.cells.size(), [&](size_t i, PoleEvaluator& ev) {
    const int ix = static_cast<int>(i % static_cast<size_t>(nx)), iy = static_cast<int>(i / static_cast<size_t>(nx));
    const Vec2 pole = sv.pole(ix, iy);
    PoleValue m = ev.geometry(pole);
    if (m.computed && m.geometry_margin >= 0.0) m = ev.full(pole);
    sv.cells[i] = m;
  }, progress);
  return sv;
}

std::vector<PoleValue> evaluate_poles(const PoleProblem& p, const std::vector<Vec2>& poles, int threads,
                                      const Progress& progress) {
  std::vector<PoleValue> out(poles.size());
  Workers w(p, threads > 0 ? threads : default_threads());
  w.run(poles.size(), [&](size_t i, PoleEvaluator& ev) { out[i] = ev.full(poles[i]); }, progress);
  return out;
}

}  // namespace polarcam
