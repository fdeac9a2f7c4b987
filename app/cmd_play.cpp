// polarcam play TAPE (--port DEV | --simulate) [--baud N] [--speed-scale K] [--size-scale P/Q] [--angle-offset M]
//               [--machine FILE] [--accel A] [--json]
// Plays a step tape on a stepper controller over a serial line (or on the in-process simulated machine).
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "app/cli.hpp"
#include "cam/format.hpp"
#include "job/job.hpp"
#include "io/output.hpp"
#include "cam/error.hpp"
#include "cam/units.hpp"
#include "machine/link/host_link.hpp"
#include "machine/player/play_plan.hpp"
#include "machine/link/serial_port.hpp"
#include "machine/controller/sim_machine.hpp"

namespace polarcam::cli {
namespace cmd_play {  // named, not anonymous: the command files are compiled together (unity build)

std::atomic<bool> g_stop{false}, g_hold{false}, g_resume{false};
extern "C" void on_sigint(int) { g_stop.store(true); }
extern "C" void on_sigusr1(int) { g_hold.store(true); }
extern "C" void on_sigusr2(int) { g_resume.store(true); }

// Acceleration for holds and underrun stops: --accel, else the job's (tape provenance), else none.
std::optional<double> job_accel(const TapeHeader& h) {
  auto j = nlohmann::json::parse(h.provenance, nullptr, false);
  if (j.is_discarded()) return std::nullopt;
  auto p = j.find("job");
  if (p == j.end() || !p->is_object()) return std::nullopt;
  auto m = p->find("motion");
  if (m == p->end() || !m->is_object()) return std::nullopt;
  auto a = m->find("accel_mps2");
  if (a == m->end() || !a->is_number()) return std::nullopt;
  return a->get<double>();
}

// The tool dwell of the machine the tape was made for (tape provenance), when it declared one.
std::optional<double> job_tool_dwell(const TapeHeader& h) {
  auto j = nlohmann::json::parse(h.provenance, nullptr, false);
  if (j.is_discarded()) return std::nullopt;
  auto p = j.find("job");
  if (p == j.end() || !p->is_object()) return std::nullopt;
  auto m = p->find("machine");
  if (m == p->end() || !m->is_object()) return std::nullopt;
  auto d = m->find("tool_dwell_s");
  if (d == m->end() || !d->is_number()) return std::nullopt;
  const double v = d->get<double>();
  if (!(v >= 0.0 && v <= 60.0)) return std::nullopt;
  return v;
}

std::string clock(double s) {
  if (!(s >= 0) || s > 1e7) return "--:--";
  const long t = static_cast<long>(s + 0.5);
  char b[32];
  if (t >= 3600) std::snprintf(b, sizeof b, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  else std::snprintf(b, sizeof b, "%ld:%02ld", t / 60, t % 60);
  return b;
}

void progress_bar(const PlayProgress& p) {
  const double f = p.steps_total ? static_cast<double>(p.steps_confirmed) / static_cast<double>(p.steps_total) : 0.0;
  const int w = 24, fill = static_cast<int>(f * w);
  const double rate = p.elapsed_s > 0 ? static_cast<double>(p.steps_confirmed) / p.elapsed_s : 0.0;
  const double eta = p.total_s - p.schedule_s;
  std::fprintf(stderr, "\r[%s%s] %3.0f%% %s/%s steps  %s steps/s  buffer %3.0f%%  ETA %s  %-8s", std::string(fill, '#').c_str(),
               std::string(w - fill, '-').c_str(), 100 * f, thousands(p.steps_confirmed).c_str(),
               thousands(p.steps_total).c_str(), thousands(static_cast<unsigned long long>(rate)).c_str(),
               100 * p.buffer_fill, clock(eta).c_str(), proto::state_name(p.state));
  std::fflush(stderr);
}

}  // namespace cmd_play

void register_play(CLI::App& app, Action& action) {
  using namespace cmd_play;
  struct Opts {
    std::string tape, port, speed = "1", size = "1", machine, accel, log;
    unsigned baud = 115200;
    std::string flow = "none";
    long long angle_offset = 0;
    unsigned long long resume = 0;
    double tick_ns = 1000;
    bool simulate = false, json = false, quiet = false;
    CLI::Option* log_opt = nullptr;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand("play", "Play a step tape on a stepper controller over a serial line, or simulate it");
  c->add_option("tape", o->tape, "step tape")->required();
  auto* port = c->add_option("--port", o->port, "serial port of the controller (e.g. /dev/ttyUSB0)");
  auto* sim = c->add_flag("--simulate", o->simulate, "run the in-process simulated machine instead of a controller");
  port->excludes(sim);
  // the line's options go with --port, the simulated controller's with --simulate: refused with the other
  c->add_option("--baud", o->baud, "baud rate (default 115200)")->needs(port);
  c->add_option("--flow", o->flow, "flow control: none or hardware (default none)")->needs(port);
  c->add_option("--speed-scale", o->speed, "speed factor K: every interval divided by K (e.g. 10, 0.5, 3/2)");
  c->add_option("--size-scale", o->size, "radial size ratio P/Q about the machine pole (e.g. 2/1, 1/2)");
  c->add_option("--angle-offset", o->angle_offset, "angular steps added to every angular index (floating angular reference)")
      ->check(CLI::Range(-(int64_t{1} << 50), int64_t{1} << 50).description("within +-2^50 steps"));
  c->add_option("--machine", o->machine, "machine file: the tape must be for its grid; its work area is checked");
  c->add_option("--accel", o->accel, "acceleration limit for holds and stops (default: the job's motion.accel)");
  c->add_option("--tick", o->tick_ns, "simulated controller tick in ns (--simulate; default 1000)")->needs(sim);
  o->log_opt = c->add_option("--log", o->log, "write the executed steps as CSV t_ns,axis,dir (--simulate)")->needs(sim);
  c->add_option("--resume", o->resume,
                "skip the first N machine steps: continue a run that stopped after N confirmed steps (the error "
                "message of the stopped run gives N; use the same tape, scales and offset)")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            return !v.empty() && v.find_first_not_of("0123456789") == std::string::npos
                       ? ""
                       : "'" + v + "' must be a whole number of machine steps, 0 or more";
          },
          "N >= 0"));
  c->add_flag("--json", o->json, "print the result as one JSON object");
  c->add_flag("--quiet", o->quiet, "no progress bar (shown on a terminal only)");
  c->callback([o, &action] {
    action = [o] {
      if (!o->simulate && o->port.empty()) throw InputError("play: give --port DEV (a controller) or --simulate");
      if (option_given(o->log_opt)) check_output_path(o->log);  // before any work (an empty name is refused)
      if (!o->simulate) check_baud(o->baud);
      if (o->flow != "none" && o->flow != "hardware") throw InputError("--flow " + o->flow + ": must be none or hardware");
      PlayScaling sc;
      sc.speed = parse_ratio(o->speed, "--speed-scale");
      sc.size = parse_ratio(o->size, "--size-scale");
      sc.angle_offset = o->angle_offset;
      if (!(o->tick_ns >= 1 && o->tick_ns <= 1e9)) throw InputError("--tick must be between 1 ns and 1 s");
      std::optional<PlayMachine> machine;
      std::optional<double> tool_dwell;
      if (!o->machine.empty()) {
        PlayMachine m;
        const Machine mf = load_machine(o->machine);
        m.grid = mf.grid;
        m.source = "machine file " + o->machine;
        machine = m;
        tool_dwell = mf.tool_dwell;
      }
      // everything about the tape and the scales is checked here, before the port is touched
      PlayPlan plan = resume_plan(plan_playback(o->tape, sc, machine), o->resume);
      // the tool's time: the machine file's tool_dwell, else that of the machine the tape was made for
      if (!tool_dwell) tool_dwell = job_tool_dwell(plan.header);
      plan.tool_dwell_s = tool_dwell.value_or(0.0);
      std::optional<double> accel = job_accel(plan.header);
      if (!o->accel.empty()) {
        accel = option_quantity(o->accel, dim::acceleration, "--accel");
        if (!(*accel > 0)) throw InputError("must be a positive acceleration, e.g. \"500 mm/s^2\"", "--accel");
      }
      const double v = plan.header.speed_mps * sc.speed.value();
      LinkOptions lo;
      lo.baud = o->baud;
      lo.ramp_s = accel && v > 0 ? v / *accel : 0.0;

      nlohmann::ordered_json j;
      j["tape"] = o->tape;
      j["speed_scale"] = to_string(sc.speed);
      j["size_scale"] = to_string(sc.size);
      j["angle_offset"] = sc.angle_offset;
      j["start_node"] = {plan.start[0], plan.start[1]};
      j["end_node_expected"] = {plan.end[0], plan.end[1]};
      if (o->resume) j["resumed_from"] = o->resume;
      if (!plan.tools.empty()) j["tool_dwell_s"] = plan.tool_dwell_s;

      if (o->simulate) {
        const uint64_t tick_ps = static_cast<uint64_t>(o->tick_ns * 1000 + 0.5);
        Schedule s = compress_schedule(plan, tick_ps);
        struct Log : StepMonitor {
          std::string csv = "t_ns,axis,dir\n";
          bool on = false;
          void on_tool(uint64_t t_ns, bool down) override {
            if (on) csv += std::to_string(t_ns) + (down ? ",tool,down\n" : ",tool,up\n");
          }
          void on_step(const ExecutedStep& e) override {
            if (!on) return;
            char b[64];
            int n = std::snprintf(b, sizeof b, "%llu,%s,%+d\n", static_cast<unsigned long long>(e.t_ns), e.axis == 0 ? "r" : "theta", e.dir);
            csv.append(b, static_cast<size_t>(n));
          }
        } log;
        log.on = !o->log.empty();
        SimResult r = simulate_playback(plan, s, machine ? *machine : machine_from_header(plan.header), &log);
        if (log.on) write_file_atomic(o->log, log.csv);
        std::string bytes;
        ItemCodec codec;
        for (const QueueItem& it : s.items) codec.encode(it, bytes);
        j["mode"] = "simulate";
        j["tick_ns"] = o->tick_ns;
        j["steps_total"] = r.steps_expected;
        j["steps_executed"] = r.steps;
        j["steps_mismatched"] = r.mismatched;
        j["max_time_error_ns"] = r.max_time_error_ns;
        j["tool_events"] = r.tool_events_expected;
        j["tool_events_executed"] = r.tool_events;
        j["tool_events_mismatched"] = r.tool_mismatched;
        j["max_tool_time_error_ns"] = r.max_tool_time_error_ns;
        j["duration_s"] = r.duration_s;
        j["end_node"] = {r.end[0], r.end[1]};
        j["runs"] = s.runs;
        j["queue_bytes"] = bytes.size();
        j["queue_bytes_per_step"] = r.steps ? static_cast<double>(bytes.size()) / static_cast<double>(r.steps) : 0.0;
        if (o->json) {
          std::cout << j.dump(2) << "\n";
        } else {
          std::ostringstream os;
          os << "polarcam play " << o->tape << " (simulated machine, tick " << o->tick_ns << " ns)\n"
             << "  scale     speed x" << to_string(sc.speed) << ", size " << to_string(sc.size) << ", angle offset " << sc.angle_offset << "\n"
             << "  steps     " << thousands(r.steps) << " of " << thousands(r.steps_expected) << " executed, " << r.mismatched
             << " out of order, max time error " << r.max_time_error_ns << " ns\n";
          if (r.tool_events_expected > 0)
            os << "  tool      " << r.tool_events << " of " << r.tool_events_expected << " tool events executed, "
               << r.tool_mismatched << " out of place, max time error " << r.max_tool_time_error_ns << " ns, dwell "
               << plan.tool_dwell_s << " s\n";
          os             << "  time      " << r.duration_s << " s, end node [" << r.end[0] << ", " << r.end[1] << "]\n"
             << "  schedule  " << thousands(s.runs) << " runs in " << thousands(bytes.size()) << " bytes ("
             << j["queue_bytes_per_step"].get<double>() << " bytes/step)\n";
          std::cout << os.str();
        }
        return r.mismatched == 0 && r.steps == r.steps_expected && r.tool_mismatched == 0 &&
                       r.tool_events == r.tool_events_expected
                   ? 0
                   : 1;
      }

      SerialTransport port_io(o->port, o->baud, o->flow);
      HostLink link(port_io, lo);
      proto::Ident id = link.identify();
      Schedule s = compress_schedule(plan, id.tick_ps);
      const bool tty = ::isatty(2) && !o->quiet;
      if (tty) link.on_progress = progress_bar;
      g_stop.store(false);
      auto old = std::signal(SIGINT, on_sigint);
      auto old1 = std::signal(SIGUSR1, on_sigusr1);  // feed hold
      auto old2 = std::signal(SIGUSR2, on_sigusr2);  // resume
      link.stop = &g_stop;
      link.hold_request = &g_hold;
      link.resume_request = &g_resume;
      PlayReport rep;
      std::string error;
      try {
        rep = link.play(plan, s);
      } catch (const PlayError& e) {
        error = e.what();
        rep = link.report();
      }
      std::signal(SIGINT, old);
      std::signal(SIGUSR1, old1);
      std::signal(SIGUSR2, old2);
      if (tty) std::fprintf(stderr, "\n");
      j["mode"] = "serial";
      j["port"] = o->port;
      j["baud"] = o->baud;
      j["controller"] = id.name;
      j["tick_ns"] = static_cast<double>(id.tick_ps) * 1e-3;
      j["controller_slots"] = id.slots;
      j["controller_max_step_rate"] = id.max_step_rate;
      j["steps_total"] = rep.steps_total;
      j["steps_sent"] = rep.steps_sent;
      j["steps_confirmed"] = rep.steps_confirmed;
      j["tool_events"] = rep.tool_events;
      j["retransmissions"] = rep.retransmissions;
      j["naks"] = rep.naks;
      j["underruns"] = rep.underruns;
      j["reconnects"] = rep.reconnects;
      j["frames_sent"] = rep.frames_sent;
      j["bytes_sent"] = rep.bytes_sent;
      j["duration_s"] = rep.duration_s;
      j["wall_s"] = rep.wall_s;
      j["end_node"] = {rep.end_node[0], rep.end_node[1]};
      j["completed"] = error.empty();
      j["step_reached"] = o->resume + rep.steps_confirmed;  // machine steps of the whole tape, resumed ones included
      if (!error.empty() && rep.resumable && o->resume + rep.steps_confirmed > 0)
        error += "; to continue from there, run the same play command with --resume " +
                 std::to_string(o->resume + rep.steps_confirmed);
      if (!error.empty()) j["error"] = error;
      if (o->json) {
        std::cout << j.dump(2) << "\n";
      } else if (error.empty()) {
        std::cout << "polarcam play " << o->tape << " on " << port_io.describe() << " (" << id.name << ")\n"
                  << "  steps     " << thousands(rep.steps_confirmed) << " of " << thousands(rep.steps_total)
                  << " confirmed, end node [" << rep.end_node[0] << ", " << rep.end_node[1] << "]\n"
                  << "  time      " << rep.duration_s << " s on the controller, " << rep.wall_s << " s wall\n"
                  << "  link      " << thousands(rep.bytes_sent) << " bytes in " << thousands(rep.frames_sent) << " frames, "
                  << rep.retransmissions << " retransmissions, " << rep.underruns << " underruns\n";
      }
      std::cout.flush();
      if (!error.empty()) {
        std::fprintf(stderr, "polarcam: error: %s\n", terminal_text(error).c_str());
        return exit_status(ErrorKind::device);
      }
      return 0;
    };
  });
  (void)c;
}

}  // namespace polarcam::cli
