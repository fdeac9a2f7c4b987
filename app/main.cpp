// polarcam: polar-coordinate contouring toolchain. See README.md and docs/.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <iostream>

#include "app/cli.hpp"
#include "cam/error.hpp"

#ifndef POLARCAM_VERSION
#define POLARCAM_VERSION "0.0.0"
#endif

int main(int argc, char** argv) {
  using namespace polarcam;
  CLI::App app{"polarcam - contours in, exactly timed polar step tapes out"};
  app.set_version_flag("--version", std::string("polarcam ") + POLARCAM_VERSION);
  app.require_subcommand(1);
  cli::Action action;
  for (cli::Register* add : cli::kCommands) add(app, action);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  }
  try {
    return action ? action() : 2;
  } catch (const Error& e) {  // the one place where an error becomes an exit status
    std::cout.flush();
    std::fprintf(stderr, "polarcam: error: %s\n", e.what());
    return exit_status(e.kind());
  } catch (const std::exception& e) {
    std::cout.flush();
    std::fprintf(stderr, "polarcam: internal error: %s\n", e.what());
    return exit_status(ErrorKind::internal);
  }
}
