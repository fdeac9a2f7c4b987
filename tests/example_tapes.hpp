#pragma once
// Tapes of the four seed examples (examples/<name>.toml on the machine examples/machines/fahim1983.toml),
// digitized in-process with the digitizer alone: the contour, pole, grid, work area and speed written out here, so
// the player, link and controller tests need no job file reader.
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "cam/curves.hpp"
#include "cam/toolpath.hpp"
#include "digitizer/digitize.hpp"
#include "digitizer/tape.hpp"
#include "tests/temp_path.hpp"

namespace polarcam::test {

struct ExampleJob {
  CurvePtr contour;
  Placement placement;
  bool whole_plane = false;  // r_min = 0 and no angular range (limacon, serpentine), else the machine's work area
};

// examples/<name>.toml: limacon, witch, serpentine or circle.
inline ExampleJob example_job(const std::string& name) {
  const double pi = std::numbers::pi;
  if (name == "limacon") return {make_limacon(0.0508, 0.0762), {0.0127, 0.0}, true};
  if (name == "witch") return {make_witch(0.2159, -0.2032, 0.2032), {0.1546, 1.236}, false};
  if (name == "serpentine") return {make_serpentine(0.0127, 0.0762, -0.0762, 0.0762), {0.0537, 4.247}, true};
  if (name == "circle") return {make_circle({0.0, 0.0}, 0.0508), {0.2032, 1.5 * pi}, false};
  throw std::invalid_argument("no example job " + name);
}

// The Fahim 1983 prototype's grid (0.001 in, 16000 steps per revolution) and work area (r 7.62 .. 33.02 cm,
// theta 0 .. 2.8 rad), homed at (r_min, theta_min).
inline Grid example_grid(bool whole_plane) {
  Grid g;
  g.dr = 0.0254e-3;
  g.steps_per_rev = 16000;
  g.dtheta = dtheta_from_steps(g.steps_per_rev);
  g.r_min = whole_plane ? 0.0 : 0.0762;
  g.r_max = 0.3302;
  if (!whole_plane) g.theta_min = 0.0, g.theta_max = 2.8;
  g.home_r = g.r_min;
  g.home_theta = g.theta_min.value_or(0.0);
  return g;
}

// Digitizes example `name` at 1.52 cm/s, nearest rule, into a temporary tape (once per test process) and returns
// its path.
inline std::string example_tape(const std::string& name) {
  struct Cleanup {
    std::vector<std::string> files;
    ~Cleanup() {
      for (const auto& f : files) std::remove(f.c_str());
    }
  };
  static Cleanup cleanup;
  const std::string path = temp_path(name + ".tape");
  if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
    std::fclose(f);
    return path;
  }
  const ExampleJob job = example_job(name);
  const Grid g = example_grid(job.whole_plane);
  const double speed = 0.0152;
  TapeHeader h;
  h.res[0] = g.dr, h.res[1] = g.dtheta, h.steps_per_rev = g.steps_per_rev;
  h.r_min = g.r_min, h.has_r_max = true, h.r_max = *g.r_max;
  h.has_theta_range = g.theta_min.has_value(), h.theta_min = g.theta_min.value_or(0.0);
  h.theta_max = g.theta_max.value_or(0.0);
  h.home[0] = g.home_n(), h.home[1] = g.home_m(), h.speed_mps = speed;
  ToolPathPtr path_m = make_tool_path(job.contour, job.placement, ToolSpec{}, TravelSpec{});
  const PolarTrack track = PolarTrack::build(*path_m);
  TapeWriter w(path, h);
  const DigitizeResult r = digitize(track, g, StepRule::nearest, *make_constant_speed(speed, track.length()), &w);
  h.start[0] = r.start_n, h.start[1] = r.start_m, h.end[0] = r.end_n, h.end[1] = r.end_m;
  h.duration_ticks = static_cast<uint64_t>(r.duration_ns), h.path_length_m = r.path_length_m;
  h.closed = r.closed, h.returns_to_start = r.returns_to_start;
  w.finish(h);
  cleanup.files.push_back(path);
  return path;
}

}  // namespace polarcam::test
