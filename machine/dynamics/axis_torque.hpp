#pragma once
// Torques the two motors must deliver at one point of the path (Eq. 5.15, 5.16 of A. Fahim's thesis (1983)), the
// pull-out torque their motors offer at the step rate there (Eq. 5.17-5.21), and the torque ratio.
//   T_R     = K2 [ M a_cr + F_cr ]                                                (Eq. 5.15)
//   T_theta = K1 [ J_A theta'' + M r a_cn + r F_cn + F_f L_A sgn(theta') ]        (Eq. 5.16)
// M = M_c + added mass; (F_cr, F_cn) the components along e_r and e_theta of the force the drives must apply
// against the process, -F_tool = F_t T - F_n s N (s = +1 with the tool centre on the left of the travel).
// Motor speeds: radial k_R |r'| rev/s, angular k_theta |theta'| / (2 pi) rev/s; step rates are those times the
// motor's steps per revolution (Eq. 5.18-5.19 with their units sorted out, docs/dynamics.md).
#include "machine/dynamics/kinematics.hpp"
#include "machine/dynamics/load.hpp"
#include "machine/dynamics/mechanics.hpp"
#include "machine/dynamics/stepper.hpp"

namespace polarcam {

// Mechanics and the two motors: everything the dynamics need to know about a machine.
struct MachineModel {
  Mechanics mech;
  StepperMotor radial, angular;
};

// How the Coulomb friction of the arm support acts at a point. Where the arm turns: F_f L_A sgn(theta'), always.
// Where it does not (theta' = 0 to rounding) and theta'' != 0, the arm is reversing or starting from rest: `moving`
// takes the limit after that instant (the arm turning with theta''), `reversal_before` the limit before it (still
// turning against theta''). Where theta'' = 0 too, static friction holds the arm and takes up to F_f L_A of the
// other torque.
enum class FrictionMode { moving, reversal_before };

struct AxisDemand {
  double torque = 0.0;     // N m, signed: + drives the axis towards +r / +theta
  double step_rate = 0.0;  // Hz, motor steps per second
  double pullout = 0.0;    // N m available at that rate
  double ratio = 0.0;      // torque / pullout (signed); +inf where the motor has no pull-out torque left
};

struct PointDynamics {
  PathState st;
  ToolForce force;
  AxisDemand radial, angular;
};

// s is the arc length (for a load that varies along the path). Throws OutsideCurveError when a step rate falls
// outside a motor's tabulated curve.
PointDynamics point_dynamics(const PathState& st, double s, const MachineModel& m, const Load& load, int side,
                             FrictionMode mode);

}  // namespace polarcam
