// The host side of the controller protocol (machine/link/host_link.hpp, protocol.hpp): what a controller (or a
// damaged line) sends is the input. HostLink identifies the controller over a transport that delivers the input
// in pieces on a simulated clock and, when it answers, plays a small plan to it (configure, queue, start, status,
// acknowledgements, NAKs, errors, BOOT); every frame of the input also goes through the payload decoders.
// A run ends when the input is exhausted and the host's timeouts expire (a device error).
#include "fuzz/protocol_frames.hpp"
#include "machine/link/host_link.hpp"
#include "machine/player/schedule.hpp"

namespace {

class FuzzTransport : public polarcam::Transport {
 public:
  explicit FuzzTransport(std::string in) : in_(std::move(in)) {}
  bool write(const std::string&, double) override { return true; }
  std::string read(double timeout_s) override {
    if (pos_ >= in_.size()) {
      now_ += timeout_s;
      return {};
    }
    // pieces of 1..32 bytes, their lengths from the bytes themselves
    const size_t n = std::min<size_t>(in_.size() - pos_, 1 + static_cast<uint8_t>(in_[pos_]) % 32);
    std::string s = in_.substr(pos_, n);
    pos_ += n;
    now_ += 1e-4;
    return s;
  }
  double now() override { return now_; }
  std::string describe() const override { return "fuzz"; }

 private:
  std::string in_;
  size_t pos_ = 0;
  double now_ = 0;
};

// Twelve steps (radial out, angular on, radial back) on a 0.1 mm / 0.1 degree grid, one every millisecond, the tool
// lifted over the angular ones.
polarcam::PlayPlan small_plan() {
  polarcam::PlayPlan p;
  p.tape = "fuzz.tape";
  p.header.tick_ps = 1000;
  p.header.res[0] = 1e-4;
  p.header.res[1] = 2 * M_PI / 3600;
  p.header.steps_per_rev = 3600;
  p.start[0] = p.end[0] = 500;
  const int axes[12] = {0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0};
  const int dirs[12] = {1, 1, 1, 1, 1, 1, 1, 1, -1, -1, -1, -1};
  for (int i = 0; i < 12; ++i) {
    p.steps.push_back({static_cast<uint64_t>(i + 1) * 1000000, static_cast<uint64_t>(i + 1),
                       static_cast<uint8_t>(axes[i]), static_cast<int8_t>(dirs[i])});
    ++p.steps_per_axis[axes[i]];
  }
  p.end[1] = 4;
  p.lo[0] = 500, p.hi[0] = 504, p.hi[1] = 4;
  // a lifting tape's tool items: down at the start, up after the radial steps out, down again before they come back
  p.header.event_count = 2;
  p.tools = {{0, 0, true}, {4500000, 4, false}, {8500000, 8, true}};
  p.tool_dwell_s = 0.002;
  return p;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace polarcam;
  static const PlayPlan plan = small_plan();
  const std::string stream = fuzz::protocol_stream(data, size);
  fuzz::decode_payloads(stream);
  fuzz::expect_typed([&] {
    FuzzTransport t(stream);
    HostLink link(t, LinkOptions{});
    const proto::Ident id = link.identify();
    link.play(plan, compress_schedule(plan, id.tick_ps));
  });
  return 0;
}
