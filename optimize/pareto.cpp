#include "optimize/pareto.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "cam/error.hpp"

namespace polarcam {
namespace {

Placement placement_of(Vec2 pole) {
  Placement pl;
  pl.C = norm(pole);
  double b = pl.C > 0.0 ? std::atan2(pole.y, pole.x) : 0.0;
  if (b < 0.0) b += 2.0 * std::numbers::pi;
  pl.beta = b;
  return pl;
}

bool complete(const PoleValue& v) {
  return v.feasible() && v.area_m2 >= 0.0 && v.torque_computed && v.torque.computed && std::isfinite(v.torque.worst);
}

}  // namespace

std::vector<Placement> starts_from(const std::vector<ParetoPoint>& known, const std::function<bool(const ParetoPoint&)>& ok,
                                   const std::function<double(const ParetoPoint&)>& key, double apart, size_t most) {
  std::vector<const ParetoPoint*> c;
  for (const ParetoPoint& x : known)
    if (complete(x.v) && ok(x)) c.push_back(&x);
  std::stable_sort(c.begin(), c.end(), [&](const ParetoPoint* a, const ParetoPoint* b) { return key(*a) < key(*b); });
  std::vector<Placement> out;
  std::vector<Vec2> taken;
  for (const ParetoPoint* x : c) {
    if (out.size() >= most) break;
    bool far = true;
    for (Vec2 t : taken) far = far && norm(x->pole - t) >= apart;
    if (!far) continue;
    taken.push_back(x->pole);
    out.push_back(x->placement);
  }
  return out;
}

std::vector<ParetoPoint> survey_points(const PoleSurvey& survey) {
  std::vector<ParetoPoint> pts;
  for (int iy = 0; iy < survey.ny; ++iy)
    for (int ix = 0; ix < survey.nx; ++ix) {
      const PoleValue& v = survey.cells[static_cast<size_t>(iy) * static_cast<size_t>(survey.nx) + static_cast<size_t>(ix)];
      const Vec2 pole = survey.pole(ix, iy);
      if (complete(v)) pts.push_back({pole, placement_of(pole), v, "survey"});
    }
  return pts;
}

double start_spacing(const PoleSurvey& s) {
  return 1.5 * std::hypot((s.box.x1 - s.box.x0) / std::max(1, s.nx - 1), (s.box.y1 - s.box.y0) / std::max(1, s.ny - 1));
}

std::vector<ParetoPoint> non_dominated(std::vector<ParetoPoint> pts) {
  std::erase_if(pts, [](const ParetoPoint& x) { return !complete(x.v); });
  std::stable_sort(pts.begin(), pts.end(), [](const ParetoPoint& a, const ParetoPoint& b) {
    if (a.v.torque.worst != b.v.torque.worst) return a.v.torque.worst < b.v.torque.worst;
    return a.v.area_m2 < b.v.area_m2;
  });
  std::vector<ParetoPoint> out;
  for (const ParetoPoint& x : pts)
    if (out.empty() || x.v.area_m2 < out.back().v.area_m2) out.push_back(x);
  return out;
}

ParetoResult pareto_front(const PoleProblem& p0, const Placement& start, const PlacementOptions& o,
                          const ParetoOptions& po, const Progress& progress) {
  if (!p0.torque) throw InputError("the Pareto front needs the machine's dynamics and the job's load");
  const int threads = po.threads > 0 ? po.threads : (o.threads > 0 ? o.threads : default_threads());
  PoleProblem p = p0;
  p.torque_limit.reset();
  p.objective = PoleObjective::area;
  ParetoResult res;
  std::vector<ParetoPoint> pts;

  // the survey: both objectives over the feasible box
  const SearchBox box = feasible_box(p, search_box(p), 41, threads);
  // progress: the survey 0-30 %, the two ends to 50 %, the levels to 95 %, the last evaluation to 100 %
  res.survey = survey_poles(p, box, std::max(2, po.survey), std::max(2, po.survey), threads,
                            progress_part(progress, 0.0, 0.3));
  res.evaluations += static_cast<int>(res.survey.cells.size());
  pts = survey_points(res.survey);

  // The searches below start from the survey's best poles (at least one and a half survey cells apart): the
  // survey has mapped the basins, so each search is local (optimize_placement's local stages).
  const double apart = start_spacing(res.survey);
  auto worst = [](const ParetoPoint& x) { return x.v.torque.worst; };
  auto area_of = [](const ParetoPoint& x) { return x.v.area_m2; };
  auto any = [](const ParetoPoint&) { return true; };

  // the two ends: least area error (the full search: it is `optimize`'s answer), least worst ratio (local, from
  // the two surveyed poles of least worst ratio; the torque objective's global search when the survey found none)
  PlacementOptions oa = o;
  oa.objective = PoleObjective::area;
  oa.method = PoleMethod::nlopt;
  oa.threads = threads;
  oa.box = box;  // the survey's: the same for the two ends, a bound for the levels' local searches
  const PlacementResult ra = optimize_placement(p, start, oa, progress_part(progress, 0.3, 0.4));
  PoleProblem pt = p;
  pt.objective = PoleObjective::torque;
  PlacementOptions ot = oa;
  ot.objective = PoleObjective::torque;
  ot.local_starts = starts_from(pts, any, worst, apart, 2);
  ot.max_evaluations = o.max_evaluations > 0 ? o.max_evaluations : (ot.local_starts.empty() ? 0 : 200);
  const PlacementResult rt = optimize_placement(pt, start, ot, progress_part(progress, 0.4, 0.5));
  res.evaluations += ra.evaluations + rt.evaluations;
  std::vector<Vec2> poles = {ra.pole, rt.pole, start.pole()};
  std::vector<std::string> sources = {"least area", "least torque", "job"};

  // epsilon-constraint: least area with the worst ratio below levels between the ends
  const std::vector<PoleValue> ends = evaluate_poles(p, {ra.pole, rt.pole}, threads);
  if (complete(ends[0]) && complete(ends[1]) && ends[0].torque.worst > ends[1].torque.worst) {
    const double lo = ends[1].torque.worst, hi = ends[0].torque.worst;
    // Each level searches locally from the two poles of least area error among those already evaluated (the
    // survey and the two ends) that meet it; a level that none meets gets the global search.
    std::vector<ParetoPoint> known = pts;
    known.push_back({ra.pole, placement_of(ra.pole), ends[0], "least area"});
    known.push_back({rt.pole, placement_of(rt.pole), ends[1], "least torque"});
    const double steps = ends[0].steps > 0 ? static_cast<double>(ends[0].steps) : 1e4;
    for (int k = 1; k <= po.levels; ++k) {
      PoleProblem pl = p;
      const double level = lo + (hi - lo) * k / (po.levels + 1);
      pl.torque_limit = level;
      PlacementOptions ol = oa;
      ol.local_starts = starts_from(known, [&](const ParetoPoint& x) { return x.v.torque.worst <= level; }, area_of,
                                    apart, 2);
      // and the pole of least area a little above the level (up to the next one): its basin may cross the level
      const double next = lo + (hi - lo) * (k + 1) / (po.levels + 1);
      if (!ol.local_starts.empty())
        for (const Placement& x : starts_from(known, [&](const ParetoPoint& x) { return x.v.torque.worst > level && x.v.torque.worst <= next; },
                                              area_of, apart, 1))
          ol.local_starts.push_back(x);
      if (po.level_evaluations > 0) {
        ol.max_evaluations = po.level_evaluations;
      } else if (o.max_evaluations > 0) {
        ol.max_evaluations = o.max_evaluations;
      } else {
        ol.max_evaluations = ol.local_starts.empty() ? static_cast<int>(std::clamp(3e6 / steps, 150.0, 1000.0))
                                                     : static_cast<int>(std::clamp(1.2e6 / steps, 60.0, 300.0));
      }
      try {
        const PlacementResult r = optimize_placement(
            pl, start, ol,
            progress_part(progress, 0.5 + 0.45 * (k - 1) / po.levels, 0.5 + 0.45 * k / po.levels));
        res.evaluations += r.evaluations;
        poles.push_back(r.pole);
        sources.push_back("level " + std::to_string(k));
      } catch (const InputError&) {
        // no pole meets this level: the front has a gap there
      }
    }
  }
  const std::vector<PoleValue> vals = evaluate_poles(p, poles, threads, progress_part(progress, 0.95, 1.0));
  for (size_t i = 0; i < poles.size(); ++i) pts.push_back({poles[i], placement_of(poles[i]), vals[i], sources[i]});
  res.front = non_dominated(std::move(pts));
  return res;
}

}  // namespace polarcam
