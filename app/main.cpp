// polarcam: polar-coordinate contouring toolchain. See README.md and docs/.
#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <functional>
#include <iostream>

#include "app/cli.hpp"
#include "cam/error.hpp"
#include "cam/format.hpp"
#include "io/temp_files.hpp"

#ifndef POLARCAM_VERSION
#define POLARCAM_VERSION "0.0.0"
#endif

namespace {

// The standard output, flushed: 0, or 3 with one line when it could not be written (a full disk, a closed pipe).
int check_stdout(int status) {
  std::cout.flush();
  errno = 0;
  if (std::fflush(stdout) == 0 && !std::ferror(stdout) && std::cout.good()) return status;
  const int e = errno;
  std::fprintf(stderr, "polarcam: error: standard output: cannot write (%s)\n",
               e ? std::strerror(e) : "the output was closed or is full");
  return polarcam::exit_status(polarcam::ErrorKind::device);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace polarcam;
  // a closed pipe is a write error (exit status 3), not a silent death; an interrupt removes temporary files
  std::signal(SIGPIPE, SIG_IGN);
  remove_temporaries_on_signal();
  CLI::App app{"polarcam - contours in, exactly timed polar step tapes out"};
  app.set_version_flag("--version", std::string("polarcam ") + POLARCAM_VERSION);
  app.require_subcommand(1);
  cli::Action action;
  for (cli::Register* add : cli::kCommands) add(app, action);
  // the same exit statuses for every command, at the end of every --help
  const std::string exits =
      "Exit status: 0 success (GO), 1 computed but NO-GO (the verdict fails), 2 bad input or usage, 3 I/O or device "
      "error, 4 internal error (a bug: please report it).";
  std::function<void(CLI::App*)> add_footer = [&](CLI::App* a) {
    a->footer(exits);
    for (CLI::App* sub : a->get_subcommands([](CLI::App*) { return true; })) add_footer(sub);
  };
  add_footer(&app);
  // every command takes --quiet, so that a script can pass it to all; those that draw no progress bar ignore it
  std::function<void(CLI::App*)> add_quiet = [&](CLI::App* a) {
    for (CLI::App* sub : a->get_subcommands([](CLI::App*) { return true; })) {
      if (sub->get_option_no_throw("--quiet") == nullptr)
        sub->add_flag("--quiet")->description("no progress bar (this command draws none: taken for scripts that pass it to all)");
      add_quiet(sub);
    }
  };
  add_quiet(&app);
  // an unknown command is named as such (CLI11 would say that a subcommand is required)
  bool known_command = false;
  std::string known;
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
    known += (known.empty() ? "" : ", ") + sub->get_name();
    if (argc > 1 && sub->check_name(argv[1])) known_command = true;
  }
  if (argc > 1 && argv[1][0] != '-' && !known_command) {
    std::fprintf(stderr, "polarcam: error: unknown command '%s' (the commands: %s; polarcam --help says more)\n",
                 terminal_text(argv[1]).c_str(), known.c_str());
    return exit_status(ErrorKind::input);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // one line, as every other error: what CLI11 found, and where the command's options are described
    std::string command = "polarcam";
    for (const CLI::App* sub : app.get_subcommands()) command += " " + sub->get_name();
    std::fprintf(stderr, "polarcam: error: %s (%s --help lists the options)\n", terminal_text(e.what()).c_str(),
                 command.c_str());
    return exit_status(ErrorKind::input);
  }
  try {
    return check_stdout(action ? action() : 2);
  } catch (const Error& e) {  // the one place where an error becomes an exit status
    std::cout.flush();
    std::fprintf(stderr, "polarcam: error: %s\n", terminal_text(e.what()).c_str());
    return exit_status(e.kind());
  } catch (const std::exception& e) {
    std::cout.flush();
    std::fprintf(stderr, "polarcam: internal error: %s\n", terminal_text(e.what()).c_str());
    return exit_status(ErrorKind::internal);
  }
}
