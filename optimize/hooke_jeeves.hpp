#pragma once
// Hooke and Jeeves direct search (Sec. 4.8 of A. Fahim's thesis (1983) and its subroutine HOOKE, App. E):
// exploratory moves of +-step along each coordinate from a base point, keeping each move that lowers the
// function; after a successful exploration, pattern moves x_new = x + alpha (x - x_old) followed by exploration
// while they keep succeeding; when an exploration fails, every step is multiplied by the reduction factor. Stops
// when every step is below its minimum, after max_reductions reductions, or after max_evaluations evaluations.
// Infeasible points are +infinity (never accepted).
#include <functional>
#include <vector>

namespace polarcam {

struct HookeJeevesOptions {
  std::vector<double> step;      // initial step per coordinate
  std::vector<double> min_step;  // stop when every step is below these
  double reduction = 0.5;        // BETA of HOKJEV
  double acceleration = 1.0;     // ALPHA of HOKJEV
  int max_reductions = 50;       // NKAT
  int max_evaluations = 1000;
};

struct HookeJeevesResult {
  std::vector<double> x;
  double f = 0.0;
  int evaluations = 0, reductions = 0;
  std::vector<std::vector<double>> bases;  // the successive base points, from the start
};

HookeJeevesResult hooke_jeeves(const std::function<double(const std::vector<double>&)>& f, std::vector<double> x0,
                               const HookeJeevesOptions& o);

}  // namespace polarcam
