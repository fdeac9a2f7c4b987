#include "job/job_dynamics.hpp"

#include <deque>
#include <filesystem>
#include <set>

#include "cam/error.hpp"
#include "job/job.hpp"

namespace polarcam::jobfile {
namespace {

const char* const kTriggers[] = {
    "carriage_mass", "arm_inertia", "arm_friction_torque", "worm_factor",  "screw_factor", "worm",
    "screw",         "motor",       "radial_motor",        "angular_motor"};

const toml::table* sub(const toml::table* t, const char* key) {
  if (!t) return nullptr;
  const toml::node* n = t->get(key);
  return n ? n->as_table() : nullptr;
}

// A sub-table of [machine] ([machine.worm], [machine.screw]) with the job's keys over the machine file's. The
// sections stay at stable addresses (each refers to the one below it).
class Layers {
 public:
  explicit Layers(const MachineTables& t) : t_(t) {}
  Section* layer(const char* key) {
    const std::string name = std::string("machine.") + key;
    Section& f = store_.emplace_back(sub(t_.file, key), t_.machine_file, name, nullptr);
    return &store_.emplace_back(sub(t_.job, key), t_.job_file, name, &f);
  }

 private:
  const MachineTables& t_;
  std::deque<Section> store_;
};

double positive(Section& s, const std::string& key, const Dim& d) {
  const double v = s.require_quantity(key, d);
  if (!(v > 0.0)) s.fail(key, "must be positive");
  return v;
}

double non_negative(Section& s, const std::string& key, const Dim& d) {
  const double v = s.require_quantity(key, d);
  if (!(v >= 0.0)) s.fail(key, "must be zero or positive");
  return v;
}

const std::set<std::string> kCommonMotorKeys{"model", "max_step_rate"};
const std::set<std::string> kElectricalKeys{"energisation", "supply_voltage", "torque_constant", "voltage_constant",
                                            "rotor_teeth",  "resistance",     "inductance"};
const std::set<std::string> kCurveKeys{"steps_per_rev", "pullout_curve"};

struct RawLayer {
  const toml::table* t;
  std::string file, name;
};

std::string line_of(const RawLayer& l, const toml::node& n) {
  return l.file + (n.source().begin.line ? ":" + std::to_string(n.source().begin.line) : std::string());
}

// The motor of one axis. Its keys are looked up in [machine.<axis>_motor] of the job, then of the machine file, then
// [machine.motor] of the job, then of the machine file. The first of these tables that names a model decides it;
// tables naming another model are left out (a job can replace the machine file's electrical model by a curve).
// Every key of the tables used must belong to that model.
StepperMotor parse_motor(const MachineTables& tables, const std::string& axis, std::deque<Section>& store) {
  const std::string per_axis = axis + "_motor";
  const RawLayer all[] = {{sub(tables.job, per_axis.c_str()), tables.job_file, "machine." + per_axis},
                          {sub(tables.file, per_axis.c_str()), tables.machine_file, "machine." + per_axis},
                          {sub(tables.job, "motor"), tables.job_file, "machine.motor"},
                          {sub(tables.file, "motor"), tables.machine_file, "machine.motor"}};
  std::optional<std::string> model;
  for (const auto& l : all)
    if (l.t && !model)
      if (const toml::node* n = l.t->get("model")) {
        auto v = n->value<std::string>();
        if (!v) throw InputError(line_of(l, *n) + ": key '" + l.name + ".model': expected a string");
        model = *v;
      }
  if (!model) {
    bool any = false;
    for (const auto& l : all) any = any || l.t;
    if (!any)
      throw InputError("[machine]: no motor for the " + axis +
                       " axis: give [machine.motor] (both axes) or [machine." + per_axis + "]", tables.job_file);
    for (const auto& l : all)
      if (l.t)
        throw InputError("[" + l.name + "]: the key 'model' is missing (\"electrical\" or \"curve\")", l.file);
  }
  const std::set<std::string>* own =
      *model == "electrical" ? &kElectricalKeys : (*model == "curve" ? &kCurveKeys : nullptr);
  Section* top = nullptr;
  for (int i = 3; i >= 0; --i) {
    const RawLayer& l = all[i];
    if (!l.t) continue;
    if (const toml::node* n = l.t->get("model"); n && n->value<std::string>() != model) continue;  // another model
    if (own)
      for (const auto& [k, v] : *l.t) {
        const std::string key(k.str());
        if (kCommonMotorKeys.count(key) || own->count(key)) continue;
        const bool other = kElectricalKeys.count(key) || kCurveKeys.count(key);
        throw InputError(line_of(l, v) + ": " + (other ? "key '" : "unknown key '") + l.name + "." + key + "'" +
                         (other ? " does not apply to a motor of model \"" + *model + "\"" : ""));
      }
    top = &store.emplace_back(l.t, l.file, l.name, top);
  }
  Section& m = *top;
  std::optional<double> max_rate;
  if (m.has("max_step_rate")) max_rate = positive(m, "max_step_rate", dim::frequency);
  if (*model == "electrical") {
    ElectricalMotor e;
    if (auto en = m.string("energisation")) {
      auto p = parse_energisation(*en);
      if (!p) m.fail("energisation", "must be \"wave\" (half step), \"full_one\" or \"full_two\" (Table F.1)");
      e.energisation = *p;
    }
    e.supply_voltage = positive(m, "supply_voltage", dim::voltage);
    e.K_T = positive(m, "torque_constant", dim::torque / dim::current);
    // the voltage constant per rad/s of the shaft: "V s/rad", or "V s" read the same way
    {
      const toml::node* n = m.node("voltage_constant");
      if (!n) throw InputError("[" + m.name() + "]: the key 'voltage_constant' is missing (V s/rad)", m.file());
      auto str = n->value<std::string>();
      if (!str) m.fail("voltage_constant", "expected a quantity string such as \"0.068 V s/rad\"");
      Quantity q;
      try {
        q = parse_quantity(*str);
      } catch (const InputError& err) {
        m.fail("voltage_constant", err.what());
      }
      const Dim per_rad = dim::voltage * dim::time / dim::angle, plain = dim::voltage * dim::time;
      if (!(q.dim == per_rad || q.dim == plain)) m.fail("voltage_constant", "expected V s/rad, got " + describe(q.dim));
      if (!(q.value >= 0.0)) m.fail("voltage_constant", "must be zero or positive");
      e.K_V = q.value;
    }
    auto teeth = m.integer("rotor_teeth");
    if (!teeth) throw InputError("[" + m.name() + "]: the key 'rotor_teeth' is missing (N_s)", m.file());
    if (*teeth <= 0 || *teeth > 100000) m.fail("rotor_teeth", "must be a positive whole number");
    e.rotor_teeth = static_cast<int>(*teeth);
    e.R_a = positive(m, "resistance", dim::resistance);
    e.L_a = non_negative(m, "inductance", dim::inductance);
    return make_electrical_motor(e, max_rate);
  }
  if (*model == "curve") {
    auto spr = m.number("steps_per_rev");
    if (!spr)
      throw InputError("[" + m.name() +
                       "]: the key 'steps_per_rev' is missing (motor steps per revolution as driven)", m.file());
    if (!(*spr > 0.0)) m.fail("steps_per_rev", "must be positive");
    const toml::node* n = m.node("pullout_curve");
    if (!n)
      throw InputError("[" + m.name() +
                       "]: the key 'pullout_curve' is missing ([[\"rate\", \"torque\"], ...])", m.file());
    const toml::array* arr = n->as_array();
    if (!arr) m.fail("pullout_curve", "expected a list of [\"step rate\", \"torque\"] pairs");
    std::vector<double> rate, torque;
    for (size_t i = 0; i < arr->size(); ++i) {
      const toml::array* pr = arr->get(i)->as_array();
      const std::string row = "point " + std::to_string(i + 1);
      if (!pr || pr->size() != 2 || !pr->get(0)->is_string() || !pr->get(1)->is_string())
        m.fail("pullout_curve", row + " is not a pair of quantity strings such as [\"500 Hz\", \"0.3 N m\"]");
      try {
        rate.push_back(parse_quantity_as(*pr->get(0)->value<std::string>(), dim::frequency));
        torque.push_back(parse_quantity_as(*pr->get(1)->value<std::string>(), dim::torque));
      } catch (const InputError& err) {
        m.fail("pullout_curve", row + ": " + err.what());
      }
    }
    try {
      return make_curve_motor(PulloutCurve(rate, torque), *spr, max_rate);
    } catch (const InputError& err) {
      m.fail("pullout_curve", err.what());
    }
  }
  m.fail("model", "must be \"electrical\" (Eq. 5.17, from the motor's constants) or \"curve\" (a pull-out curve)");
}

}  // namespace

std::optional<MachineModel> parse_dynamics(Section& machine, const MachineTables& tables) {
  bool any = false;
  for (const char* k : kTriggers) any = any || machine.has(k);
  if (!any) return std::nullopt;
  for (const char* k : {"worm", "screw", "motor", "radial_motor", "angular_motor"}) {
    machine.node(k);  // read below, layer by layer
    for (const toml::table* t : {tables.job, tables.file})
      if (const toml::node* n = t ? t->get(k) : nullptr; n && !n->is_table())
        machine.fail(k, std::string("expected a table [machine.") + k + "]");
  }

  MachineModel mm;
  Mechanics& k = mm.mech;
  k.carriage_mass = non_negative(machine, "carriage_mass", dim::mass);
  k.arm_inertia = non_negative(machine, "arm_inertia", dim::inertia);
  k.arm_friction_torque = non_negative(machine, "arm_friction_torque", dim::torque);
  k.k_theta = machine.number("angular_gear_ratio").value_or(1.0);
  if (!(k.k_theta > 0.0)) machine.fail("angular_gear_ratio", "must be positive");
  const double gear_R = machine.number("radial_gear_ratio").value_or(1.0);
  if (!(gear_R > 0.0)) machine.fail("radial_gear_ratio", "must be positive");
  if (!machine.has("screw_lead"))
    throw InputError(tables.job_file +
                     ": [machine]: the dynamics need 'screw_lead' (carriage travel per screw revolution)");
  const double lead = positive(machine, "screw_lead", dim::length);
  k.k_R = gear_R / lead;

  Layers layers(tables);
  Section* worm = layers.layer("worm");
  if (machine.has("worm_factor")) {
    if (worm->present()) machine.fail("worm_factor", "give either 'worm_factor' or a [machine.worm] table, not both");
    k.K1 = *machine.number("worm_factor");
    if (!(k.K1 > 0.0)) machine.fail("worm_factor", "must be positive");
  } else if (worm->present()) {
    WormGeometry g;
    g.worm_pitch_radius = positive(*worm, "worm_pitch_radius", dim::length);
    g.gear_pitch_radius = positive(*worm, "gear_pitch_radius", dim::length);
    g.pressure_angle = worm->require_quantity("pressure_angle", dim::angle);
    g.lead_angle = worm->quantity("lead_angle", dim::angle);
    if (!worm->has("friction"))
      throw InputError(worm->file() + ": [machine.worm]: the key 'friction' is missing (mu_1)");
    g.friction = *worm->number("friction");
    try {
      k.K1 = worm_factor(g, k.k_theta);
    } catch (const InputError& e) {
      worm->fail_section(e.what());
    }
    worm->finish();
  } else {
    throw InputError("[machine]: give 'worm_factor' (K1) or a [machine.worm] table (Eq. 5.12)", tables.job_file);
  }

  Section* screw = layers.layer("screw");
  if (machine.has("screw_factor")) {
    if (screw->present())
      machine.fail("screw_factor", "give either 'screw_factor' or a [machine.screw] table, not both");
    k.K2 = positive(machine, "screw_factor", dim::length);
  } else if (screw->present()) {
    ScrewGeometry g;
    g.lead = lead;
    g.mean_radius = positive(*screw, "mean_radius", dim::length);
    g.thread_half_angle = screw->require_quantity("thread_half_angle", dim::angle);
    g.helix_angle = screw->quantity("helix_angle", dim::angle);
    if (!screw->has("friction"))
      throw InputError(screw->file() + ": [machine.screw]: the key 'friction' is missing (mu_2)");
    g.friction = *screw->number("friction");
    try {
      k.K2 = screw_factor(g);
    } catch (const InputError& e) {
      screw->fail_section(e.what());
    }
    screw->finish();
  } else {
    throw InputError("[machine]: give 'screw_factor' (K2) or a [machine.screw] table (Eq. 5.14)", tables.job_file);
  }
  try {
    k.validate();
  } catch (const InputError& e) {
    machine.fail_section(e.what());
  }

  // motors: per-axis tables over the shared [machine.motor]
  std::deque<Section> store;
  mm.radial = parse_motor(tables, "radial", store);
  mm.angular = parse_motor(tables, "angular", store);
  return mm;
}

LoadSpec parse_load(Section s) {
  LoadSpec l;
  if (!s.present()) return l;
  const std::string kind = s.require_string("kind");
  auto mass = [&](bool required) {
    if (!required && !s.has("mass")) return 0.0;
    return non_negative(s, "mass", dim::mass);
  };
  if (kind == "none") {
    l.kind = LoadKind::none;
  } else if (kind == "inertial") {
    l.kind = LoadKind::inertial;
    l.mass = mass(true);
  } else if (kind == "grinding") {
    l.kind = LoadKind::grinding;
    l.mass = mass(false);
    GrindingSpec& g = l.grinding;
    g.k_c = positive(s, "k_c", dim::pressure);
    auto c1 = s.number("c1");
    if (!c1) throw InputError("[load]: the key 'c1' is missing (normal to tangential force ratio)", s.file());
    if (!(*c1 >= 0.0)) s.fail("c1", "must be zero or positive");
    g.c1 = *c1;
    g.depth = positive(s, "depth", dim::length);
    g.width = positive(s, "width", dim::length);
    g.wheel_speed = positive(s, "wheel_speed", dim::speed);
  } else if (kind == "force") {
    l.kind = LoadKind::force;
    l.mass = mass(false);
    l.force.tangential = s.require_quantity("tangential", dim::force);
    l.force.normal = s.quantity("normal", dim::force, 0.0);
  } else if (kind == "milling") {
    // an end mill's cut (docs/process.md, "The milling load"); the job binds the model to its path (job_milling)
    l.kind = LoadKind::milling;
    l.mass = mass(false);
    MillingLoadSpec& m = l.milling;
    std::filesystem::path tf(s.require_string("tool"));
    if (tf.is_relative()) tf = std::filesystem::path(s.file()).parent_path() / tf;
    m.tool_file = tf.lexically_normal().string();
    m.spindle_speed = positive(s, "spindle_speed", dim::angular_speed);
    m.axial_depth = positive(s, "axial_depth", dim::length);
    m.radial_width = positive(s, "radial_width", dim::length);
    m.K_t = positive(s, "K_t", dim::pressure);
    m.K_r = non_negative(s, "K_r", dim::pressure);
    if (s.has("K_a")) m.K_a = non_negative(s, "K_a", dim::pressure);
    const std::string dir = s.string("spindle_direction").value_or("cw");
    if (dir != "cw" && dir != "ccw") s.fail("spindle_direction", "must be \"cw\" (M03) or \"ccw\" (M04)");
    m.clockwise = dir == "cw";
  } else {
    s.fail("kind", "must be none, inertial, grinding, force or milling");
  }
  s.finish();
  return l;
}

double parse_limits(Section s) {
  double sf = 1.0;
  if (auto v = s.number("safety_factor")) {
    if (!(*v >= 1.0)) s.fail("safety_factor", "must be at least 1 (GO when every torque ratio <= 1/safety_factor)");
    sf = *v;
  }
  s.finish();
  return sf;
}

}  // namespace polarcam::jobfile

namespace polarcam {

MachineModel load_machine_dynamics(const std::string& path) {
  Machine m = load_machine(path);
  if (!m.dynamics) throw InputError("[machine] describes no dynamics (docs/dynamics.md)", path);
  return *std::move(m.dynamics);
}

}  // namespace polarcam
