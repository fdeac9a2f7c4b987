#pragma once
// Machines, loads and analyses for the dynamics tests. The numbers are Table 5.1 of the thesis, written out here
// (the reference test reads them from the shared reference data instead).
#include <numbers>

#include "cam/curves.hpp"
#include "cam/toolpath.hpp"
#include "machine/dynamics/torque_analysis.hpp"

namespace polarcam::test {

inline ElectricalMotor thesis_motor() {
  ElectricalMotor e;
  e.supply_voltage = 24.0;
  e.K_T = 0.0759;
  e.K_V = 0.068;
  e.rotor_teeth = 50;
  e.R_a = 6.5;
  e.L_a = 6.3e-4;
  e.energisation = Energisation::wave;
  return e;
}

inline MachineModel thesis_machine() {
  MachineModel m;
  m.mech.carriage_mass = 0.9;
  m.mech.arm_inertia = 0.217;
  m.mech.arm_friction_torque = 0.127;
  m.mech.K1 = 2.78e-2;
  m.mech.K2 = 2.25e-2;
  m.mech.k_theta = 40.0;
  m.mech.k_R = 1.0 / (0.05 * 0.0254);
  m.radial = make_electrical_motor(thesis_motor());
  m.angular = make_electrical_motor(thesis_motor());
  return m;
}

inline GrindingSpec thesis_grinding() {
  GrindingSpec g;
  g.k_c = 6.46e10;
  g.c1 = 1.66;
  g.depth = 0.0254e-3;
  g.width = 0.635e-2;
  g.wheel_speed = 16.62;
  return g;
}

inline Load inertial(double mass) {
  LoadSpec s;
  s.kind = LoadKind::inertial;
  s.mass = mass;
  return make_load(s);
}

inline Load grinding(const GrindingSpec& g = thesis_grinding()) {
  LoadSpec s;
  s.kind = LoadKind::grinding;
  s.grinding = g;
  return make_load(s);
}

// A path with everything the analysis needs, kept alive together.
struct Rig {
  ToolPathPtr path;
  PolarTrack track;
  SpeedProfilePtr profile;
  MachineModel machine = thesis_machine();
  Load load;
  int side = 1;
  Rig(CurvePtr contour, Placement pl, double speed, Load l, int side_ = 1, bool reverse = false)
      : load(std::move(l)), side(side_) {
    TravelSpec tr;
    tr.reverse = reverse;
    path = make_tool_path(std::move(contour), pl, ToolSpec{}, tr);
    track = PolarTrack::build(*path);
    profile = make_constant_speed(speed, track.length());
  }
  DynamicsInput input() const { return {path.get(), &track, 0.0, profile.get(), &machine, &load, side}; }
  TorqueAnalysis run(AnalysisOptions o = {}) const { return analyze_torques(input(), o); }
  // everything at one path parameter (not at a reversal)
  PointDynamics at(double u) const {
    const double s = 0.0;  // the loads here do not depend on s
    return point_dynamics(path_state(path->eval(u, 2), profile->speed_at(s), 0.0), s, machine, load, side,
                          FrictionMode::moving);
  }
};

// The Ch. 5 test contours at the Ch. 5 poles (O = O1 + C e^{j beta}).
inline CurvePtr ch5_circle() { return make_circle({0.0, 0.0}, 0.0508); }
inline Placement ch5_circle_pole() { return {0.2032, 1.5 * std::numbers::pi}; }
inline CurvePtr ch5_witch() { return make_witch(0.2159, -0.2032, 0.2032); }
inline Placement ch5_witch_pole() { return {0.254, 0.5 * std::numbers::pi}; }

}  // namespace polarcam::test
