#include "machine/dynamics/load.hpp"

#include <cmath>

#include "cam/error.hpp"

namespace polarcam {

const char* to_string(LoadKind k) {
  static constexpr const char* kNames[] = {"none", "inertial", "grinding", "force", "milling"};  // in the order of the enum
  return kNames[static_cast<int>(k)];
}

double GrindingSpec::K_c() const { return k_c * std::sqrt(1.0 + c1 * c1) * depth * width / wheel_speed; }

void GrindingSpec::validate() const {
  auto pos = [](double v, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v)) throw InputError(std::string("grinding: ") + what + " must be positive");
  };
  pos(k_c, "the force factor k_c");
  if (!(c1 >= 0.0) || !std::isfinite(c1)) throw InputError("grinding: the force ratio c1 must be zero or positive");
  pos(depth, "the depth of cut");
  pos(width, "the width of cut");
  pos(wheel_speed, "the wheel speed");
}

Load make_load(const LoadSpec& spec) {
  if (!(spec.mass >= 0.0) || !std::isfinite(spec.mass)) throw InputError("the added mass must be zero or positive");
  Load l;
  l.added_mass = spec.mass;
  switch (spec.kind) {
    case LoadKind::none:
    case LoadKind::inertial:
      break;
    case LoadKind::grinding: {
      spec.grinding.validate();
      // F_c = K_c V at alpha_c = atan(c1) to the surface: tangential F_c cos(alpha_c), normal F_c sin(alpha_c)
      const double Kc = spec.grinding.K_c(), alpha = std::atan(spec.grinding.c1);
      l.force_per_speed = {Kc * std::cos(alpha), Kc * std::sin(alpha)};
      break;
    }
    case LoadKind::force:
      if (!std::isfinite(spec.force.tangential) || !std::isfinite(spec.force.normal))
        throw InputError("the tool force must be finite");
      l.force_const = spec.force;
      break;
    case LoadKind::milling:
      if (!spec.milling.model)
        throw InputError("the milling load has no force model: it is bound to the job's tool path when the job is read");
      l.force_at = spec.milling.model;
      break;
  }
  return l;
}

}  // namespace polarcam
