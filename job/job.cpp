#include "job/job.hpp"

#include <cmath>
#include <filesystem>
#include <numbers>

#include "job/job_contour.hpp"
#include "job/job_optimize.hpp"
#include "job/job_dynamics.hpp"
#include "job/job_gcode.hpp"
#include "job/job_milling.hpp"
#include "job/toml_section.hpp"
#include "cam/error.hpp"
#include "digitizer/tape_file.hpp"
#include "digitizer/template_speed.hpp"

namespace polarcam {
namespace {

using jobfile::Section;
using json = nlohmann::ordered_json;

// "none" (or "unlimited") switches an optional limit off, even when a machine file sets it.
std::optional<double> limit(Section& s, const std::string& key, const Dim& d) {
  if (!s.has(key)) return std::nullopt;
  const toml::node* n = s.node(key);
  if (auto str = n->value<std::string>(); str && (*str == "none" || *str == "unlimited")) return std::nullopt;
  return s.quantity(key, d);
}

Grid parse_grid(Section& s, json& prov, std::string& name) {
  Grid g;
  name = s.string("name").value_or("");
  // radial resolution: given, or from the drive train (motor steps, microstepping, gear ratio, screw lead)
  if (auto dr = s.quantity("radial_resolution", dim::length)) {
    g.dr = *dr;
  } else if (s.has("screw_lead")) {
    double lead = s.require_quantity("screw_lead", dim::length);
    double steps = s.number("radial_motor_steps_per_rev").value_or(200);
    double micro = s.number("radial_microstepping").value_or(1);
    double gear = s.number("radial_gear_ratio").value_or(1);
    if (!(steps > 0 && micro > 0 && gear > 0)) s.fail_section("radial motor steps, microstepping and gear ratio must be positive");
    g.dr = lead / (steps * micro * gear);
  } else {
    s.fail_section("give 'radial_resolution' (e.g. \"0.001 in\") or 'screw_lead' with the radial motor's steps");
  }
  // angular resolution
  if (auto n = s.integer("angular_steps_per_rev")) {
    if (*n <= 0 || *n > kMaxStepsPerRev)
      s.fail("angular_steps_per_rev", "must be a whole number from 1 to 2^40 (1099511627776), the most a tape holds");
    g.steps_per_rev = *n;
    g.dtheta = dtheta_from_steps(*n);
  } else if (auto dt = s.quantity("angular_resolution", dim::angle)) {
    if (!(*dt > 0)) s.fail("angular_resolution", "must be positive");
    g.steps_per_rev = steps_per_rev_from_dtheta(*dt);
    g.dtheta = g.steps_per_rev > 0 ? dtheta_from_steps(g.steps_per_rev) : *dt;
  } else if (s.has("angular_motor_steps_per_rev")) {
    double steps = *s.number("angular_motor_steps_per_rev");
    double micro = s.number("angular_microstepping").value_or(1);
    double gear = s.number("angular_gear_ratio").value_or(1);
    double per_rev = steps * micro * gear;
    if (!(per_rev > 0)) s.fail_section("angular motor steps, microstepping and gear ratio must be positive");
    g.dtheta = 2.0 * std::numbers::pi / per_rev;
    g.steps_per_rev = steps_per_rev_from_dtheta(g.dtheta);
    if (g.steps_per_rev > 0) g.dtheta = dtheta_from_steps(g.steps_per_rev);
  } else {
    s.fail_section("give 'angular_steps_per_rev' (e.g. 16000), 'angular_resolution' or 'angular_motor_steps_per_rev'");
  }
  g.r_min = s.quantity("r_min", dim::length, 0.0);
  g.r_max = limit(s, "r_max", dim::length);
  g.theta_min = limit(s, "theta_min", dim::angle);
  g.theta_max = limit(s, "theta_max", dim::angle);
  g.home_r = s.quantity("home_r", dim::length, g.r_min);
  g.home_theta = s.quantity("home_theta", dim::angle, g.theta_min.value_or(0.0));
  try {
    g.validate();
  } catch (const InputError& e) {
    s.fail_section(e.what());
  }
  prov["radial_resolution_m"] = g.dr;
  prov["angular_resolution_rad"] = g.dtheta;
  prov["angular_steps_per_rev"] = g.steps_per_rev;
  prov["r_min_m"] = g.r_min;
  if (g.r_max) prov["r_max_m"] = *g.r_max;
  if (g.theta_min) {
    prov["theta_min_rad"] = *g.theta_min;
    prov["theta_max_rad"] = *g.theta_max;
  }
  prov["home_r_m"] = g.home_r;
  prov["home_theta_rad"] = g.home_theta;
  return g;
}

// The whole [machine] table, once: grid and work area, then mechanics and motors; every key accounted for.
Machine parse_machine(Section& machine, const jobfile::MachineTables& tables, json& pm) {
  Machine m;
  m.grid = parse_grid(machine, pm, m.name);
  if (!m.name.empty()) pm["name"] = m.name;
  if (auto n = machine.number("coupling")) {
    if (!std::isfinite(*n) || std::abs(*n) > 1e9) machine.fail("coupling", "must be a finite number of radial steps per revolution of the arm");
    m.coupling = *n * m.grid.dr / (2.0 * std::numbers::pi);
    pm["coupling_steps_per_rev"] = *n;
  }
  if (auto w = machine.quantity("max_angular_speed", dim::angular_speed)) {
    if (!(*w > 0.0) || !std::isfinite(*w)) machine.fail("max_angular_speed", "must be a positive angular speed (e.g. \"2 rad/s\" or \"20 rpm\")");
    m.max_angular_speed = *w;
    pm["max_angular_speed_rad_s"] = *w;
  }
  if (auto a = machine.quantity("max_acceleration", dim::acceleration)) {
    if (!(*a > 0.0) || !std::isfinite(*a)) machine.fail("max_acceleration", "must be a positive acceleration (e.g. \"0.5 m/s^2\")");
    m.max_acceleration = *a;
    pm["max_acceleration_mps2"] = *a;
  }
  if (machine.has("max_jerk"))
    machine.fail("max_jerk", "is not supported: the time-optimal schedule limits the acceleration (max_acceleration), "
                             "not its rate of change; remove the key");
  if (auto n = machine.integer("counts_per_step")) {
    if (*n < 1 || *n > (int64_t{1} << 20)) machine.fail("counts_per_step", "must be a whole number of encoder counts from 1 to 2^20 (1048576)");
    m.counts_per_step = *n;
    pm["counts_per_step"] = *n;
  }
  if (auto lift = machine.boolean("tool_lift")) {
    m.tool_lift = *lift;
    if (*lift) pm["tool_lift"] = true;
  }
  if (auto v = machine.quantity("rapid_speed", dim::speed)) {
    if (!(*v > 0.0) || !std::isfinite(*v)) machine.fail("rapid_speed", "must be a positive speed (e.g. \"100 mm/s\")");
    m.rapid_speed = *v;
    pm["rapid_speed_mps"] = *v;
  }
  if (auto v = machine.quantity("tool_dwell", dim::time)) {
    if (!(*v >= 0.0) || !(*v <= 60.0)) machine.fail("tool_dwell", "must be a time from 0 to 60 s (e.g. \"0.2 s\")");
    m.tool_dwell = *v;
    if (*v > 0.0) pm["tool_dwell_s"] = *v;
  }
  m.dynamics = jobfile::parse_dynamics(machine, tables);
  machine.finish();
  return m;
}

// The [gcode] table beside [machine] in a machine file, when there is one.
std::optional<GcodeSpec> parse_machine_gcode(const toml::table& root, const std::string& file, const Machine& m) {
  const toml::node* g = root.get("gcode");
  if (g && !g->is_table()) throw InputError("'gcode' must be a table", file + ":" + std::to_string(g->source().begin.line));
  Section gcode(g ? g->as_table() : nullptr, file, "gcode");
  return jobfile::parse_gcode(gcode, m.grid.r_max, m.coupling);
}

ToolSide parse_side(Section& s, const std::string& v) {
  if (v == "left") return ToolSide::left;
  if (v == "right") return ToolSide::right;
  if (v == "outside") return ToolSide::outside;
  if (v == "inside") return ToolSide::inside;
  s.fail("side", "must be left, right, outside or inside");
}

}  // namespace

Job load_job(const std::string& path) {
  Job job;
  job.file = path;
  const std::string base = std::filesystem::path(path).parent_path().string();
  toml::table root = jobfile::parse_toml_file(path);
  Section top(&root, path, "");

  // [machine], optionally over a machine file
  const toml::node* jm = root.get("machine");
  if (jm && !jm->is_table()) throw InputError("'machine' must be a table", path);
  Section job_machine(jm ? jm->as_table() : nullptr, path, "machine");
  top.node("machine");  // accounted for
  toml::table machine_root;
  std::optional<Section> machine_file_section;
  std::string machine_file_name;
  if (auto mf = job_machine.string("file")) {
    std::filesystem::path mp(*mf);
    if (mp.is_relative()) mp = std::filesystem::path(base) / mp;
    machine_file_name = mp.lexically_normal().string();
    try {
      machine_root = jobfile::parse_toml_file(machine_file_name);
    } catch (const InputError& e) {
      job_machine.fail("file", e.what());
    }
    const toml::node* mt = machine_root.get("machine");
    if (!mt || !mt->is_table()) throw InputError("the [machine] section is missing", machine_file_name);
    for (const auto& [k, v] : machine_root)
      if (k.str() != "machine" && k.str() != "gcode")
        throw InputError("unknown section '" + std::string(k.str()) + "'",
                         machine_file_name + ":" + std::to_string(v.source().begin.line));
    machine_file_section.emplace(mt->as_table(), machine_file_name, "machine");
  }
  Section machine(jm ? jm->as_table() : nullptr, path, "machine", machine_file_section ? &*machine_file_section : nullptr);
  if (!machine.present()) throw InputError("the [machine] section is missing", path);
  if (machine_file_section) machine.string("file");  // consumed
  json prov;
  prov["format"] = "polarcam-job/1";
  json& pm = prov["machine"];
  {
    const toml::node* fm = machine_file_section ? machine_root.get("machine") : nullptr;
    job.machine = parse_machine(
        machine, {jm ? jm->as_table() : nullptr, path, fm ? fm->as_table() : nullptr, machine_file_name}, pm);
  }
  // [gcode] of the machine file (job/job_gcode.hpp)
  if (machine_file_section) job.machine.gcode = parse_machine_gcode(machine_root, machine_file_name, job.machine);

  // [contour]
  Section contour = top.subsection("contour");
  json& pc = prov["contour"];
  job.contour = jobfile::parse_contour(contour, base, pc, job.contour_kind, job.machine.grid.r_max);

  // [placement]
  Section pl = top.subsection("placement");
  job.placement.C = pl.quantity("C", dim::length, 0.0);
  job.placement.beta = pl.quantity("beta", dim::angle, 0.0);
  pl.finish();
  prov["placement"] = {{"C_m", job.placement.C}, {"beta_rad", job.placement.beta}};

  // [tool]
  Section tool = top.subsection("tool");
  job.tool.radius = tool.quantity("radius", dim::length, 0.0);
  if (!(job.tool.radius >= 0.0)) tool.fail("radius", "must be zero or positive");
  job.tool.side = job.contour->closed() ? ToolSide::outside : ToolSide::left;
  if (auto side = tool.string("side")) job.tool.side = parse_side(tool, *side);
  tool.finish();
  static const char* side_names[] = {"left", "right", "outside", "inside"};
  prov["tool"] = {{"radius_m", job.tool.radius}, {"side", side_names[static_cast<int>(job.tool.side)]}};

  // [motion]
  Section mo = top.subsection("motion");
  if (!mo.present()) throw InputError("the [motion] section is missing", path);
  json& pmo = prov["motion"];
  const toml::node* table = mo.node("speed_profile");
  const bool named = table && table->is_string();
  const bool topt = named && table->value<std::string>() == "time-optimal";
  const bool cforce = named && table->value<std::string>() == "constant-force";
  const bool templ = named && !topt && !cforce;
  if (cforce) {
    // the milling load's force held at nominal_force, within the tool's limits and `speed` (job/job_milling)
    job.motion.speed = mo.require_quantity("speed", dim::speed);
    if (!(job.motion.speed > 0.0)) mo.fail("speed", "must be positive (the top feed the schedule may reach)");
    job.motion.nominal_force = mo.require_quantity("nominal_force", dim::force);
    if (!(job.motion.nominal_force > 0.0)) mo.fail("nominal_force", "must be a positive force");
    job.motion.entry_length = mo.quantity("entry_length", dim::length);
    if (job.motion.entry_length && !(*job.motion.entry_length >= 0.0))
      mo.fail("entry_length", "must be zero or a positive length");
    job.motion.constant_force = true;
    pmo["speed_mps"] = job.motion.speed;
    pmo["speed_profile"] = "constant-force";
    pmo["nominal_force_N"] = job.motion.nominal_force;
    if (job.motion.entry_length) pmo["entry_length_m"] = *job.motion.entry_length;
    table = nullptr;
  } else if (topt) {
    // the fastest schedule the dynamics allow, never above `speed`
    if (!job.machine.dynamics)
      mo.fail("speed_profile", "\"time-optimal\" needs a machine with dynamics (mechanics and [machine.motor])");
    job.motion.speed = mo.require_quantity("speed", dim::speed);
    if (!(job.motion.speed > 0.0)) mo.fail("speed", "must be positive (the top speed the schedule may reach)");
    job.motion.time_optimal = true;
    pmo["speed_mps"] = job.motion.speed;
    pmo["speed_profile"] = "time-optimal";
    table = nullptr;
  } else if (templ) {
    if (table->value<std::string>() != "template")
      mo.fail("speed_profile", "must be \"template\", \"time-optimal\", \"constant-force\" or a list of [\"arc length\", \"speed\"] pairs");
    job.motion.speed = mo.require_quantity("speed", dim::speed);
    if (!(job.motion.speed > 0.0)) mo.fail("speed", "must be positive");
    pmo["speed_mps"] = job.motion.speed;
    pmo["speed_profile"] = "template";
    table = nullptr;
  } else if (table) {
    const toml::array* arr = table->as_array();
    if (!arr || arr->empty()) mo.fail("speed_profile", "expected a list of [\"arc length\", \"speed\"] pairs");
    for (size_t i = 0; i < arr->size(); ++i) {
      const toml::array* pr = arr->get(i)->as_array();
      auto str = [&](size_t k) -> std::string {
        auto v = pr ? pr->get(k)->value<std::string>() : std::nullopt;
        if (!pr || pr->size() != 2 || !v) mo.fail("speed_profile", "row " + std::to_string(i + 1) + " is not a pair of quantity strings");
        return *v;
      };
      try {
        SpeedStation st{parse_quantity_as(str(0), dim::length), parse_quantity_as(str(1), dim::speed)};
        job.motion.table.push_back(st);
        pmo["speed_profile"].push_back({st.s, st.v});
      } catch (const InputError& e) {
        mo.fail("speed_profile", "row " + std::to_string(i + 1) + ": " + e.what());
      }
    }
    if (mo.has("speed")) mo.fail("speed", "give either 'speed' or 'speed_profile', not both");
  } else {
    job.motion.speed = mo.require_quantity("speed", dim::speed);
    if (!(job.motion.speed > 0.0)) mo.fail("speed", "must be positive");
    pmo["speed_mps"] = job.motion.speed;
  }
  if (auto a = mo.quantity("accel", dim::acceleration)) {
    if (!(*a > 0.0)) mo.fail("accel", "must be positive");
    if (table || templ) mo.fail("accel", "cannot be combined with 'speed_profile'");
    if (topt) mo.fail("accel", "cannot be combined with speed_profile = \"time-optimal\"; give the machine's max_acceleration");
    if (cforce) mo.fail("accel", "cannot be combined with speed_profile = \"constant-force\"; give the machine's max_acceleration");
    job.motion.accel = *a;
    pmo["accel_mps2"] = *a;
  }
  std::string rule = mo.string("rule").value_or("nearest");
  if (rule == "nearest") {
    job.motion.rule = StepRule::nearest;
  } else if (rule == "thesis") {
    job.motion.rule = StepRule::thesis;
  } else {
    mo.fail("rule", "must be \"nearest\" or \"thesis\"");
  }
  pmo["rule"] = rule;
  std::string dir = mo.string("direction").value_or("forward");
  if (dir != "forward" && dir != "reverse") mo.fail("direction", "must be \"forward\" or \"reverse\"");
  job.motion.travel.reverse = dir == "reverse";
  pmo["direction"] = dir;
  if (auto sp = mo.number("start_parameter")) {
    if (!job.contour->closed()) mo.fail("start_parameter", "applies to closed contours only");
    job.motion.travel.start_parameter = *sp;
    pmo["start_parameter"] = *sp;
  }
  mo.finish();

  // [template]: the template digitizer's rollers, for speed_profile = "template"
  Section te = top.subsection("template");
  if (te.present() && !templ)
    te.fail_section("applies only with [motion] speed_profile = \"template\"; add it there or remove [template]");
  if (templ) {
    if (!te.present())
      mo.fail("speed_profile", "\"template\" needs a [template] section with thickness and roller_radius");
    TemplateRollers tr;
    tr.thickness = te.require_quantity("thickness", dim::length);
    if (!(tr.thickness > 0.0)) te.fail("thickness", "must be a positive length");
    tr.roller_radius = te.require_quantity("roller_radius", dim::length);
    if (!(tr.roller_radius > 0.0)) te.fail("roller_radius", "must be a positive length");
    tr.side = job.tool.side;
    if (auto side = te.string("side")) tr.side = parse_side(te, *side);
    if (!job.contour->closed() && (tr.side == ToolSide::inside || tr.side == ToolSide::outside))
      te.fail("side", "the contour is open: give left or right of the direction of travel");
    te.finish();
    job.motion.rollers = tr;
    static const char* names[] = {"left", "right", "outside", "inside"};
    prov["template"] = {{"thickness_m", tr.thickness}, {"roller_radius_m", tr.roller_radius},
                        {"side", names[static_cast<int>(tr.side)]}};
  }

  // [cartesian] (optional)
  Section ca = top.subsection("cartesian");
  CartesianSpec& cs = job.cartesian;
  cs.resolution = ca.quantity("resolution", dim::length, job.machine.grid.dr);
  if (!(cs.resolution > 0.0)) ca.fail("resolution", "must be a positive length");
  cs.tolerance = ca.quantity("tolerance", dim::length, 0.25 * cs.resolution);
  if (!(cs.tolerance > 0.0)) ca.fail("tolerance", "must be a positive length");
  if (cs.tolerance < 1e-6 * cs.resolution) ca.fail("tolerance", "is less than a millionth of the resolution");
  cs.interrupt_rate = ca.quantity("interrupt_rate", dim::frequency, cs.interrupt_rate);
  if (!(cs.interrupt_rate > 0.0) || cs.interrupt_rate > 1e9) ca.fail("interrupt_rate", "must be a frequency above 0 and up to 1 GHz");
  ca.finish();
  if (ca.present())
    prov["cartesian"] = {{"resolution_m", cs.resolution}, {"tolerance_m", cs.tolerance},
                         {"interrupt_rate_hz", cs.interrupt_rate}};
  // [optimize]: read and checked here so that a job file has one set of keys for every command
  Section op = top.subsection("optimize");
  job.optimize = jobfile::parse_optimize(op);
  // [load], [limits]: read by the dynamics (polarcam analyze); they do not change the tape
  job.load = jobfile::parse_load(top.subsection("load"));
  job.safety_factor = jobfile::parse_limits(top.subsection("limits"));
  // [process]: the chatter structure, read whole here so that a bad file is refused before any work
  Section proc = top.subsection("process");
  if (auto cf = proc.string("chatter")) {
    std::filesystem::path cp(*cf);
    if (cp.is_relative()) cp = std::filesystem::path(base) / cp;
    job.chatter_file = cp.lexically_normal().string();
    try {
      job.chatter = process::read_chatter_file(job.chatter_file);
    } catch (const InputError& e) {
      proc.fail("chatter", e.what());
    }
  }
  proc.finish();
  if (cforce && job.load.kind != LoadKind::milling)
    mo.fail("speed_profile", "\"constant-force\" needs a [load] with kind = \"milling\" (the force it holds)");

  top.finish();
  if (job.load.kind == LoadKind::milling) {
    // the cut changes a constant-force job's tape: it is part of the provenance
    const MillingLoadSpec& ml = job.load.milling;
    prov["milling"] = {{"tool_file", std::filesystem::path(ml.tool_file).filename().string()},
                       {"spindle_speed_rad_s", ml.spindle_speed}, {"axial_depth_m", ml.axial_depth},
                       {"radial_width_m", ml.radial_width}, {"K_t_Pa", ml.K_t}, {"K_r_Pa", ml.K_r},
                       {"K_a_Pa", ml.K_a}, {"spindle_direction", ml.clockwise ? "cw" : "ccw"}};
  }
  job.provenance = std::move(prov);
  if (job.load.kind == LoadKind::milling) bind_milling(job);
  return job;
}

Machine load_machine(const std::string& path, json* prov) {
  if (is_tape_file(path)) throw InputError("is a step tape, not a machine file (a TOML file with a [machine] table)", path);
  toml::table root = jobfile::parse_toml_file(path);
  const toml::node* mt = root.get("machine");
  if (!mt || !mt->is_table()) throw InputError("the [machine] section is missing", path);
  Section machine(mt->as_table(), path, "machine");
  json local;
  json& pj = prov ? *prov : local;
  Machine m = parse_machine(machine, {mt->as_table(), path, nullptr, path}, pj);
  m.gcode = parse_machine_gcode(root, path, m);
  return m;
}

ToolPathPtr make_job_path(const Job& job) {
  return in_file(job.file, [&] { return make_tool_path(job.contour, job.placement, job.tool, job.motion.travel); });
}

SpeedProfilePtr make_job_profile(const Job& job, const ToolPath& path, double length) {
  // the schedule depends on the path's arc length only, not on where it is placed (job/job_milling)
  if (job.motion.constant_force) return constant_force_job_profile(job, length);
  if (!job.motion.rollers) return make_job_profile(job, length);
  const TemplateRollers& tr = *job.motion.rollers;
  return in_file(job.file, [&]() -> SpeedProfilePtr {
    const int sign = tool_side_sign(path.contour(), ToolSpec{tr.roller_radius, tr.side}, job.motion.travel);
    return make_template_speed(path, path.offset(), job.motion.speed,
                               TemplateSpec{tr.thickness, tr.roller_radius, sign}, length);
  });
}

SpeedProfilePtr make_job_profile(const Job& job, double length) {
  if (job.motion.time_optimal)
    throw InputError("[motion] speed_profile = \"time-optimal\" is not available here: it needs the dynamics of the "
                     "whole path; give 'speed'", job.file);
  if (job.motion.constant_force)
    throw InputError("[motion] speed_profile = \"constant-force\" is not available here: it follows the milling "
                     "force along the whole tool path; give 'speed'", job.file);
  if (job.motion.rollers)
    throw InputError("[motion] speed_profile = \"template\" is not available here: it follows the curvature of the "
                     "tool path; give 'speed'", job.file);
  if (!job.motion.table.empty()) return make_table_speed(job.motion.table, length);
  if (job.motion.accel) return make_trapezoid_speed(job.motion.speed, *job.motion.accel, length);
  return make_constant_speed(job.motion.speed, length);
}

}  // namespace polarcam
