#include "job/job_optimize.hpp"

#include <initializer_list>
#include <optional>
#include <string>
#include <utility>

namespace polarcam::jobfile {
namespace {

// The value of a keyword key: the entry of `words` it names; fails with `expected` for another word.
template <class E>
std::optional<E> keyword(Section& s, const char* key, std::initializer_list<std::pair<const char*, E>> words,
                         const char* expected) {
  const std::optional<std::string> v = s.string(key);
  if (!v) return std::nullopt;
  for (const auto& [word, value] : words)
    if (*v == word) return value;
  s.fail(key, expected);
}

}  // namespace

PlacementOptions parse_optimize(Section& s) {
  PlacementOptions o;
  if (!s.present()) return o;
  if (auto v = s.string("objective"); v && *v == "pareto")
    o.pareto = true;
  else if (auto e = keyword<PoleObjective>(
               s, "objective",
               {{"area", PoleObjective::area}, {"f1", PoleObjective::f1}, {"balanced", PoleObjective::balanced}},
               "must be \"area\", \"f1\", \"balanced\" or \"pareto\""))
    o.objective = *e;
  if (auto v = s.boolean("torque_limit")) o.torque_limit = *v;
  if (auto e = keyword<PoleMethod>(s, "method", {{"nlopt", PoleMethod::nlopt}, {"hooke-jeeves", PoleMethod::hooke_jeeves}},
                                   "must be \"nlopt\" or \"hooke-jeeves\""))
    o.method = *e;
  if (auto e = keyword<PoleHold>(s, "hold", {{"none", PoleHold::none}, {"C", PoleHold::C}, {"beta", PoleHold::beta}},
                                 "must be \"none\", \"C\" or \"beta\""))
    o.hold = *e;
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
