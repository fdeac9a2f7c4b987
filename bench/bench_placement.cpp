// Pole placement on the exact area error (default method: DIRECT-L, COBYLA, sampling, polish; default budget) for
// the three Table 4.1 contours of examples/, wall time on all cores (real time, not CPU time), and the F1 +
// Hooke-Jeeves search of the thesis for comparison.
#include <benchmark/benchmark.h>

#include <string>

#include "cam/curves.hpp"
#include "cam/toolpath.hpp"
#include "optimize/placement.hpp"

using namespace polarcam;

namespace {

struct Case {
  const char* name;
  CurvePtr contour;
  Grid grid;
  Placement start;
};

Case make_case(int which) {
  Grid g;
  g.dr = 0.0254e-3;
  g.steps_per_rev = 16000;
  g.dtheta = dtheta_from_steps(16000);
  g.r_max = 0.3302;
  switch (which) {
    case 0:  // the prototype's work area
      g.r_min = 0.0762;
      g.theta_min = 0.0;
      g.theta_max = 2.8;
      return {"witch", make_witch(0.2159, -0.2032, 0.2032), g, {0.1546, 1.236}};
    case 1:  // pole inside: r_min and the angular range lifted, as examples/limacon.toml
      return {"limacon", make_limacon(0.0508, 0.0762), g, {0.0127, 0.0}};
    default:  // only r <= r_max, as examples/serpentine.toml
      return {"serpentine", make_serpentine(0.0127, 0.0762, -0.0762, 0.0762), g, {0.0537, 4.247}};
  }
}

void run(benchmark::State& state, PoleObjective obj) {
  const Case c = make_case(static_cast<int>(state.range(0)));
  auto path0 = make_tool_path(c.contour, Placement{}, ToolSpec{}, TravelSpec{});
  PlacementResult r;
  for (auto _ : state) {
    PoleProblem p = make_pole_problem(path0, c.grid, StepRule::nearest, obj, 100, false);
    PlacementOptions o;
    o.objective = obj;
    r = optimize_placement(p, c.start, o);
  }
  state.counters["evaluations"] = r.evaluations;
  state.SetLabel(std::string(c.name) + ": C " + std::to_string(r.placement.C * 1e3) + " mm, beta " +
                 std::to_string(r.placement.beta) + ", area " + std::to_string(r.at.area_m2 * 1e6) + " mm^2");
}

void BM_OptimizeArea(benchmark::State& state) { run(state, PoleObjective::area); }
BENCHMARK(BM_OptimizeArea)->DenseRange(0, 2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

void BM_OptimizeF1HookeJeeves(benchmark::State& state) { run(state, PoleObjective::f1); }
BENCHMARK(BM_OptimizeF1HookeJeeves)->DenseRange(0, 2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
