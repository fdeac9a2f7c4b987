// End-to-end tests of `polarcam digitize` and `polarcam inspect`, including every kind of bad input: one line
// naming the file and key, exit code 2, and no output file left behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli {  // the test files of a program compile together (unity build)

using namespace polarcam::test;
using json = nlohmann::json;

namespace {

const std::string kGoodJob = cli_job("limacon.toml");

void expect_bad(const Scratch& sc, const std::string& job_text, const std::string& must_mention) {
  expect_bad_job(sc, "digitize", "-o", "tape", job_text, "", must_mention);
}

}  // namespace

TEST(Cli, DigitizeAndInspectAgree) {
  Scratch sc;
  std::string job = sc.write("lim.toml", kGoodJob), tape = sc.path("lim.tape");
  json s = cli_json("digitize " + job + " -o " + tape + " --json");
  EXPECT_EQ(s["steps_total"].get<int>(), s["steps_radial"].get<int>() + s["steps_angular"].get<int>());
  EXPECT_EQ(s["steps_angular"].get<int>(), 16000);  // the pole is inside: one full turn
  EXPECT_EQ(s["start_node"][1].get<int>() + 16000, s["end_node"][1].get<int>());
  EXPECT_EQ(s["start_node"][0], s["end_node"][0]);
  for (const char* k : {"duration_s", "path_length_m", "max_step_rate_radial_hz", "max_step_rate_angular_hz"})
    EXPECT_TRUE(s[k].is_number()) << k;

  json h = cli_json("inspect " + tape + " --json");
  EXPECT_EQ(h["steps_total"], s["steps_total"]);
  EXPECT_EQ(h["start_node"], s["start_node"]);
  EXPECT_EQ(h["end_node"], s["end_node"]);
  EXPECT_EQ(h["provenance"]["job"]["contour"]["kind"], "limacon");

  CliResult c = run_cli("inspect " + tape + " --csv");
  ASSERT_EQ(c.code, 0) << c.err;
  std::istringstream in(c.out);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t_ns,axis,dir,n,m");
  long rows = 0, n = s["start_node"][0].get<long>(), m = s["start_node"][1].get<long>();
  long long last_t = 0;
  while (std::getline(in, line)) {
    ++rows;
    long long t;
    char axis[8];
    int dir;
    long nn, mm;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lld,%7[a-z],%d,%ld,%ld", &t, axis, &dir, &nn, &mm), 5) << line;
    (std::string(axis) == "r" ? n : m) += dir;
    ASSERT_EQ(nn, n);
    ASSERT_EQ(mm, m);
    ASSERT_GE(t, last_t);
    last_t = t;
  }
  EXPECT_EQ(rows, s["steps_total"].get<long>());
}

TEST(Cli, SameJobSameBytes) {
  Scratch sc;
  std::string job = sc.write("lim.toml", kGoodJob);
  ASSERT_EQ(run_cli("digitize " + job + " -o " + sc.path("a.tape")).code, 0);
  ASSERT_EQ(run_cli("digitize " + job + " -o " + sc.path("b.tape")).code, 0);
  EXPECT_EQ(read_file(sc.path("a.tape")), read_file(sc.path("b.tape")));
  // a job file with other formatting, key order and comments describes the same job: same bytes
  std::string other = sc.write(
      "other.toml", "# same job\n" + replace(replace(kGoodJob, "a = \"5.08 cm\"\nb = \"7.62 cm\"", "b=\"7.62 cm\"   # b\na =  \"5.08 cm\""),
                                         "[tool]\nradius = \"0 mm\"\n", ""));
  ASSERT_EQ(run_cli("digitize " + other + " -o " + sc.path("c.tape")).code, 0);
  EXPECT_EQ(read_file(sc.path("a.tape")), read_file(sc.path("c.tape")));
}

TEST(Cli, BadInputGivesOneClearLine) {
  Scratch sc;
  expect_bad(sc, std::string(kGoodJob) + "[contour2]\nx = 1\n", "unknown key 'contour2'");
  // one thing changed in the good job each: from, to, what the message must mention
  const struct {
    const char *from, *to, *mention;
  } cases[] = {
      {"rule = \"nearest\"", "rule = \"nearest\"\nfoo = 3", "unknown key 'motion.foo'"},
      {"a = \"5.08 cm\"\n", "", "'a' is missing"},
      {"a = \"5.08 cm\"", "a = \"5.08 kg\"", "contour.a"},
      {"a = \"5.08 cm\"", "a = \"five cm\"", "contour.a"},
      {"a = \"5.08 cm\"", "a = \"nan cm\"", "contour.a"},
      {"a = \"5.08 cm\"", "a = nan", "contour.a"},
      {"speed = \"1.52 cm/s\"", "speed = \"0 cm/s\"", "motion.speed"},
      {"speed = \"1.52 cm/s\"", "speed = \"1.52 cm\"", "speed (m/s)"},
      // the machine pole on the limacon's point (-2.54 cm, 0)
      {"C = \"1.27 cm\"\nbeta = \"0 rad\"", "C = \"2.54 cm\"\nbeta = \"pi rad\"", "pole"},
      {"r_min = \"0 cm\"", "r_min = \"7.62 cm\"", "r_min"},
      {"theta_max = \"none\"", "theta_max = \"2.8 rad\"", "theta"},
      {"kind = \"limacon\"", "kind = \"ellipse\"", "unknown contour kind"},
      {"[motion]", "[motion", "bad.toml:"},
      {"file = \"machines/fahim1983.toml\"", "file = \"machines/nope.toml\"", "nope.toml"},
      {"radius = \"0 mm\"", "radius = \"30 mm\"", "radius"},
  };
  for (const auto& c : cases) expect_bad(sc, replace(kGoodJob, c.from, c.to), c.mention);
}

TEST(Cli, BadTapesGiveOneClearLine) {
  Scratch sc;
  std::string job = sc.write("lim.toml", kGoodJob), tape = sc.path("lim.tape");
  ASSERT_EQ(run_cli("digitize " + job + " -o " + tape).code, 0);
  std::string bytes = read_file(tape);
  sc.write("cut.tape", bytes.substr(0, bytes.size() - 10));
  CliResult r = run_cli("inspect " + sc.path("cut.tape") + " --csv");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(r.out.empty()) << "a damaged tape must not produce a partial listing";
  EXPECT_NE(r.err.find("cut.tape"), std::string::npos);
  EXPECT_NE(r.err.find("truncated"), std::string::npos) << r.err;
  sc.write("junk.tape", "hello");
  r = run_cli("inspect " + sc.path("junk.tape"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("not a polarcam tape"), std::string::npos) << r.err;
}

TEST(Cli, HelpAndUsage) {
  EXPECT_EQ(run_cli("digitize --help").code, 0);
  EXPECT_EQ(run_cli("inspect --help").code, 0);
  EXPECT_EQ(run_cli("digitize").code, 2);
  EXPECT_EQ(run_cli("frobnicate").code, 2);
}

TEST(Cli, EveryExampleDigitizes) {
  for (const char* ex : {"limacon", "witch", "serpentine", "circle", "plate"}) {
    CliResult r = run_cli(std::string("digitize ") + POLARCAM_SOURCE_DIR + "/examples/" + ex + ".toml --json");
    EXPECT_EQ(r.code, 0) << ex << ": " << r.err;
  }
}

TEST(Cli, AbsurdNumbersAreRefusedNamingTheBound) {
  Scratch sc;
  const struct {
    const char *from, *to, *mention;
  } cases[] = {
      // the limacon's path is about 0.48 m: at 1e-300 m/s it would take 1e299 s, beyond 2^62 ns
      {"speed = \"1.52 cm/s\"", "speed = \"1e-300 m/s\"", "lowest speed that fits"},
      {"speed = \"1.52 cm/s\"", "speed = \"1e20 m/s\"", "1 ns tick"},
      {"speed = \"1.52 cm/s\"", "speed = \"1e308 m/s\"", "within 1e+30 in SI units"},
      {"r_min = \"0 cm\"", "r_min = \"0 cm\"\nangular_steps_per_rev = 9223372036854775807", "machine.angular_steps_per_rev"},
      {"r_min = \"0 cm\"", "r_min = \"0 cm\"\nradial_resolution = \"1e-13 m\"", "1e-12 m"},
  };
  for (const auto& c : cases) expect_bad(sc, replace(kGoodJob, c.from, c.to), c.mention);
}

TEST(Cli, UnknownCommandsAndBadOptionsAreOneLineErrors) {
  const std::string src = POLARCAM_SOURCE_DIR;
  expect_one_line_error(run_cli("frobnicate"), "polarcam: error: unknown command 'frobnicate' (the commands: ");
  expect_one_line_error(run_cli("frobnicate"), "digitize");
  expect_one_line_error(run_cli("digitize " + src + "/examples/limacon.toml --no-such-option"),
                        "(polarcam digitize --help lists the options)");
  expect_one_line_error(run_cli("template-speed --thickness"), "polarcam: error: ");
  // check reads theta-rho patterns only, and says what to use for a drawing
  expect_one_line_error(run_cli("check " + src + "/examples/patterns/logo.svg"), "check reads theta-rho patterns (.thr)");
}

// The circle (radius 50.8 mm, its centre 203.2 mm from the pole) at 50 cm/s: the radial speed reaches the whole
// 50 cm/s where the path runs along the arm, 0.5 / 0.0000254 = 19 685 tape steps/s, 8 motor steps each on the
// thesis's machine (0.001 in, 20 turns per inch, 400 steps per turn): 157 480 steps/s against 5 500. digitize and
// preview both warn, make their output and succeed; at the job's own speed neither warns.
TEST(Cli, AMotorAboveItsStepRateIsWarnedOfByDigitizeAndPreview) {
  Scratch sc;
  const std::string job = std::string(POLARCAM_SOURCE_DIR) + "/examples/circle.toml";
  for (const std::string& cmd : {"digitize " + job + " -o " + sc.path("c.tape"), "preview " + job + " -o " + sc.path("c.svg")}) {
    SCOPED_TRACE(cmd);
    const CliResult fast = run_cli(cmd + " --speed \"50 cm/s\"");
    EXPECT_EQ(fast.code, 0) << fast.err;
    EXPECT_NE(fast.err.find("warning: the radial motor would step at 1.5748e+05 steps/s (19685 tape steps/s x 8), above "
                            "its max_step_rate of 5500 steps/s"),
              std::string::npos)
        << fast.err;
    const CliResult own = run_cli(cmd);
    EXPECT_EQ(own.code, 0) << own.err;
    EXPECT_EQ(own.err.find("warning"), std::string::npos) << own.err;
  }
}

// Every command takes --quiet, so that a script may pass it to all; a command that draws no bar prints the same.
TEST(Cli, EveryCommandTakesQuiet) {
  const std::string ex = std::string(POLARCAM_SOURCE_DIR) + "/examples/";
  for (const std::string& cmd : {"optimize-speed " + ex + "ch6/witch_inertial.toml", "capacity " + ex + "ch6/witch_inertial.toml",
                                 "simulate bands " + ex + "process/fussell_limit_cycle.toml", "limits " + ex + "process/fussell_table1.toml"}) {
    SCOPED_TRACE(cmd);
    const CliResult plain = run_cli(cmd), quiet = run_cli(cmd + " --quiet");
    EXPECT_EQ(plain.code, 0) << plain.err;
    EXPECT_EQ(quiet.code, 0) << quiet.err;
    EXPECT_EQ(quiet.out, plain.out);
  }
  const CliResult help = run_cli("--help");
  ASSERT_EQ(help.code, 0);
  // the commands as the help lists them: each one's --help names --quiet
  std::istringstream lines(help.out);
  std::string line;
  bool in_list = false;
  int commands = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("SUBCOMMANDS", 0) == 0 || line.rfind("Subcommands", 0) == 0) {
      in_list = true;
      continue;
    }
    if (!in_list || line.size() < 3 || line[0] != ' ') continue;
    std::istringstream ws(line);
    std::string name;
    ws >> name;
    if (name.empty() || name[0] == '-') continue;
    ++commands;
    const CliResult h = run_cli(name + " --help");
    EXPECT_NE(h.out.find("--quiet"), std::string::npos) << name;
  }
  EXPECT_GE(commands, 25) << help.out;
}

// Values of an option that once stood for "not given" are checked as every other value: --safety-factor 0 (each
// command that takes it) and --integral -1 were silently replaced by the job's or the drives' own.
TEST(Cli, AnOptionGivenIsCheckedWhateverItsValue) {
  const std::string ex = std::string(POLARCAM_SOURCE_DIR) + "/examples/";
  for (const std::string& cmd : {std::string("analyze"), std::string("capacity"), std::string("optimize"),
                                 std::string("optimize-speed"), std::string("report")}) {
    SCOPED_TRACE(cmd);
    const std::string out = cmd == "report" ? " -o /tmp/polarcam-never-written.html" : "";
    expect_one_line_error(run_cli(cmd + " " + ex + "ch6/witch_grinding.toml --safety-factor 0" + out),
                          "--safety-factor: must be at least 1");
  }
  expect_one_line_error(run_cli("servo --path square --drives " + ex + "drives/peng1989.toml --integral=-1 --json"),
                        "--integral: must be from 0 to 1e6");
  expect_one_line_error(
      run_cli("monitor --spindle \"600 rpm\" --teeth 4 --generate /tmp/polarcam-never-written.csv --engagement 0"),
      "--engagement");
  // motor fit: a value given is checked, whatever the machine file would have given
  Scratch sc;
  const std::string pts = sc.write("pts.csv", "rate,torque\n100,0.2\n200,0.18\n400,0.15\n800,0.1\n");
  const std::string fit = "motor fit " + pts + " --machine " + ex + "machines/fahim1983.toml";
  expect_one_line_error(run_cli(fit + " --rotor-teeth 0"), "--rotor-teeth");
  expect_one_line_error(run_cli(fit + " --supply-voltage \"0 V\""), "--supply-voltage: must be a positive voltage");
  // the A/C loop without an impact strategy watches for no impact: its peak force, not "never exceeded"
  const CliResult r = run_cli("simulate ac " + ex + "process/elbestawi_ac_sec5_7.toml --strategy none");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("no impact strategy; peak force"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("never exceeded"), std::string::npos) << r.out;
}

}  // namespace tu_cli_test_cli
