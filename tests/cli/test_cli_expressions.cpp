// Expression contours end to end: curves that were refused as "cannot resolve the path" while their derivatives
// were finite differences now digitize, with the steps counted independently: a circle about the pole turns
// exactly one revolution of angular steps and no radial step; the limacon typed as a formula steps as the named
// limacon does, lap after lap. A step function is refused in one line naming the key.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_expressions {  // the test files of a program compile together (unity build)

using namespace polarcam::test;
using nlohmann::json;

namespace {

constexpr int kStepsPerRev = 16000;  // the thesis machine: 200-step motor, half-stepped, 40:1 worm

// A job on the thesis machine with its work area lifted, the pole at `pole` from the contour pole, and `contour`
// (the lines of [contour]).
std::string job(const std::string& contour, const std::string& pole = "1.27 cm") {
  return "[machine]\nfile = \"machines/fahim1983.toml\"\nr_min = \"0 cm\"\ntheta_min = \"none\"\ntheta_max = \"none\"\n"
         "[contour]\n" + contour + "[placement]\nC = \"" + pole + "\"\nbeta = \"0 rad\"\n[tool]\nradius = \"0 mm\"\n"
         "[motion]\nspeed = \"1.52 cm/s\"\nrule = \"nearest\"\n";
}

const std::string kNamedLimacon = "kind = \"limacon\"\na = \"5.08 cm\"\nb = \"7.62 cm\"\n";

std::string parametric_limacon(int laps) {
  std::ostringstream os;
  os.precision(17);
  os << "kind = \"parametric\"\nx = \"(b + a*cos(u))*cos(u)\"\ny = \"(b + a*cos(u))*sin(u)\"\nunit = \"cm\"\n"
     << "t_from = 0\nt_to = " << 2 * std::numbers::pi * laps << "\n[contour.constants]\na = 5.08\nb = 7.62\n";
  return os.str();
}

struct Step {
  long long t_ns;
  std::string axis;
  int dir;
  long long n, m;
};

// The steps of a tape, from `inspect --csv`.
std::vector<Step> steps_of(const std::string& tape) {
  const CliResult r = run_cli("inspect " + tape + " --csv");
  EXPECT_EQ(r.code, 0) << r.err;
  std::istringstream in(r.out);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t_ns,axis,dir,n,m");
  std::vector<Step> out;
  while (std::getline(in, line)) {
    Step s;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream f(line);
    f >> s.t_ns >> s.axis >> s.dir >> s.n >> s.m;
    out.push_back(s);
  }
  return out;
}

TEST(CliExpressions, ParametricAndPolarCircleAboutThePoleTurnOnlyTheArm) {
  Scratch sc;
  const double R = 0.020, v = 0.0152;
  for (const std::string& contour :
       {std::string("kind = \"parametric\"\nx = \"20*cos(u)\"\ny = \"20*sin(u)\"\nunit = \"mm\"\nt_from = 0\n"
                    "t_to = 6.283185307179586\n"),
        std::string("kind = \"polar\"\nr = \"20\"\nunit = \"mm\"\n")}) {
    SCOPED_TRACE(contour);
    const json j = cli_json("digitize " + sc.write("circle.toml", job(contour, "0 cm")) + " --json");
    // r = 20 mm = 787.4 radial units: between two levels all the way round, so no radial step; one revolution
    EXPECT_EQ(j["steps_radial"], 0);
    EXPECT_EQ(j["steps_angular"], kStepsPerRev);
    EXPECT_EQ(j["steps_angular_minus"], 0);
    EXPECT_NEAR(j["duration_s"].get<double>(), 2 * std::numbers::pi * R / v, 1e-9);
  }
}

// A circle computed from numbers a million times its radius (1e6 + 20 cos u - 1e6): the track's tolerances are
// those of the numbers the position comes from, so it is resolved, and steps as the circle does.
TEST(CliExpressions, CancellingTermsSetTheTolerances) {
  Scratch sc;
  const json j = cli_json(
      "digitize " +
      sc.write("circle.toml", job("kind = \"parametric\"\nx = \"1e6 + 20*cos(u) - 1e6\"\ny = \"20*sin(u)\"\n"
                                  "unit = \"mm\"\nt_from = 0\nt_to = 6.283185307179586\n",
                                  "0 cm")) +
      " --json");
  EXPECT_EQ(j["steps_radial"], 0);
  EXPECT_EQ(j["steps_angular"], kStepsPerRev);
}

// One lap, as a polar formula and as a parametric one: the named limacon's tape, step for step.
TEST(CliExpressions, LimaconFormulasStepAsTheNamedLimacon) {
  Scratch sc;
  const std::string named = sc.path("named.tape");
  cli_json("digitize " + sc.write("named.toml", job(kNamedLimacon)) + " -o " + named + " --json");
  const std::vector<Step> want = steps_of(named);
  ASSERT_GT(want.size(), 20000u);
  const std::string polar =
      "kind = \"polar\"\nr = \"b + a*cos(t)\"\nunit = \"cm\"\n[contour.constants]\na = 5.08\nb = 7.62\n";
  for (const std::string& contour : {polar, parametric_limacon(1)}) {
    SCOPED_TRACE(contour);
    const std::string tape = sc.path("formula.tape");
    cli_json("digitize " + sc.write("formula.toml", job(contour)) + " -o " + tape + " --json");
    const std::vector<Step> got = steps_of(tape);
    ASSERT_EQ(got.size(), want.size());
    for (size_t i = 0; i < got.size(); ++i) {
      ASSERT_EQ(got[i].axis, want[i].axis) << "step " << i;
      ASSERT_EQ(got[i].dir, want[i].dir) << "step " << i;
      ASSERT_EQ(got[i].n, want[i].n) << "step " << i;
      ASSERT_EQ(got[i].m, want[i].m) << "step " << i;
      ASSERT_LE(std::llabs(got[i].t_ns - want[i].t_ns), 1) << "step " << i;
    }
  }
}

// The witch of Agnesi as a formula y(x) (refused before): the named witch's tape (examples/witch.toml's placement).
TEST(CliExpressions, CartesianWitchStepsAsTheNamedWitch) {
  Scratch sc;
  const std::string head = "[machine]\nfile = \"machines/fahim1983.toml\"\n[contour]\n",
                    tail = "[placement]\nC = \"15.46 cm\"\nbeta = \"1.236 rad\"\n[motion]\nspeed = \"1.52 cm/s\"\n";
  const std::string named = sc.path("named.tape"), formula = sc.path("formula.tape");
  cli_json("digitize " +
           sc.write("named.toml", head + "kind = \"witch\"\na = \"21.59 cm\"\nx_from = \"-20.32 cm\"\n"
                                         "x_to = \"20.32 cm\"\n" + tail) +
           " -o " + named + " --json");
  cli_json("digitize " +
           sc.write("formula.toml", head + "kind = \"cartesian\"\ny = \"8*a^3/(x^2+4*a^2)\"\nunit = \"cm\"\n"
                                           "x_from = \"-20.32 cm\"\nx_to = \"20.32 cm\"\n" + tail +
                                           "[contour.constants]\na = 21.59\n") +
           " -o " + formula + " --json");
  const std::vector<Step> want = steps_of(named), got = steps_of(formula);
  ASSERT_GT(want.size(), 6000u);
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got[i].axis, want[i].axis) << "step " << i;
    ASSERT_EQ(got[i].dir, want[i].dir) << "step " << i;
    ASSERT_EQ(got[i].n, want[i].n) << "step " << i;
    ASSERT_EQ(got[i].m, want[i].m) << "step " << i;
    ASSERT_LE(std::llabs(got[i].t_ns - want[i].t_ns), 1) << "step " << i;
  }
}

// Several laps: lap k is the named limacon's lap, one revolution of the arm further (m + k 16000) and k lap
// times later (within the nanosecond each time is rounded to).
TEST(CliExpressions, ParametricLimaconLapsRepeatTheNamedLap) {
  Scratch sc;
  const std::string named = sc.path("named.tape");
  const json jn = cli_json("digitize " + sc.write("named.toml", job(kNamedLimacon)) + " -o " + named + " --json");
  const std::vector<Step> lap = steps_of(named);
  const double lap_ns = jn["duration_s"].get<double>() * 1e9;
  for (int laps : {2, 3}) {
    SCOPED_TRACE(std::to_string(laps) + " laps");
    const std::string tape = sc.path("laps.tape");
    cli_json("digitize " + sc.write("laps.toml", job(parametric_limacon(laps))) + " -o " + tape + " --json");
    const std::vector<Step> got = steps_of(tape);
    ASSERT_EQ(got.size(), laps * lap.size());
    for (int k = 0; k < laps; ++k)
      for (size_t i = 0; i < lap.size(); ++i) {
        const Step& g = got[k * lap.size() + i];
        ASSERT_EQ(g.axis, lap[i].axis) << "lap " << k << " step " << i;
        ASSERT_EQ(g.dir, lap[i].dir) << "lap " << k << " step " << i;
        ASSERT_EQ(g.n, lap[i].n) << "lap " << k << " step " << i;
        ASSERT_EQ(g.m, lap[i].m + k * kStepsPerRev) << "lap " << k << " step " << i;
        ASSERT_LE(std::abs(static_cast<double>(g.t_ns - lap[i].t_ns) - k * lap_ns), 1.0) << "lap " << k << " step " << i;
      }
  }
  // 50 and 100 laps (refused before): the counts and the time of so many named laps
  for (int laps : {50, 100}) {
    SCOPED_TRACE(std::to_string(laps) + " laps");
    const json j = cli_json("digitize " + sc.write("laps.toml", job(parametric_limacon(laps))) + " --json");
    EXPECT_EQ(j["steps_radial"], laps * jn["steps_radial"].get<long long>());
    EXPECT_EQ(j["steps_radial_plus"], laps * jn["steps_radial_plus"].get<long long>());
    EXPECT_EQ(j["steps_angular"], static_cast<long long>(laps) * kStepsPerRev);
    EXPECT_EQ(j["steps_angular_minus"], 0);
    EXPECT_NEAR(j["duration_s"].get<double>(), laps * jn["duration_s"].get<double>(), laps * 1e-9);
  }
}

TEST(CliExpressions, AStepFunctionIsRefusedNamingTheKeyAndTheFunction) {
  Scratch sc;
  const std::string contour =
      "kind = \"parametric\"\nx = \"20*cos(u)\"\ny = \"20*sign(sin(u))\"\nunit = \"mm\"\nt_from = 0\nt_to = 3\n";
  expect_bad_job(sc, "digitize", "-o", "tape", job(contour), "", "key 'contour.y'");
  const CliResult r = run_cli("digitize " + sc.write("bad.toml", job(contour)) + " --json");
  expect_one_line_error(r, "sign()");
}

// A contour that stands still (r = 0; x and y that do not depend on u) has no length: refused by every command that
// reads the job, as the named circle of radius 0 is, instead of an empty tape. (A Cartesian y(x) always has a
// length: its empty range is refused as such.)
TEST(CliExpressions, AContourWithoutLengthIsRefused) {
  Scratch sc;
  for (const std::string& contour :
       {std::string("kind = \"polar\"\nr = \"0\"\nunit = \"cm\"\n"),
        std::string("kind = \"parametric\"\nx = \"5\"\ny = \"3\"\nunit = \"mm\"\nt_from = 0\nt_to = 1\n")}) {
    SCOPED_TRACE(contour);
    expect_bad_job(sc, "digitize", "-o", "tape", job(contour, "0 cm"), "", "has no length");
    expect_bad_job(sc, "export", "-o", "svg", job(contour, "0 cm"), "--format svg", "has no length");
  }
}

// A contour that would turn some sixteen thousand times or more is a wrong unit or a damaged number: refused by the
// key at once (a spiral to 1e12 rad was refused much later as a path too close to the pole), and a rose's ratio
// beyond its limit says the limit (found by a sweep of hostile inputs).
TEST(CliExpressions, ContoursThatTurnTooOftenAreRefusedByTheirKey) {
  Scratch sc;
  expect_bad_job(sc, "digitize", "-o", "tape", job("kind = \"polar\"\nr = \"3\"\nunit = \"cm\"\nt_to = \"1e6 rad\"\n"),
                 "", "key 'contour.t_to': is beyond 1e5 rad");
  expect_bad_job(sc, "digitize", "-o", "tape",
                 job("kind = \"spiral\"\na = \"5 mm\"\npitch = \"0.3 mm\"\nt_to = \"1e12 rad\"\n", "0 cm"), "",
                 "key 'contour.t_to': is beyond 1e5 rad");
  expect_bad_job(sc, "digitize", "-o", "tape", job("kind = \"rose\"\na = \"3 cm\"\nk = \"1000001/999999\"\n", "0 cm"), "",
                 "each at most 1000000");
  const CliResult arc = run_cli("digitize " + sc.write("arc.toml", job("kind = \"path\"\nstart = [\"30 mm\", \"0 mm\"]\n"
                                                                      "[[contour.segments]]\nkind = \"arc\"\n"
                                                                      "center = [\"0 mm\", \"0 mm\"]\nsweep = \"1e9 rad\"\n",
                                                                      "0 cm")));
  expect_one_line_error(arc, "arc.toml:12: key 'contour.segments[1].sweep': is beyond 1e5 rad", 2);
}

}  // namespace

}  // namespace tu_cli_test_cli_expressions
