#pragma once
// Subcommands of the polarcam executable. Each registers itself on the CLI11 app and, when chosen, stores the
// action to run in `action`; main() runs it and maps errors to exit codes (InputError -> 2).
#include <CLI/CLI.hpp>
#include <functional>

namespace polarcam::cli {

using Action = std::function<int()>;

// Adds one subcommand to `app`; when it is chosen, stores what to run in `action`.
using Register = void(CLI::App& app, Action& action);
Register register_digitize, register_inspect, register_dda, register_play, register_controller_sim, register_error,
    register_optimize, register_analyze, register_motor, register_compare, register_capacity, register_report,
    register_export;

// The subcommands, in the order `polarcam --help` lists them.
inline constexpr Register* kCommands[] = {
    register_digitize, register_inspect, register_dda,     register_play,    register_controller_sim, register_error,
    register_optimize, register_analyze, register_motor,   register_compare, register_capacity,       register_report,
    register_export};

}  // namespace polarcam::cli
