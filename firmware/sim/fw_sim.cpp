// Runs the reference firmware in simavr (an ATmega328P at 16 MHz), its UART bridged to a pseudo-terminal, and
// records the step, direction and LED pins in a VCD file.
//
//   fw_sim FIRMWARE.elf OUT.vcd [--faults drop=F,corrupt=F,seed=N] [--time-scale F]
//
// Prints the pty's path as its first line (as `polarcam controller-sim --pty`), then runs until SIGTERM or
// SIGINT. The simulated clock is held to the wall clock (times --time-scale) so that a host talking to the pty
// sees the board's pace; the UART's bytes take the simulated baud rate's time. Faults, in each direction, per
// byte: drop=F drops it, corrupt=F flips one of its bits (a seeded generator: the same faults every run).
// VCD signals: r_step (PD2), r_dir (PD5), theta_step (PD3), theta_dir (PD6), enable (PB0), run (PB5, the LED:
// rising at schedule tick 0), tool (PB4, high while the tool is down). At the end it reports the deepest stack (the RAM above the variables is painted).
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <simavr/avr_extint.h>
#include <simavr/avr_ioport.h>
#include <simavr/avr_uart.h>
#include <simavr/sim_avr.h>
#include <simavr/sim_elf.h>
#include <simavr/sim_vcd_file.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <random>
#include <string>

namespace {

volatile sig_atomic_t g_quit = 0;
constexpr uint8_t kPaint = 0xa5;
extern "C" void on_term(int) { g_quit = 1; }

struct Faults {
  double drop = 0, corrupt = 0;
  unsigned seed = 1;
};

Faults parse_faults(const std::string& spec) {
  Faults f;
  size_t pos = 0;
  while (pos < spec.size()) {
    size_t end = spec.find(',', pos);
    if (end == std::string::npos) end = spec.size();
    const std::string item = spec.substr(pos, end - pos);
    const size_t eq = item.find('=');
    const std::string key = item.substr(0, eq), val = eq == std::string::npos ? "" : item.substr(eq + 1);
    char* stop = nullptr;
    const double v = std::strtod(val.c_str(), &stop);
    if (eq == std::string::npos || stop == val.c_str() || *stop != 0 || !(v >= 0) ||
        (key != "seed" && v > 1)) {
      std::fprintf(stderr, "fw_sim: --faults %s: give drop=F,corrupt=F,seed=N (fractions in [0, 1])\n", item.c_str());
      std::exit(2);
    }
    if (key == "drop") f.drop = v;
    else if (key == "corrupt") f.corrupt = v;
    else if (key == "seed") f.seed = static_cast<unsigned>(v);
    else {
      std::fprintf(stderr, "fw_sim: --faults: unknown item %s (drop, corrupt, seed)\n", key.c_str());
      std::exit(2);
    }
    pos = end + 1;
  }
  return f;
}

// One direction of the line: drops and damages bytes as the fault spec says.
struct Line {
  const Faults* f;
  std::mt19937 rng;
  std::uniform_real_distribution<double> u{0.0, 1.0};
  uint64_t dropped = 0, corrupted = 0;
  Line(const Faults* faults, unsigned seed) : f(faults), rng(seed) {}
  bool pass(uint8_t& b) {
    const double r = u(rng);
    if (r < f->drop) {
      ++dropped;
      return false;
    }
    if (r < f->drop + f->corrupt) {
      b ^= static_cast<uint8_t>(1u << (rng() % 8));
      ++corrupted;
    }
    return true;
  }
};

struct Bridge {
  avr_t* avr = nullptr;
  avr_irq_t* to_avr = nullptr;
  bool xon = true;
  std::deque<uint8_t> in, out;  // host -> board, board -> host
  Line* to_host = nullptr;
};

void on_uart_out(avr_irq_t*, uint32_t value, void* param) {
  auto* b = static_cast<Bridge*>(param);
  uint8_t c = static_cast<uint8_t>(value);
  if (b->to_host->pass(c)) b->out.push_back(c);
}
void on_xon(avr_irq_t*, uint32_t, void* param) { static_cast<Bridge*>(param)->xon = true; }
void on_xoff(avr_irq_t*, uint32_t, void* param) { static_cast<Bridge*>(param)->xon = false; }

// The simulator must not sleep in real time by itself: this program paces it.
void no_sleep(avr_t*, avr_cycle_count_t) {}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: fw_sim FIRMWARE.elf OUT.vcd [--faults SPEC] [--time-scale F]\n");
    return 2;
  }
  const char* elf = argv[1];
  const char* vcd_path = argv[2];
  Faults faults;
  double time_scale = 1.0;
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--faults" && i + 1 < argc) faults = parse_faults(argv[++i]);
    else if (a == "--time-scale" && i + 1 < argc) time_scale = std::atof(argv[++i]);
    else {
      std::fprintf(stderr, "fw_sim: unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  if (!(time_scale > 0)) {
    std::fprintf(stderr, "fw_sim: --time-scale must be positive\n");
    return 2;
  }

  // simavr reports on stdout while it loads; stdout carries only the pty's path
  std::fflush(stdout);
  const int saved_stdout = ::dup(1);
  ::dup2(2, 1);
  elf_firmware_t fw;
  std::memset(&fw, 0, sizeof fw);
  if (elf_read_firmware(elf, &fw) != 0) {
    std::fprintf(stderr, "fw_sim: cannot read %s\n", elf);
    return 3;
  }
  std::strcpy(fw.mmcu, "atmega328p");
  fw.frequency = 16000000;
  avr_t* avr = avr_make_mcu_by_name(fw.mmcu);
  if (!avr) {
    std::fprintf(stderr, "fw_sim: simavr has no atmega328p\n");
    return 3;
  }
  avr_init(avr);
  avr_load_firmware(avr, &fw);
  avr->frequency = fw.frequency;
  // the RAM above the variables painted, to find the stack's deepest point at the end
  const uint32_t ram_vars_end = 0x100 + fw.datasize + fw.bsssize;
  for (uint32_t a = ram_vars_end; a <= avr->ramend; ++a) avr->data[a] = kPaint;
  avr->sleep = no_sleep;
  // INT0 and INT1 share PD2 and PD3 with the step pins: simavr polls a low pin every cycle for a level-triggered
  // interrupt even while it is masked, which stops the simulator from sleeping. The firmware uses no external
  // interrupt.
  avr_extint_set_strict_lvl_trig(avr, 0, 0);
  avr_extint_set_strict_lvl_trig(avr, 1, 0);
  // simavr sizes its sleep steps before it knows the clock (a step of one cycle): sleep up to 1 ms at a time
  avr->run_cycle_limit = fw.frequency / 1000;
  avr->log = 0;

  // UART: no console printing, no polling sleeps; bytes through the bridge
  uint32_t flags = 0;
  avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
  flags &= ~(AVR_UART_FLAG_STDIO | AVR_UART_FLAG_POLL_SLEEP);
  avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
  Line to_host(&faults, faults.seed * 2 + 1), to_board(&faults, faults.seed * 2 + 2);
  Bridge br;
  br.avr = avr;
  br.to_host = &to_host;
  br.to_avr = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT), on_uart_out, &br);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XON), on_xon, &br);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XOFF), on_xoff, &br);

  avr_vcd_t vcd;
  avr_vcd_init(avr, vcd_path, &vcd, 100000);
  avr_vcd_add_signal(&vcd, avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('D'), 2), 1, "r_step");
  avr_vcd_add_signal(&vcd, avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('D'), 5), 1, "r_dir");
  avr_vcd_add_signal(&vcd, avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('D'), 3), 1, "theta_step");
  avr_vcd_add_signal(&vcd, avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('D'), 6), 1, "theta_dir");
  avr_vcd_add_signal(&vcd, avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('B'), 0), 1, "enable");
  avr_vcd_add_signal(&vcd, avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('B'), 5), 1, "run");
  avr_vcd_add_signal(&vcd, avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('B'), 4), 1, "tool");
  avr_vcd_start(&vcd);
  std::fflush(stdout);
  ::dup2(saved_stdout, 1);
  ::close(saved_stdout);

  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || ::grantpt(master) != 0 || ::unlockpt(master) != 0) {
    std::fprintf(stderr, "fw_sim: cannot create a pseudo-terminal: %s\n", std::strerror(errno));
    return 3;
  }
  const std::string path = ::ptsname(master);
  termios tio{};
  tcgetattr(master, &tio);
  cfmakeraw(&tio);
  tcsetattr(master, TCSANOW, &tio);
  const int keep = ::open(path.c_str(), O_RDWR | O_NOCTTY);  // the pty outlives each host connection
  fcntl(master, F_SETFL, fcntl(master, F_GETFL) | O_NONBLOCK);
  std::printf("%s\n", path.c_str());
  std::fflush(stdout);
  signal(SIGTERM, on_term);
  signal(SIGINT, on_term);
  signal(SIGPIPE, SIG_IGN);

  using clk = std::chrono::steady_clock;
  const auto t0 = clk::now();
  int state = cpu_Running;
  double max_lag_s = 0;  // how far the simulated clock fell behind the wall clock (a starved simulator)
  while (!g_quit && state != cpu_Done && state != cpu_Crashed) {
    // host -> board: bytes from the pty while the bridge holds few (a UART's back-pressure), then into the board
    if (br.in.size() < 64) {
      uint8_t buf[64];
      const ssize_t n = ::read(master, buf, sizeof buf);
      for (ssize_t i = 0; i < n; ++i) {
        uint8_t c = buf[i];
        if (to_board.pass(c)) br.in.push_back(c);
      }
    }
    while (br.xon && !br.in.empty()) {
      avr_raise_irq(br.to_avr, br.in.front());
      br.in.pop_front();
    }
    // board -> host
    while (!br.out.empty()) {
      uint8_t buf[256];
      size_t n = 0;
      while (n < sizeof buf && n < br.out.size()) buf[n] = br.out[n], ++n;
      const ssize_t w = ::write(master, buf, n);
      if (w <= 0) break;
      br.out.erase(br.out.begin(), br.out.begin() + w);
    }
    // run 1 ms of simulated time, then wait for the wall clock to catch up
    const avr_cycle_count_t until = avr->cycle + fw.frequency / 1000;
    while (avr->cycle < until && state != cpu_Done && state != cpu_Crashed) state = avr_run(avr);
    const double sim_s = static_cast<double>(avr->cycle) / fw.frequency;
    const double wall_s = std::chrono::duration<double>(clk::now() - t0).count() * time_scale;
    max_lag_s = std::max(max_lag_s, (wall_s - sim_s) / time_scale);
    if (sim_s > wall_s) {
      pollfd p{master, POLLIN, 0};
      ::poll(&p, 1, static_cast<int>((sim_s - wall_s) / time_scale * 1000));
    }
  }
  avr_vcd_stop(&vcd);
  avr_vcd_close(&vcd);
  uint32_t untouched = ram_vars_end;
  while (untouched <= avr->ramend && avr->data[untouched] == kPaint) ++untouched;
  std::fprintf(stderr, "fw_sim: %.3f s simulated; RAM %u bytes of variables, stack at most %u bytes, %u never used; to the board %llu bytes dropped, %llu corrupted; to the host %llu dropped, %llu corrupted; at most %.1f ms behind the wall clock%s\n",
               static_cast<double>(avr->cycle) / fw.frequency, ram_vars_end - 0x100, avr->ramend + 1 - untouched,
               untouched - ram_vars_end, static_cast<unsigned long long>(to_board.dropped),
               static_cast<unsigned long long>(to_board.corrupted), static_cast<unsigned long long>(to_host.dropped),
               static_cast<unsigned long long>(to_host.corrupted), max_lag_s * 1e3, state == cpu_Crashed ? " (the firmware crashed)" : "");
  ::close(keep);
  ::close(master);
  return state == cpu_Crashed ? 4 : 0;
}
