#include "machine/controller/sim_machine.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace polarcam {

SimResult simulate_playback(const PlayPlan& plan, const Schedule& sched, const PlayMachine& machine,
                            StepMonitor* monitor, LostStepModel* motors) {
  ControllerSpec spec;
  spec.tick_ps = sched.tick_ps;
  spec.slots = static_cast<uint32_t>(sched.items.size() + 1);
  Controller ctl(spec);
  proto::Configure c;
  c.tick_ps = sched.tick_ps;
  c.start[0] = plan.start[0];
  c.start[1] = plan.start[1];
  std::string why;
  if (!ctl.configure(c, &why)) throw std::logic_error("simulated controller: " + why);
  for (const QueueItem& it : sched.items)
    if (!ctl.push(it)) throw std::logic_error("simulated controller: queue refused an item");

  SimResult res;
  res.steps_expected = plan.steps.size();
  const double ns_per_tick = static_cast<double>(sched.tick_ps) * 1e-3;
  const long double exact_scale = static_cast<long double>(plan.header.tick_ps) * 1e-3L *
                                  static_cast<long double>(plan.scaling.speed.den) / static_cast<long double>(plan.scaling.speed.num);
  int64_t node[2] = {plan.start[0], plan.start[1]};
  // exact times: the scaled tape time and a tool dwell for every tool item before
  const double dwell_ns = static_cast<double>(sched.tool_dwell_ticks) * ns_per_tick;
  std::vector<uint64_t> tools_before(plan.steps.size() + 1, 0);
  for (size_t i = 0, j = 0; i <= plan.steps.size(); ++i) {
    while (j < plan.tools.size() && plan.tools[j].before <= i) ++j;
    tools_before[i] = j;
  }
  res.tool_events_expected = plan.tools.size();
  ctl.on_tool = [&](uint64_t t, bool down) {
    const uint64_t j = res.tool_events++;
    if (j >= plan.tools.size()) {
      ++res.tool_mismatched;
      return;
    }
    const PlayTool& e = plan.tools[j];
    if (e.down != down || e.before != res.steps) ++res.tool_mismatched;
    const double exact = static_cast<double>(static_cast<long double>(e.t) * exact_scale) + static_cast<double>(j) * dwell_ns;
    res.max_tool_time_error_ns = std::max(res.max_tool_time_error_ns, std::fabs(static_cast<double>(t) * ns_per_tick - exact));
    if (monitor) monitor->on_tool(static_cast<uint64_t>(std::llround(static_cast<double>(t) * ns_per_tick)), down);
  };
  ctl.on_step = [&](uint64_t t, int axis, int dir) {
    ExecutedStep s;
    s.index = ++res.steps;
    s.t_ns = static_cast<uint64_t>(std::llround(static_cast<double>(t) * ns_per_tick));
    s.axis = axis;
    s.dir = dir;
    node[axis] += dir;
    s.node[0] = node[0];
    s.node[1] = node[1];
    s.r_m = static_cast<double>(node[0]) * machine.grid.dr;
    s.theta_rad = static_cast<double>(node[1]) * machine.grid.dtheta;
    if (s.index <= plan.steps.size()) {
      const PlayStep& p = plan.steps[s.index - 1];
      s.t_exact_ns = static_cast<double>(static_cast<long double>(p.t) * exact_scale) +
                     static_cast<double>(tools_before[s.index - 1]) * dwell_ns;
      if (p.axis != axis || p.dir != dir) ++res.mismatched;
      res.max_time_error_ns = std::max(res.max_time_error_ns, std::fabs(static_cast<double>(t) * ns_per_tick - s.t_exact_ns));
    } else {
      ++res.mismatched;
    }
    res.duration_s = static_cast<double>(t) * ns_per_tick * 1e-9;
    if (monitor) monitor->on_step(s);
    if (motors) {
      const double ratio = motors->torque_ratio(s);
      res.max_torque_ratio = std::max(res.max_torque_ratio, ratio);
      if (ratio > 1.0) ++res.lost_steps;
    }
  };
  ctl.start(0);
  ctl.advance(sched.last_tick + 2);
  if (ctl.state() != proto::State::done) throw std::logic_error("simulated controller did not finish the schedule");
  res.end[0] = node[0];
  res.end[1] = node[1];
  return res;
}

}  // namespace polarcam
