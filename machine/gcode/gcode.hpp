#pragma once
// G-code for polar sand tables driven as two linear axes (the open-source hosts on GRBL and FluidNC: the arm angle
// theta on one axis, the ball's radius rho on the other), written so that the ball moves at a constant speed
// along the pattern (docs/gcode.md).
//
// The axes. The theta axis is at  T = theta_units_per_rad * theta,  the radial axis at
//   R = rho_units_per_radius * rho / table_radius + coupling * theta,
// so that a theta-rho segment (linear in theta and rho) is one straight G1 move in axis space. `coupling` is the
// radial axis travel that must be ADDED per radian of arm rotation to keep the ball at the same radius: on arms
// whose ball moves towards the centre when the arm turns counter-clockwise (theta increasing) with the radial
// motor held, coupling is the inward travel per radian, in radial axis units, and is positive; it is negative
// when the ball moves outwards. Zero for an arm without coupling.
//
// The ball speed. Within one G1 the axes move at constant rates, so theta and rho are linear in time and the
// ball's speed sqrt(rho'^2 + rho^2 theta'^2) = g(rho) / T, with g(rho) = sqrt(drho^2 + rho^2 dtheta^2) over the
// move and T its duration, varies with rho along the move (g is monotone in rho). Inverse-time mode (G93) gives
// each move its duration, F = 1 / minutes: a segment is split at intermediate vertices (exactly on it, linear in
// theta and rho) into n moves of equal ratio g_end / g_start, n the least for which that ratio is at most
// 1.009 / 0.991, and each move lasts T = (g_start + g_end) / (2 V), which centres the ball speed on V: it stays
// within 0.9 % of V before rounding, within 1 % of V after the coordinates and F are rounded to the printed
// decimals (a move that is not is split again; one that cannot be split further because its axis travel is within
// 20 units of the last decimal is marked "(resolution limit)"). Where an axis would exceed its largest feed
// the move is slowed to the limit and marked "(axis limit: X)". A move in which the ball stays at the centre
// (the arm turning about the pole, both ends at rho = 0) is timed by the axis limits and marked
// "(axis limit: X, ball at the centre)". Axis mode (G94) is what today's hosts send: one G1 per segment at a
// constant feed F in axis units per minute (slowed, and marked, where one axis alone would exceed its limit).
//
// The program: comment lines, the header lines, G93 or G94, a rapid G0 to the pattern's start, the moves, G94,
// the footer lines, M2 (write_gcode_lifting: each contour after its own G0, between pen_up and pen_down lines). Uppercase words, coordinates and F with a fixed number of decimals (no "-0"), accepted by
// LinuxCNC's interpreter, GRBL and FluidNC. The same input gives the same bytes.
#include <iosfwd>
#include <string>
#include <vector>

#include "cam/theta_rho_path.hpp"

namespace polarcam {

enum class FeedMode { inverse_time, axis };

struct GcodeSpec {
  std::string theta_axis = "X";           // axis letter of the arm angle: one of X Y Z A B C U V W
  std::string rho_axis = "Y";             // axis letter of the radius, another one of them
  double theta_units_per_rad = 1.0;       // theta axis units per radian of arm angle (not 0; negative reverses)
  double rho_units_per_radius = 1.0;      // radial axis units per table radius (> 0): 1 for rho in 0..1, or mm
  double table_radius = 0.0;              // m: the radius rho = 1 stands for (> 0)
  double coupling = 0.0;                  // radial axis units added per radian of arm rotation (see above)
  double theta_max_feed = 0.0;            // largest rate of the theta axis, units/min (> 0)
  double rho_max_feed = 0.0;              // largest rate of the radial axis, units/min (> 0)
  FeedMode feed_mode = FeedMode::inverse_time;
  double axis_feed = 0.0;                 // axis mode: F in axis units/min (> 0 in that mode)
  std::vector<std::string> header{"G21", "G90"};  // lines written before the moves
  std::vector<std::string> footer;        // lines written after them, before M2
  // A machine that lifts its tool between contours (write_gcode_lifting): the lines that lift it and lower it.
  // The defaults stop and start the spindle, which GRBL builds for pen plotters and laser cutters take as pen up
  // and pen down; a Z move ("G0 Z5") suits a cutter.
  std::vector<std::string> pen_up{"M5"};
  std::vector<std::string> pen_down{"M3"};
  int decimals = 4;                       // decimals of coordinates and F (1 .. 9)
};

// Checks a spec; InputError naming the field (as the [gcode] key) otherwise.
void validate(const GcodeSpec& spec);

struct GcodeStats {
  size_t lines = 0;                 // lines of the program
  size_t g1 = 0;                    // G1 moves
  size_t limited = 0;               // of them, slowed by an axis limit or at the coordinate resolution
  size_t centre_turns = 0;          // of them, with the ball at the centre (the arm turning about the pole)
  double duration_s = 0.0;          // sum of the G1 durations, as the F words give them
  double max_speed_error_pct = 0.0; // largest |ball speed / requested - 1| x 100 at the ends of the moves not limited
  double ball_speed_min_mps = 0.0;  // smallest and largest ball speed at the ends of the moves (centre turns apart)
  double ball_speed_max_mps = 0.0;
  size_t pen_ups = 0, pen_downs = 0;  // write_gcode_lifting: the pen_up and pen_down groups written
  size_t rapids = 0;                  // G0 moves between contours (the G0 to the start apart)
};

// Writes the program for the theta-rho vertices `v` (rho in metres, at most the table radius) at ball speed
// `ball_speed_mps` (> 0; in axis mode only the statistics use it). `comments` become "(...)" lines at the top
// (parentheses removed, at most 70 characters each). Throws InputError for a bad spec, fewer than two
// vertices, a rho beyond the table radius or a non-finite value.
GcodeStats write_gcode(std::ostream& out, const std::vector<ThetaRho>& v, const GcodeSpec& spec,
                       double ball_speed_mps, const std::vector<std::string>& comments = {});

// The same with a ball speed per segment (a speed schedule along the path, e.g. a time-optimal one):
// `segment_speeds[i]` (m/s, > 0) for the segment from v[i] to v[i + 1]; each move keeps within 1 % of its segment's
// speed, and max_speed_error_pct is against it. InputError unless there is one positive speed per segment.
GcodeStats write_gcode(std::ostream& out, const std::vector<ThetaRho>& v, const GcodeSpec& spec,
                       const std::vector<double>& segment_speeds, const std::vector<std::string>& comments = {});

// The same for the contours of a drawing on a machine that lifts its tool between them: before each contour the
// pen_up lines, a rapid G0 to its start (a straight line in axis space: linear in theta and rho, the move the
// tape's rapid makes), the pen_down lines, then its moves; the pen_up lines after the last. So the program lifts
// the tool once more than it has contours (the first lift before the G0 to the start) and lowers it once per
// contour. Errors name the contour and point.
GcodeStats write_gcode_lifting(std::ostream& out, const std::vector<std::vector<ThetaRho>>& contours,
                               const GcodeSpec& spec, double speed_mps, const std::vector<std::string>& comments = {});

}  // namespace polarcam
