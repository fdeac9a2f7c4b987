// polarcam inspect TAPE [--json | --csv]
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.hpp"
#include "io/output.hpp"
#include "digitizer/replay.hpp"

namespace polarcam::cli {
namespace cmd_inspect {  // named, not anonymous: the command files are compiled together (unity build)

const char* axis_name(const TapeHeader& h, int axis) {
  if (h.axes == TapeAxes::polar) return axis == 0 ? "r" : "theta";
  return axis == 0 ? "x" : "y";
}

nlohmann::ordered_json header_json(const TapeHeader& h, const std::string& path) {
  nlohmann::ordered_json j;
  j["tape"] = path;
  j["format_version"] = h.version;
  j["axes"] = h.axes == TapeAxes::polar ? "polar" : "cartesian";
  j["rule"] = to_string(h.rule);
  j["tick_ns"] = static_cast<double>(h.tick_ps) * 1e-3;
  if (h.axes == TapeAxes::polar) {
    j["radial_resolution_m"] = h.res[0];
    j["angular_resolution_rad"] = h.res[1];
    j["angular_steps_per_rev"] = h.steps_per_rev;
    j["r_min_m"] = h.r_min;
    if (h.has_r_max) j["r_max_m"] = h.r_max;
    if (h.has_theta_range) {
      j["theta_min_rad"] = h.theta_min;
      j["theta_max_rad"] = h.theta_max;
    }
  } else {
    j["x_resolution_m"] = h.res[0];
    j["y_resolution_m"] = h.res[1];
  }
  j["home_node"] = {h.home[0], h.home[1]};
  j["start_node"] = {h.start[0], h.start[1]};
  j["end_node"] = {h.end[0], h.end[1]};
  j["closed"] = h.closed;
  j["returns_to_start"] = h.returns_to_start;
  j["steps_total"] = h.record_count;
  if (h.version >= kTapeVersionEvents) {
    j["tool_events"] = h.event_count;
    j["tool_starts"] = h.tool_starts_up ? "up" : "down";
  }
  const char* a0 = h.axes == TapeAxes::polar ? "radial" : "x";
  const char* a1 = h.axes == TapeAxes::polar ? "angular" : "y";
  j[std::string("steps_") + a0] = h.plus[0] + h.minus[0];
  j[std::string("steps_") + a1] = h.plus[1] + h.minus[1];
  j[std::string("steps_") + a0 + "_plus"] = h.plus[0];
  j[std::string("steps_") + a0 + "_minus"] = h.minus[0];
  j[std::string("steps_") + a1 + "_plus"] = h.plus[1];
  j[std::string("steps_") + a1 + "_minus"] = h.minus[1];
  j["duration_s"] = static_cast<double>(h.duration_ticks) * static_cast<double>(h.tick_ps) * 1e-12;
  j["last_step_s"] = static_cast<double>(h.last_step_ticks) * static_cast<double>(h.tick_ps) * 1e-12;
  j["path_length_m"] = h.path_length_m;
  j["speed_mps"] = h.speed_mps;
  j["records_bytes"] = h.records_bytes;
  char crc[16];
  std::snprintf(crc, sizeof crc, "%08x", h.records_crc);
  j["records_crc32"] = crc;
  auto prov = nlohmann::ordered_json::parse(h.provenance, nullptr, false);
  j["provenance"] = prov.is_discarded() ? nlohmann::ordered_json(h.provenance) : prov;
  return j;
}

}  // namespace cmd_inspect

void register_inspect(CLI::App& app, Action& action) {
  using namespace cmd_inspect;
  struct Opts {
    std::string tape;
    bool json = false, csv = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand("inspect", "Check a step tape and print its header, or every step");
  c->add_option("tape", o->tape, "step tape")->required();
  auto* fj = c->add_flag("--json", o->json, "print the header and totals as JSON");
  auto* fc = c->add_flag("--csv", o->csv, "print every step: t_ns,axis,dir,n,m (node after the step); a tool event "
                                          "as t_ns,tool,up|down,n,m");
  fj->excludes(fc);
  c->callback([o, &action] {
    action = [o] {
      if (o->csv) {
        // verify first, so a corrupted tape produces an error and no partial listing
        verify_tape(o->tape);
        TapeReader rd(o->tape);
        const TapeHeader& h = rd.header();
        TapeReplay rp(rd);
        MachineStep s;
        std::string buf;
        buf.reserve(1 << 16);
        buf += "t_ns,axis,dir,n,m\n";
        char line[128];
        const double ns_per_tick = static_cast<double>(h.tick_ps) * 1e-3;
        rd.on_tool_event([&](const ToolEvent& e) {
          unsigned long long t = h.tick_ps == 1000 ? e.t_ticks
                                                   : static_cast<unsigned long long>(static_cast<double>(e.t_ticks) * ns_per_tick + 0.5);
          int n = std::snprintf(line, sizeof line, "%llu,tool,%s,%lld,%lld\n", t, e.down ? "down" : "up",
                                static_cast<long long>(rp.node()[0]), static_cast<long long>(rp.node()[1]));
          buf.append(line, static_cast<size_t>(n));
        });
        while (rp.next(s)) {
          unsigned long long t = h.tick_ps == 1000 ? s.t_ticks
                                                   : static_cast<unsigned long long>(static_cast<double>(s.t_ticks) * ns_per_tick + 0.5);
          int n = std::snprintf(line, sizeof line, "%llu,%s,%+d,%lld,%lld\n", t, axis_name(h, s.axis), s.dir,
                                static_cast<long long>(s.node[0]), static_cast<long long>(s.node[1]));
          buf.append(line, static_cast<size_t>(n));
          if (buf.size() > (1 << 16) - 256) {
            std::fwrite(buf.data(), 1, buf.size(), stdout);
            buf.clear();
          }
        }
        std::fwrite(buf.data(), 1, buf.size(), stdout);
        return 0;
      }
      TapeHeader h = verify_tape(o->tape);
      nlohmann::ordered_json j = header_json(h, o->tape);
      if (o->json) {
        std::cout << j.dump(2) << "\n";
        return 0;
      }
      std::ostringstream os;
      os << "polarcam tape " << o->tape << " (format " << h.version << ", " << j["axes"].get<std::string>()
         << ", rule " << to_string(h.rule) << ") - checksums OK\n";
      if (h.axes == TapeAxes::polar)
        os << "  grid      dR = " << h.res[0] * 1e3 << " mm, dtheta = " << h.res[1] << " rad ("
           << h.steps_per_rev << " steps/rev)\n";
      else
        os << "  grid      x " << h.res[0] * 1e3 << " mm, y " << h.res[1] * 1e3 << " mm per step\n";
      os << "  steps     " << thousands(h.record_count) << " (" << axis_name(h, 0) << " +" << thousands(h.plus[0])
         << " / -" << thousands(h.minus[0]) << ", " << axis_name(h, 1) << " +" << thousands(h.plus[1]) << " / -"
         << thousands(h.minus[1]) << ")\n";
      if (h.event_count > 0)
        os << "  tool      " << thousands(h.event_count) << " events (up / down), starting "
           << (h.tool_starts_up ? "up" : "down") << "\n";
      os << "  time      " << j["duration_s"].get<double>() << " s, path " << h.path_length_m * 1e3 << " mm\n";
      os << "  nodes     start [" << h.start[0] << ", " << h.start[1] << "], end [" << h.end[0] << ", " << h.end[1]
         << "], home [" << h.home[0] << ", " << h.home[1] << "]\n";
      os << "  bytes     " << thousands(h.records_bytes) << " of records\n";
      std::cout << os.str();
      return 0;
    };
  });
}

}  // namespace polarcam::cli
