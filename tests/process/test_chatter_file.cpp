// The chatter structure file: plain SI numbers and quantities with units read alike; every bad key named with its
// file and line.
#include <gtest/gtest.h>

#include <string>

#include "cam/error.hpp"
#include "process/chatter_file.hpp"

namespace polarcam::test {
namespace tu_process_test_chatter_file {  // named: the test files compile together

const std::string kGood = R"([structure]
M_m = 0.03
C_m = 0.1
K_m = 120000
M_w = 0.09
C_w = 0.01
K_w = 12000
[cut]
overlap = 1
revolution_period = 0.2
)";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  s.replace(s.find(from), from.size(), to);
  return s;
}

std::string refusal(const std::string& text) {
  try {
    process::parse_chatter_toml(text, "s.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(ChatterFile, PlainNumbersAreSI) {
  const auto p = process::parse_chatter_toml(kGood, "s.toml");
  EXPECT_EQ(p.structure.M_m, 0.03);
  EXPECT_EQ(p.structure.K_w, 12000.0);
  EXPECT_EQ(p.cut.overlap, 1.0);
  EXPECT_EQ(p.cut.revolution_period, 0.2);
  EXPECT_EQ(p.cut.depth, 1e-3);
}

TEST(ChatterFile, QuantitiesWithUnits) {
  std::string t = replaced(kGood, "K_m = 120000", "K_m = \"120 kN/m\"");
  t = replaced(t, "M_w = 0.09", "M_w = \"90 g\"");
  t = replaced(t, "C_w = 0.01", "C_w = \"0.01 N s/m\"");
  t = replaced(t, "revolution_period = 0.2", "revolution_period = \"200 ms\"\ndepth_of_cut = \"0.5 mm\"");
  const auto p = process::parse_chatter_toml(t, "s.toml");
  EXPECT_DOUBLE_EQ(p.structure.K_m, 120000.0);
  EXPECT_DOUBLE_EQ(p.structure.M_w, 0.09);
  EXPECT_DOUBLE_EQ(p.structure.C_w, 0.01);
  EXPECT_DOUBLE_EQ(p.cut.revolution_period, 0.2);
  EXPECT_DOUBLE_EQ(p.cut.depth, 5e-4);
}

TEST(ChatterFile, BadKeysNamed) {
  EXPECT_EQ(refusal(replaced(kGood, "K_w = 12000\n", "")), "s.toml: key 'structure.K_w': missing: give the workpiece's stiffness (N/m)");
  EXPECT_EQ(refusal(replaced(kGood, "M_w = 0.09", "M_w = \"0.09 m\"")).rfind("s.toml:5: key 'structure.M_w': ", 0), 0u);
  EXPECT_EQ(refusal(replaced(kGood, "overlap = 1", "overlap = 1.2")), "s.toml:9: key 'cut.overlap': must be a fraction from 0 to 1");
  EXPECT_EQ(refusal(replaced(kGood, "overlap = 1", "overlap = 1e-300")),
            "s.toml:9: key 'cut.overlap': must be 0 or at least 1e-6 (below that nothing regenerates: write 0)");
  EXPECT_EQ(refusal(replaced(kGood, "K_m = 120000", "K_m = -1")), "s.toml:4: key 'structure.K_m': must be a positive stiffness");
  EXPECT_EQ(refusal(replaced(kGood, "overlap = 1", "overlap = 1\nspeed = 3")), "s.toml:10: unknown key 'cut.speed'");
  EXPECT_EQ(refusal(kGood + "[tool]\n"), "s.toml:11: unknown section [tool] (expected [structure], [cut] and an optional [suppressor])");
  EXPECT_EQ(refusal(replaced(kGood, "C_m = 0.1", "C_m = true")), "s.toml:3: key 'structure.C_m': must be a number in SI units or a quantity with units (\"0.2 s\")");
  EXPECT_EQ(refusal("[structure\n").rfind("s.toml:1:", 0), 0u);
  EXPECT_EQ(refusal(replaced(replaced(kGood, "C_m = 0.1", "C_m = 0"), "C_w = 0.01", "C_w = 0")),
            "s.toml:3: key 'structure.C_m': every mode of the structure needs some damping: give C_m or C_w above 0");
}

TEST(ChatterFile, SuppressorTable) {
  // lines 11-15 after the cut
  const std::string sup = "[suppressor]\nsample_period = \"2 ms\"\nstep_size = \"0.67 mm\"\nmax_step_rate = \"3 kHz\"\n";
  const auto p = process::parse_chatter_toml(kGood + sup, "s.toml");
  ASSERT_TRUE(p.suppressor.has_value());
  EXPECT_DOUBLE_EQ(p.suppressor->sample_period, 2e-3);
  EXPECT_DOUBLE_EQ(p.suppressor->step_size, 6.7e-4);
  EXPECT_DOUBLE_EQ(p.suppressor->max_step_rate, 3000.0);
  EXPECT_EQ(p.suppressor->source, process::ModelSource::structure);
  EXPECT_FALSE(process::parse_chatter_toml(kGood, "s.toml").suppressor.has_value());
  const auto g = process::parse_chatter_toml(
      kGood + sup + "model = \"given\"\nomega_n = \"345 rad/s\"\nzeta = 0.01\ngain = \"0.1 mm/N\"\n", "s.toml");
  EXPECT_EQ(g.suppressor->source, process::ModelSource::given);
  EXPECT_DOUBLE_EQ(g.suppressor->omega_n, 345.0);
  EXPECT_DOUBLE_EQ(g.suppressor->gain, 1e-4);
  // omega_n is an angular speed: 55 Hz is a frequency
  EXPECT_EQ(refusal(kGood + sup + "model = \"given\"\nomega_n = \"55 Hz\"\nzeta = 0.01\ngain = \"0.1 mm/N\"\n")
                .rfind("s.toml:16: key 'suppressor.omega_n': ", 0),
            0u);
  EXPECT_EQ(refusal(kGood + sup + "model = \"given\"\nomega_n = 345\nzeta = 0.01\n"),
            "s.toml: key 'suppressor.gain': missing: give the model's static gain (m/N)");
  EXPECT_EQ(refusal(kGood + sup + "model = \"best\"\n"), "s.toml:15: key 'suppressor.model': must be \"structure\", \"given\" or \"discrete\"");
  EXPECT_EQ(refusal(kGood + sup + "speed = 3\n"), "s.toml:15: unknown key 'suppressor.speed'");
  EXPECT_EQ(refusal(replaced(kGood + sup, "\"3 kHz\"", "\"300 Hz\"")),
            "s.toml:14: key 'suppressor.max_step_rate': allows no step in a sample period: give at least 1 / "
            "sample_period steps/s");
  EXPECT_EQ(refusal(replaced(kGood + sup, "\"0.67 mm\"", "\"0.67 s\"")).rfind("s.toml:13: key 'suppressor.step_size': ", 0), 0u);
}

TEST(ChatterFile, MissingFile) {
  try {
    process::read_chatter_file("/nonexistent/s.toml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "/nonexistent/s.toml");
  }
}

}  // namespace tu_process_test_chatter_file
}  // namespace polarcam::test
