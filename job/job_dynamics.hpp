#pragma once
// Reading the dynamics parts of a job (docs/dynamics.md): the machine's mechanics and motors under [machine]
// (job over machine file, key by key; motors in [machine.motor] for both axes and/or [machine.radial_motor],
// [machine.angular_motor]), the process load [load] and the limits [limits]. Only job.cpp calls these.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "job/toml_section.hpp"
#include "machine/dynamics/axis_torque.hpp"
#include "machine/dynamics/load.hpp"

namespace polarcam::jobfile {

// The raw [machine] tables: the job's and the machine file's (either may be null).
struct MachineTables {
  const toml::table* job = nullptr;
  std::string job_file;
  const toml::table* file = nullptr;
  std::string machine_file;
};

// Reads the mechanics and motors when [machine] describes any of them (nullopt when it describes none); every
// missing or bad value is an InputError naming the file, line and key. Marks the keys it reads in `machine`.
std::optional<MachineModel> parse_dynamics(Section& machine, const MachineTables& tables);

// [load]: kind none | inertial | grinding | force. Absent: none.
LoadSpec parse_load(Section load);
// [limits]: safety_factor (>= 1, default 1).
double parse_limits(Section limits);

}  // namespace polarcam::jobfile

namespace polarcam {
// The motors (and mechanics) of a machine file, a TOML file whose [machine] table describes a machine; other keys of
// the table are not checked here. Throws InputError when the file has no dynamics.
MachineModel load_machine_dynamics(const std::string& path);
}  // namespace polarcam
