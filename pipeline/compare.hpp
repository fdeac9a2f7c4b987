#pragma once
// Job -> the polar machine and the Cartesian machine side by side (docs/compare.md): the job digitized on the polar
// machine of its [machine] and stepped on a Cartesian machine with the same linear resolution (the BLU) and the
// same tangential speed, both tapes measured by the same meters: step counts, contouring time, tangential speed
// from the pulse rates, exact area error and deviation against the same tool path, step rates, tape size, and the
// attributes of Table 3.1 of A. Fahim's thesis (1983) as measured facts (speed scaling without reprocessing,
// size scaling by one axis, resolution at the worst point of the path), with which machine wins on each for this
// job. The measurements live in digitizer/, machine/ and optimize/; this file only runs them and collects.
#include <optional>
#include <string>
#include <vector>

#include "io/progress.hpp"
#include "job/job.hpp"
#include "pipeline/job_cartesian.hpp"
#include "metrics/pulse_speed.hpp"
#include "machine/player/scaling.hpp"
#include "metrics/step_rates.hpp"

namespace polarcam {

struct CompareOptions {
  CartesianMethod method = CartesianMethod::dda;
  std::optional<double> rate;  // DDA interrupt rate (default: the job's)
  Ratio speed_scale{2, 1};     // K of the speed-scaling fact
  Ratio size_scale{1, 2};      // P/Q of the size-scaling fact
  bool figures = false;        // also collect what the HTML report draws
};

// Playing the tape K times faster (or, for the DDA control, running the program again at K V).
struct SpeedScalingFact {
  double factor = 1.0;
  bool without_reprocessing = true;
  bool possible = true;        // false: the DDA cannot run K V at its interrupt rate
  std::string how, note;
  PulseSpeedStats speed;       // measured at K V (nominal K V)
};

// Scaling the machine's indices on some axes by P/Q.
struct SizeScalingFact {
  double factor = 1.0;
  std::string axes;            // "r", "x", "x and y"
  bool measured = false;       // area error against the scaled contour (not for a distorted result)
  std::string note;            // why not, when it could not be measured
  double area_m2 = 0.0;
  Vec2 size;                   // bounding box of the scaled staircase's nodes (m)
  Vec2 wanted;                 // bounding box of the contour scaled by P/Q (m)
};

struct MachineSide {
  std::string name;            // "polar", "cartesian"
  std::string method;          // nearest, thesis, dda, exact
  std::string axis[2];         // "r", "theta" or "x", "y"
  std::string grid;            // a line describing the grid
  uint64_t steps[2] = {0, 0};
  double duration_s = 0.0, path_length_m = 0.0;
  PulseSpeedStats speed;
  double area_m2 = 0.0, deviation_m = 0.0;
  Vec2 deviation_at;           // contour frame (origin O1), m
  AxisRates rates[2];
  uint64_t tape_bytes = 0;
  double resolution_worst_m = 0.0;
  std::string resolution_where;
  SpeedScalingFact speed_scaling;
  std::vector<SizeScalingFact> size_scaling;
  // figures (contour frame, m)
  std::optional<SpeedTrace> trace;
  std::vector<std::vector<Vec2>> detail[2];  // the staircase's runs inside each detail window
  uint64_t steps_total() const { return steps[0] + steps[1]; }
  double max_step_rate_hz() const { return std::max(rates[0].max_rate_hz, rates[1].max_rate_hz); }
};

struct AttributeVerdict {  // one row of the comparison: which machine wins on an attribute
  std::string attribute;
  std::string polar, cartesian;  // the measured values, formatted
  std::string winner;            // "polar", "cartesian" or "tie"
  std::string why;               // one plain sentence
};

struct DetailWindow {
  Vec2 center;
  double half = 0.0;
  std::string title;
};

struct Comparison {
  std::string job_file, contour;
  bool closed = false;
  double nominal_speed = 0.0;   // m/s
  double path_length_m = 0.0;   // of the tool path
  double interrupt_rate = 0.0;  // DDA
  MachineSide polar, cartesian;
  std::vector<AttributeVerdict> verdicts;
  // figures (contour frame, m)
  std::vector<Vec2> outline;                  // the tool path
  Vec2 polar_pole;                            // the polar machine's pole
  DetailWindow windows[2];
  std::vector<std::vector<Vec2>> contour_in[2];  // the tool path's runs inside each window
};

// Runs both machines and all measurements. Throws InputError naming the job (or the option) for bad input.
// `progress`: the share done (the polar side, the Cartesian side, the figures).
Comparison compare_job(const Job& job, const CompareOptions& opt, const Progress& progress = {});

nlohmann::ordered_json to_json(const Comparison& c);

}  // namespace polarcam
