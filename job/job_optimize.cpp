#include "job/job_optimize.hpp"

namespace polarcam::jobfile {

PlacementOptions parse_optimize(Section& s) {
  PlacementOptions o;
  if (!s.present()) return o;
  if (auto v = s.string("objective")) {
    if (*v == "area")
      o.objective = PoleObjective::area;
    else if (*v == "f1")
      o.objective = PoleObjective::f1;
    else if (*v == "balanced")
      o.objective = PoleObjective::balanced;
    else if (*v == "pareto")
      o.pareto = true;
    else
      s.fail("objective", "must be \"area\", \"f1\", \"balanced\" or \"pareto\"");
  }
  if (auto v = s.boolean("torque_limit")) o.torque_limit = *v;
  if (auto v = s.string("method")) {
    if (*v == "nlopt")
      o.method = PoleMethod::nlopt;
    else if (*v == "hooke-jeeves")
      o.method = PoleMethod::hooke_jeeves;
    else
      s.fail("method", "must be \"nlopt\" or \"hooke-jeeves\"");
  }
  if (auto v = s.string("hold")) {
    if (*v == "none")
      o.hold = PoleHold::none;
    else if (*v == "C")
      o.hold = PoleHold::C;
    else if (*v == "beta")
      o.hold = PoleHold::beta;
    else
      s.fail("hold", "must be \"none\", \"C\" or \"beta\"");
  }
  if (auto v = s.boolean("pole_outside")) o.pole_outside = *v;
  if (auto v = s.integer("segments")) {
    if (*v < 1 || *v > 100000) s.fail("segments", "must be a whole number from 1 to 100000");
    o.segments = static_cast<int>(*v);
  }
  if (auto v = s.integer("max_evaluations")) {
    if (*v < 10 || *v > 10000000) s.fail("max_evaluations", "must be a whole number from 10 to 10000000");
    o.max_evaluations = static_cast<int>(*v);
  }
  if (auto v = s.quantity("hj_step", dim::length)) {
    if (!(*v > 0.0)) s.fail("hj_step", "must be a positive length");
    o.hj_step = *v;
  }
  if (auto v = s.quantity("hj_min_step", dim::length)) {
    if (!(*v > 0.0)) s.fail("hj_min_step", "must be a positive length");
    o.hj_min_step = *v;
  }
  if (auto v = s.number("hj_reduction")) {
    if (!(*v > 0.0 && *v < 1.0)) s.fail("hj_reduction", "must lie strictly between 0 and 1");
    o.hj_reduction = *v;
  }
  if (auto v = s.number("hj_acceleration")) {
    if (!(*v >= 0.0 && *v <= 10.0)) s.fail("hj_acceleration", "must lie between 0 and 10");
    o.hj_acceleration = *v;
  }
  if (auto v = s.integer("threads")) {
    if (*v < 0 || *v > 1024) s.fail("threads", "must be a whole number from 0 (all cores) to 1024");
    o.threads = static_cast<int>(*v);
  }
  s.finish();
  return o;
}

}  // namespace polarcam::jobfile
