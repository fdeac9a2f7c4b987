#pragma once
// The in-process simulated machine: executes a compressed schedule on the same Controller the emulator runs
// (no link), and reports the executed path against the tape's scaled steps. A StepMonitor sees every executed
// step with the machine's position; a LostStepModel (the motor dynamics, built elsewhere) can return the torque
// ratio at that moment, and steps whose ratio exceeds 1 are counted as steps a motor would lose.
#include <cstdint>
#include <vector>

#include "machine/controller/controller.hpp"
#include "machine/player/play_plan.hpp"
#include "machine/player/schedule.hpp"

namespace polarcam {

struct ExecutedStep {
  uint64_t index = 0;      // 1-based machine step
  uint64_t t_ns = 0;       // executed time since START
  double t_exact_ns = 0;   // the tape's scaled time of this step
  int axis = 0, dir = 0;
  int64_t node[2] = {0, 0};  // machine node after the step
  double r_m = 0, theta_rad = 0;
};

class StepMonitor {
 public:
  virtual ~StepMonitor() = default;
  virtual void on_step(const ExecutedStep& s) = 0;
  // Every executed tool item: ns since START, down or up.
  virtual void on_tool(uint64_t /*t_ns*/, bool /*down*/) {}
};

// Hook for the motor dynamics (Ch. 5 of the thesis): required / pull-out torque of the stepping axis at this step.
class LostStepModel {
 public:
  virtual ~LostStepModel() = default;
  virtual double torque_ratio(const ExecutedStep& s) = 0;
};

struct SimResult {
  uint64_t steps = 0, steps_expected = 0;
  uint64_t mismatched = 0;        // steps whose axis or direction differs from the tape's (must be 0)
  double max_time_error_ns = 0;   // max |executed - scaled tape time (plus the tool dwells before the step)|
  double duration_s = 0;          // time of the last step
  int64_t end[2] = {0, 0};
  uint64_t tool_events = 0, tool_events_expected = 0;  // tool items executed, and in the plan (plan.tools)
  uint64_t tool_mismatched = 0;   // tool items executed in another state, or between other steps, than the plan's
  double max_tool_time_error_ns = 0;  // max |executed - exact| of the tool items
  uint64_t lost_steps = 0;        // steps with torque ratio > 1 (needs a LostStepModel)
  double max_torque_ratio = 0;
};

SimResult simulate_playback(const PlayPlan& plan, const Schedule& sched, const PlayMachine& machine,
                            StepMonitor* monitor = nullptr, LostStepModel* motors = nullptr);

}  // namespace polarcam
