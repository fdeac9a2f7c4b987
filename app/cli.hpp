#pragma once
// Subcommands of the polarcam executable. Each registers itself on the CLI11 app and, when chosen, stores the
// action to run in `action`; main() runs it and maps errors to exit codes (InputError -> 2).
#include <CLI/CLI.hpp>
#include <functional>

namespace polarcam::cli {

using Action = std::function<int()>;

void register_digitize(CLI::App& app, Action& action);
void register_inspect(CLI::App& app, Action& action);
void register_dda(CLI::App& app, Action& action);
void register_play(CLI::App& app, Action& action);
void register_controller_sim(CLI::App& app, Action& action);
void register_error(CLI::App& app, Action& action);
void register_optimize(CLI::App& app, Action& action);
void register_analyze(CLI::App& app, Action& action);
void register_motor(CLI::App& app, Action& action);
void register_compare(CLI::App& app, Action& action);
void register_capacity(CLI::App& app, Action& action);
void register_report(CLI::App& app, Action& action);

}  // namespace polarcam::cli
