#pragma once
// Runs the polarcam executable for end-to-end tests (POLARCAM_BIN): only the CLI test targets include this.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/scratch.hpp"

namespace polarcam::test {

struct CliResult {
  int code = -1;
  std::string out, err;
};

// `polarcam ARGS` (run in the directory `cwd` when given), its exit status and what it printed.
inline CliResult run_cli(const std::string& args, const std::string& cwd = "") {
  static int counter = 0;
  std::string base = "/tmp/polarcam-cli-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  std::string cmd = (cwd.empty() ? "" : "cd '" + cwd + "' && ") + std::string(POLARCAM_BIN) + " " + args + " >" +
                    base + ".out 2>" + base + ".err";
  int st = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  r.out = read_file(base + ".out");
  r.err = read_file(base + ".err");
  std::remove((base + ".out").c_str());
  std::remove((base + ".err").c_str());
  return r;
}

// The JSON a command that succeeds prints (a failed expectation naming the command when it does not; the parse of
// its empty output then throws and ends the test).
inline nlohmann::json cli_json(const std::string& args) {
  const CliResult r = run_cli(args);
  EXPECT_EQ(r.code, 0) << args << ": " << r.err;
  return nlohmann::json::parse(r.out);
}

// A command that refused bad input: exit status 2 and one line on stderr that mentions `must_mention`.
// Exit status 2 (bad input) unless told otherwise (3: device).
inline void expect_one_line_error(const CliResult& r, const std::string& must_mention, int code = 2) {
  EXPECT_EQ(r.code, code) << r.err;
  EXPECT_NE(r.err.find(must_mention), std::string::npos) << "message: " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// The same, and `output` not written and no temporary file left behind in the scratch directory.
inline void expect_refused(const CliResult& r, const Scratch& sc, const std::string& output,
                           const std::string& must_mention) {
  expect_one_line_error(r, must_mention);
  EXPECT_FALSE(std::filesystem::exists(output));
  for (auto& e : std::filesystem::directory_iterator(sc.dir))
    EXPECT_EQ(e.path().string().find(".partial"), std::string::npos) << "left behind: " << e.path();
}

// A bad job file refused: `polarcam <command> bad.toml <output_option> bad.<output_ext> <args>` exits with one line
// that mentions `must_mention` (and `names`, the file, unless empty), writes no output, leaves no temporary file.
inline void expect_bad_job(const Scratch& sc, const std::string& command, const std::string& output_option,
                           const std::string& output_ext, const std::string& job_text, const std::string& args,
                           const std::string& must_mention, const std::string& names = "bad.toml") {
  SCOPED_TRACE("expecting: " + must_mention);
  const std::string job = sc.write("bad.toml", job_text), output = sc.path("bad." + output_ext);
  std::filesystem::remove(output);
  const CliResult r = run_cli(command + " " + job + " " + output_option + " " + output + " " + args);
  expect_refused(r, sc, output, must_mention);
  if (!names.empty()) {
    EXPECT_NE(r.err.find(names), std::string::npos) << "message does not name the file: " << r.err;
  }
}

}  // namespace polarcam::test
