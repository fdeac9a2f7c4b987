#include "job/tool_file.hpp"

#include <map>

#include "cam/error.hpp"
#include "job/toml_section.hpp"

namespace polarcam {

using jobfile::Section;

process::Tool load_tool_file(const std::string& path) {
  toml::table root = jobfile::parse_toml_file(path);
  Section top(&root, path, "");
  std::map<std::string, Section> sections;
  for (const char* name : {"tool", "tooth", "cut", "structure"}) {
    const toml::node* n = top.node(name);
    if (n && !n->is_table()) top.fail(name, "expected a table [" + std::string(name) + "]");
    sections.emplace(name, Section(n ? n->as_table() : nullptr, path, name));
  }
  top.finish();
  Section& s = sections.at("tool");
  if (!s.present()) throw InputError("the table [tool] is missing (diameter, length, teeth, ...)", path);

  process::Tool t;
  t.diameter_m = s.require_quantity("diameter", dim::length);
  t.length_m = s.require_quantity("length", dim::length);
  const auto z = s.integer("teeth");
  if (!z) throw InputError("[tool]: the key 'teeth' is missing (a whole number)", path);
  if (*z < 1 || *z > 100) s.fail("teeth", "must be a whole number from 1 to 100");
  t.teeth = static_cast<int>(*z);
  t.helix_angle_rad = s.require_quantity("helix_angle", dim::angle);
  t.breaking_stress_Pa = s.require_quantity("breaking_stress", dim::pressure);
  t.youngs_modulus_Pa = s.require_quantity("youngs_modulus", dim::pressure);
  t.yield_strength_Pa = s.quantity("yield_strength", dim::pressure);
  if (auto n = s.number("safety_factor")) t.safety_factor = *n;
  t.deflection_tolerance_m = s.quantity("deflection_tolerance", dim::length);
  s.finish();

  if (Section& g = sections.at("tooth"); g.present()) {
    process::ToothGeometry tg;
    tg.thickness_m = g.require_quantity("thickness", dim::length);
    tg.width_m = g.require_quantity("width", dim::length);
    tg.length_m = g.require_quantity("length", dim::length);
    g.finish();
    t.tooth = tg;
  }
  if (Section& c = sections.at("cut"); c.present()) {
    process::MillingCut cut;
    cut.spindle_speed_rad_s = c.require_quantity("spindle_speed", dim::angular_speed);
    cut.axial_depth_m = c.require_quantity("axial_depth", dim::length);
    cut.radial_depth_m = c.require_quantity("radial_depth", dim::length);
    const auto k = c.number("material_constant");
    if (!k) throw InputError("[cut]: the key 'material_constant' is missing (hp/(in^3/min), e.g. 0.2)", path);
    cut.material_constant = *k;
    c.finish();
    t.cut = cut;
  }
  if (Section& st = sections.at("structure"); st.present()) {
    process::Structure str;
    str.re_g_min_m_per_N = st.require_quantity("re_g_min", dim::length / dim::force);
    str.cutting_stiffness_N_per_m2 = st.require_quantity("cutting_stiffness", dim::pressure);
    st.finish();
    t.structure = str;
  }

  // The model's own checks name "table.key"; here they also name the file and the line.
  try {
    process::check_tool(t);
  } catch (const InputError& e) {
    const std::string& place = e.place();
    const auto dot = place.find('.');
    if (dot != std::string::npos) {
      auto it = sections.find(place.substr(0, dot));
      if (it != sections.end()) it->second.fail(place.substr(dot + 1), e.message());
    }
    throw InputError(e.message(), path + ": " + place);
  }
  return t;
}

}  // namespace polarcam
