// End to end: `polarcam monitor` on the example signals (clean, broken tooth, chatter) and on signals it generates,
// the exit statuses 0 (no event), 1 (events) and 2 (bad input, one line naming the file, line and column or the
// option); the generator's output the same bytes for the same options, and equal to the checked-in examples.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_monitor {  // the test files of a program compile together (unity build)

using namespace polarcam::test;

namespace {
const std::string kArgs = " --spindle \"600 rpm\" --teeth 4";
const std::string kGen = " --duration \"6 s\" --rate \"500 Hz\"";

nlohmann::json events_json(const std::string& args, int code) {
  const CliResult r = run_cli("monitor " + args + " --json");
  EXPECT_EQ(r.code, code) << args << ": " << r.err;
  return nlohmann::json::parse(r.out);
}
}  // namespace

TEST(CliMonitor, ExampleSignals) {
  const auto clean = events_json("examples/monitor/clean.csv" + kArgs, 0);
  EXPECT_TRUE(clean["events"].empty());
  EXPECT_EQ(clean["verdict"], "GO");
  EXPECT_EQ(clean["signal"], "force_N");
  EXPECT_NEAR(clean["tooth_frequency_hz"].get<double>(), 40.0, 1e-9);

  // a tooth breaks at 3 s: tooth 1's first pass after it starts at 3.025 s (passes every 25 ms)
  const auto broken = events_json("examples/monitor/broken_tooth.csv" + kArgs, 1);
  ASSERT_EQ(broken["events"].size(), 1u);
  EXPECT_EQ(broken["events"][0]["kind"], "breakage");
  EXPECT_GE(broken["events"][0]["time_s"].get<double>(), 3.025);
  EXPECT_LE(broken["events"][0]["time_s"].get<double>(), 3.1);
  EXPECT_EQ(broken["verdict"], "NO-GO");

  const auto chatter = events_json("examples/monitor/chatter.csv" + kArgs, 1);
  ASSERT_EQ(chatter["events"].size(), 1u);
  EXPECT_EQ(chatter["events"][0]["kind"], "chatter");
  EXPECT_NEAR(chatter["events"][0]["frequency_hz"].get<double>(), 173.0, 1.0);

  // the printed summary says the same
  const CliResult r = run_cli("monitor examples/monitor/broken_tooth.csv" + kArgs);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("breakage at 3.0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("NO-GO"), std::string::npos) << r.out;
}

TEST(CliMonitor, GeneratorIsReproducibleAndMatchesTheExamples) {
  Scratch sc;
  const std::string a = sc.path("a.csv"), b = sc.path("b.csv");
  ASSERT_EQ(run_cli("monitor --generate " + a + kArgs + kGen + " --break-at \"3 s\" --broken-tooth 1").code, 0);
  ASSERT_EQ(run_cli("monitor --generate " + b + kArgs + kGen + " --break-at \"3 s\" --broken-tooth 1").code, 0);
  EXPECT_EQ(read_file(a), read_file(b));
  EXPECT_EQ(read_file(a), read_file("examples/monitor/broken_tooth.csv"));
  const std::string c = sc.path("c.csv");
  ASSERT_EQ(run_cli("monitor --generate " + c + kArgs + kGen + " --seed 2").code, 0);
  EXPECT_NE(read_file(c), read_file("examples/monitor/clean.csv"));
  EXPECT_EQ(events_json(c + kArgs, 0)["events"].size(), 0u);
}

TEST(CliMonitor, OverloadAndGivenThreshold) {
  const auto j = events_json("examples/monitor/clean.csv" + kArgs + " --overload \"330 N\" --no-chatter", 1);
  ASSERT_EQ(j["events"].size(), 1u);
  EXPECT_EQ(j["events"][0]["kind"], "overload");
  EXPECT_TRUE(j["chatter"].is_null());
  // a threshold below the run-out's differences: the chips 1.1, 0.9, 0.9, 1.1 feeds change at every other tooth
  // period (-18 %, +22 %), so at least half the 228 periods after the learning ones exceed, merged into one event
  const auto t = events_json("examples/monitor/clean.csv" + kArgs + " --threshold 0.01 --no-chatter", 1);
  ASSERT_EQ(t["events"].size(), 1u);
  EXPECT_GE(t["events"][0]["count"].get<int>(), 114);
  EXPECT_EQ(t["breakage"]["threshold"].get<double>(), 0.01);
}

TEST(CliMonitor, EstimatedForceFromCurrentAndSpeed) {
  // a steady current and speed: Eq. 3.36's T_c = K_t I_a - B W = 0.3 * 5 - 0.196 * 2 = 1.108 N m, F_c = 1172.3 N
  Scratch sc;
  std::string text = "time_s,current_A,speed_rad_per_s\n";
  for (int k = 0; k < 2000; ++k) text += std::to_string(k * 1e-3) + ",5,2\n";
  const std::string f = sc.write("steady.csv", text);
  const auto j = events_json(f + kArgs + " --estimate-force --overload \"1170 N\" --no-chatter", 1);
  EXPECT_EQ(j["signal"], "estimated_force_N");
  ASSERT_EQ(j["events"].size(), 1u);
  EXPECT_NEAR(j["events"][0]["value"].get<double>(), 1058.0 * (0.3 * 5 - 0.196 * 2), 1e-6);
  events_json(f + kArgs + " --estimate-force --overload \"1175 N\" --no-chatter", 0);
}

TEST(CliMonitor, BadInputIsOneLine) {
  Scratch sc;
  const std::string bad = sc.write("bad.csv", "time_s,force_N\n0,1\n0.002,2\n0.004,x\n");
  auto r = run_cli("monitor " + bad + kArgs);
  expect_one_line_error(r, "bad.csv:4: column force_N");
  r = run_cli("monitor examples/monitor/clean.csv" + kArgs + " --signal current_A");
  expect_one_line_error(r, "--signal");
  r = run_cli("monitor examples/monitor/clean.csv" + kArgs + " --estimate-force");
  expect_one_line_error(r, "current_A and speed_rad_per_s");
  r = run_cli("monitor examples/monitor/clean.csv --spindle \"600 mm\" --teeth 4");
  expect_one_line_error(r, "--spindle");
  r = run_cli("monitor examples/monitor/clean.csv" + kArgs + " --rule other");
  expect_one_line_error(r, "--rule");
  r = run_cli("monitor examples/monitor/clean.csv" + kArgs + " --overload \"3 A\"");
  expect_one_line_error(r, "--overload");
  r = run_cli("monitor --spindle \"6000 rpm\" --teeth 4 examples/monitor/clean.csv");  // 12.5 -> 1.25 samples
  expect_one_line_error(r, "twice per tooth period");
  const std::string out = sc.path("never.csv");
  r = run_cli("monitor --generate " + out + kArgs + " --rate \"-5 Hz\"");
  expect_refused(r, sc, out, "--rate");
  // an option of the other mode, or one that another makes moot, is refused rather than ignored
  expect_one_line_error(run_cli("monitor examples/monitor/clean.csv" + kArgs + " --duration \"2 s\""), "--duration requires --generate");
  expect_one_line_error(run_cli("monitor examples/monitor/clean.csv" + kArgs + " --break-at \"3 s\""), "--break-at requires --generate");
  expect_refused(run_cli("monitor --generate " + out + kArgs + " --threshold 0.5"), sc, out, "--threshold");
  expect_refused(run_cli("monitor --generate " + out + kArgs + " --json"), sc, out, "--json");
  expect_one_line_error(run_cli("monitor examples/monitor/clean.csv" + kArgs + " --friction \"1 N m s/rad\""),
                        "--friction requires --estimate-force");
  expect_one_line_error(run_cli("monitor examples/monitor/clean.csv" + kArgs + " --threshold 0.5 --threshold-factor 10"),
                        "excludes --threshold-factor");
  expect_one_line_error(run_cli("monitor examples/monitor/clean.csv" + kArgs + " --no-chatter --chatter-setpoint \"10 N\""),
                        "excludes");
}

}  // namespace tu_cli_test_cli_monitor
