// polarcam optimize-speed JOB.toml [--json] [--csv FILE] [--safety-factor X]
// The fastest safe speed along a job's path (docs/time-optimal.md): the time-optimal schedule within the torque
// ratios 1/SF and the machine's limits, its total time against the best constant speed at the same safety factor,
// and what limits each stretch. A constant-speed job is planned without its speed; a time-optimal job keeps its
// speed as the top speed. Exit status 0, or 1 when the schedule's own analysis is NO-GO (it should not be).
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/cli.hpp"
#include "cam/error.hpp"
#include "io/output.hpp"
#include "report/analysis_report.hpp"

namespace polarcam::cli {
namespace cmd_optimize_speed {  // named, not anonymous: the command files are compiled together (unity build)

struct Opts {
  std::string job, csv;
  bool json = false;
  SafetyFactor safety_factor;
};

int run(const Opts& o) {
  if (!o.csv.empty()) check_output_path(o.csv);
  Job job = load_job_input(o.job, PatternArgs{});
  apply_safety_factor(o.safety_factor, job);
  const PreparedDynamics prep = prepare_dynamics(job);
  const SpeedPlan plan = plan_speed(job, prep, job.load);
  const Verdict v = judge(plan.schedule.check, *job.machine.dynamics, job.safety_factor);
  if (!o.csv.empty()) write_files_atomic({{o.csv, speed_plan_csv(plan)}});
  if (o.json) {
    nlohmann::ordered_json j;
    j["job"] = job.file;
    j["safety_factor"] = job.safety_factor;
    j["path_length_m"] = prep.track.length();
    j["verdict"] = v.go ? "GO" : "NO-GO";
    const nlohmann::ordered_json p = speed_plan_json(plan);
    for (auto it = p.begin(); it != p.end(); ++it) j[it.key()] = it.value();
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << "polarcam optimize-speed " << job.file << "\n";
    std::cout << speed_plan_text(plan);
    std::cout << "  " << "verdict    " << (v.go ? "GO" : "NO-GO") << " along the schedule (safety factor "
              << job.safety_factor << ")\n";
  }
  return v.go ? 0 : 1;
}

}  // namespace cmd_optimize_speed

void register_optimize_speed(CLI::App& app, Action& action) {
  using namespace cmd_optimize_speed;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "optimize-speed",
      "The fastest safe speed along a job's path: a time-optimal schedule within the torque ratios 1/SF and the "
      "machine's limits, against the best constant speed");
  c->add_option("job", o->job, "job file (TOML) whose machine has dynamics")->required();
  c->add_flag("--json", o->json, "print the result as one JSON object");
  c->add_option("--csv", o->csv, "write the schedule at its stations (s, t, V, acceleration, binding) to this file");
  add_safety_factor_option(c, o->safety_factor);
  c->callback([o, &action] { action = [o] { return run(*o); }; });
}

}  // namespace polarcam::cli
