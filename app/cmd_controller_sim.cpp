// polarcam controller-sim --pty [--tick NS] [--faults SPEC] --log FILE [--exit-after-idle SECONDS] [--baud N]
//                         [--slots N] [--queue-bytes N] [--drop-ahead] [--time-scale F] [--machine FILE] [--no-tool]
// The controller emulator: serves the controller protocol on a pseudo-terminal, executes the schedule on a
// simulated clock, logs every executed step, and injects faults. Prints the pty path as its first line.
#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "app/cli.hpp"
#include "job/job.hpp"
#include "cam/error.hpp"
#include "io/output.hpp"
#include "machine/controller/emulator.hpp"
#include "machine/link/protocol.hpp"
#include "machine/link/serial_port.hpp"

namespace polarcam::cli {
namespace cmd_controller_sim {  // named, not anonymous: the command files are compiled together (unity build)

std::atomic<bool> g_quit{false};
extern "C" void on_term(int) { g_quit.store(true); }

speed_t speed_code(unsigned baud) {
  switch (baud) {
    case 1200: return B1200;
    case 2400: return B2400;
    case 4800: return B4800;
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 460800: return B460800;
    case 921600: return B921600;
    case 1000000: return B1000000;
    case 2000000: return B2000000;
    default: return B0;
  }
}

}  // namespace cmd_controller_sim

void register_controller_sim(CLI::App& app, Action& action) {
  using namespace cmd_controller_sim;
  struct Opts {
    bool pty = false;
    double tick_ns = 1000;
    std::string faults, log, machine;
    double exit_after_idle = 0;
    unsigned baud = 115200;
    unsigned slots = 4096;
    unsigned queue_bytes = 0;
    bool drop_ahead = false;
    bool no_tool = false;
    double time_scale = 1;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand("controller-sim", "Emulate a stepper controller on a pseudo-terminal");
  c->add_flag("--pty", o->pty, "serve on a new pseudo-terminal (its path is the first line of output)")->required();
  c->add_option("--tick", o->tick_ns, "timer tick in ns (default 1000)");
  c->add_option("--faults", o->faults, "faults: drop=F,corrupt=F,delay=F,delay_ms=MS,stall=S@T,disconnect=S@T,reset@T,seed=N");
  c->add_option("--log", o->log, "CSV of every executed step: t_ns,axis,dir")->required();
  c->add_option("--exit-after-idle", o->exit_after_idle, "exit after this many seconds without input while no job runs");
  c->add_option("--baud", o->baud, "line rate it emulates, and expects the host to set (default 115200)");
  c->add_option("--slots", o->slots, "queue items it buffers (default 4096)");
  c->add_option("--queue-bytes", o->queue_bytes, "and bytes of encoded items (default: no limit; the reference firmware: 384)");
  c->add_flag("--drop-ahead", o->drop_ahead, "drop frames that arrive after a missing one, as the reference firmware");
  c->add_flag("--no-tool", o->no_tool, "a controller that drives no tool: refuses tool items (IDENT without the tool capability)");
  c->add_option("--time-scale", o->time_scale, "its clock runs this many times faster than the wall clock (default 1)");
  c->add_option("--machine", o->machine, "machine file: refuse jobs for another grid");
  c->callback([o, &action] {
    action = [o] {
      check_baud(o->baud);
      if (!(o->tick_ns >= 1 && o->tick_ns <= 1e9)) throw InputError("--tick must be between 1 ns and 1 s");
      if (!(o->time_scale > 0 && o->time_scale <= 1000)) throw InputError("--time-scale must be in (0, 1000]");
      if (o->slots < 16) throw InputError("--slots must be at least 16");
      if (o->queue_bytes != 0 && o->queue_bytes < 64) throw InputError("--queue-bytes must be at least 64 (a frame's items)");
      if (!(o->exit_after_idle >= 0)) throw InputError("--exit-after-idle must not be negative");
      FaultSpec faults = o->faults.empty() ? FaultSpec{} : parse_faults(o->faults);
      ControllerSpec spec;
      spec.tick_ps = static_cast<uint64_t>(o->tick_ns * 1000 + 0.5);
      spec.slots = o->slots;
      spec.queue_bytes = o->queue_bytes;
      spec.keep_ahead = !o->drop_ahead;
      spec.tool = !o->no_tool;
      if (!o->machine.empty()) {
        const Grid g = load_machine(o->machine).grid;
        spec.dr = g.dr;
        spec.dtheta = g.dtheta;
      }
      // the log is written as the steps run (it can be followed while they do), so it is written in place; a log
      // that cannot be written is an I/O error (exit status 3), at once or when a write fails
      check_output_path(o->log);
      std::FILE* log = std::fopen(o->log.c_str(), "w");
      if (!log) throw DeviceError(std::string("cannot create the log (") + std::strerror(errno) + ")", o->log);
      std::string log_error;  // why a write of the log failed
      auto log_written = [&] {
        if (std::fflush(log) != 0 || std::ferror(log)) {
          if (log_error.empty()) log_error = std::strerror(errno);
          return false;
        }
        return true;
      };
      std::fputs("t_ns,axis,dir\n", log);
      if (!log_written()) {
        std::fclose(log);
        throw DeviceError("cannot write the log (" + log_error + ")", o->log);
      }

      const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
      if (master < 0 || ::grantpt(master) != 0 || ::unlockpt(master) != 0) {
        std::fclose(log);
        throw DeviceError(std::string("cannot create a pseudo-terminal (") + std::strerror(errno) + ")");
      }
      const std::string path = ::ptsname(master);
      termios tio{};
      tcgetattr(master, &tio);
      cfmakeraw(&tio);
      cfsetispeed(&tio, speed_code(o->baud));
      cfsetospeed(&tio, speed_code(o->baud));
      tcsetattr(master, TCSANOW, &tio);
      // hold the slave side open ourselves, so the pty outlives each host connection (reconnects find it)
      const int keep = ::open(path.c_str(), O_RDWR | O_NOCTTY);
      fcntl(master, F_SETFL, fcntl(master, F_GETFL) | O_NONBLOCK);
      std::printf("%s\n", path.c_str());
      std::fflush(stdout);

      g_quit.store(false);
      std::signal(SIGTERM, on_term);
      std::signal(SIGINT, on_term);
      std::signal(SIGPIPE, SIG_IGN);

      Emulator emu(spec, o->baud, faults);
      bool wrote = false;
      emu.on_step = [&](uint64_t t_ns, int axis, int dir) {
        std::fprintf(log, "%llu,%s,%+d\n", static_cast<unsigned long long>(t_ns), axis == 0 ? "r" : "theta", dir);
        wrote = true;
      };
      emu.on_tool = [&](uint64_t t_ns, bool down) {
        std::fprintf(log, "%llu,tool,%s\n", static_cast<unsigned long long>(t_ns), down ? "down" : "up");
        wrote = true;
      };
      using clk = std::chrono::steady_clock;
      const auto t0 = clk::now();
      auto last_input = t0;
      std::string out;
      char buf[4096];
      while (!g_quit.load()) {
        const auto wall = clk::now();
        const double now = std::chrono::duration<double>(wall - t0).count() * o->time_scale;
        // a host whose line settings differ from ours gets garbage, as on a real line
        termios cur{};
        if (tcgetattr(master, &cur) == 0) emu.garble = cfgetospeed(&cur) != speed_code(o->baud);
        if (emu.reading(now)) {
          for (;;) {
            ssize_t n = ::read(master, buf, sizeof buf);
            if (n <= 0) break;
            emu.from_host(std::string(buf, static_cast<size_t>(n)), now);
            last_input = wall;
          }
        }
        emu.advance(now);
        out += emu.to_host(now);
        while (!out.empty()) {
          ssize_t n = ::write(master, out.data(), out.size());
          if (n <= 0) break;
          out.erase(0, static_cast<size_t>(n));
        }
        if (wrote) {
          wrote = false;
          if (!log_written()) break;  // the steps would go unrecorded: stop as a controller that fails does
        }
        const proto::State st = emu.controller().state();
        const bool busy = st == proto::State::running || st == proto::State::holding || st == proto::State::resuming ||
                          st == proto::State::stopping;
        if (o->exit_after_idle > 0 && !busy &&
            std::chrono::duration<double>(wall - last_input).count() > o->exit_after_idle)
          break;
        pollfd p{master, static_cast<short>(emu.reading(now) ? POLLIN : 0), 0};
        ::poll(&p, 1, 1);
      }
      // stopped (SIGTERM, SIGINT): what was on its way to the host, then where it stopped, as firmware that is
      // shutting down reports it, so that the host can offer to resume from the last step executed
      if (g_quit.load()) {
        out += proto::encode_frame(0, proto::STATUS_REPLY, emu.controller().status().encode());
        for (int tries = 0; tries < 200 && !out.empty(); ++tries) {
          const ssize_t n = ::write(master, out.data(), out.size());
          if (n > 0) out.erase(0, static_cast<size_t>(n));
          else ::usleep(1000);
        }
        // closing the pseudo-terminal discards what the host has not read yet. The kernel moves the bytes to the
        // host's side asynchronously (later still on a loaded machine), so they are counted only after a moment:
        // wait until they have been seen there and read (up to 5 s), or, never seen, half a second (a host
        // blocked in its read takes them at once)
        ::usleep(50000);
        bool seen = false;
        for (int tries = 0; tries < 5000 && keep >= 0; ++tries) {
          int queued = 0;
          if (::ioctl(keep, FIONREAD, &queued) != 0) break;
          if (queued > 0) seen = true;
          else if (seen || tries >= 450) break;
          ::usleep(1000);
        }
      }
      if (std::fclose(log) != 0 && log_error.empty()) log_error = std::strerror(errno);
      if (keep >= 0) ::close(keep);
      ::close(master);
      if (!log_error.empty())
        throw DeviceError("the log could not be written (" + log_error + "): the emulator stopped after " +
                              std::to_string(emu.controller().status().executed[0] + emu.controller().status().executed[1]) +
                              " steps",
                          o->log);
      return 0;
    };
  });
}

}  // namespace polarcam::cli
