#include "io/temp_files.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstring>

namespace polarcam {
namespace {

// The registry: fixed slots, so that the signal handler reads it with async-signal-safe operations only (lock-free
// atomics and unlink). A slot is free (0), being written (1) or holds a name (2).
constexpr int kSlots = 64;
constexpr size_t kMaxPath = 4096;
struct Slot {
  std::atomic<int> state{0};
  char path[kMaxPath];
};
Slot g_slots[kSlots];
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs lock-free atomics");

extern "C" void remove_and_reraise(int sig) {
  for (Slot& s : g_slots)
    if (s.state.load() == 2) ::unlink(s.path);
  ::signal(sig, SIG_DFL);  // then die of the same signal: the parent sees how the run ended
  ::raise(sig);
}

int take_slot(const std::string& path) {
  if (path.size() >= kMaxPath) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (g_slots[i].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
      g_slots[i].state.store(2);
      return i;
    }
  }
  return -1;
}

}  // namespace

void remove_temporaries_on_signal() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    struct sigaction sa {};
    sa.sa_handler = remove_and_reraise;
    sigemptyset(&sa.sa_mask);
    ::sigaction(sig, &sa, nullptr);
  }
}

TempFile::TempFile(std::string path) : path_(std::move(path)), slot_(take_slot(path_)) {}

TempFile::~TempFile() {
  if (!kept_) std::remove(path_.c_str());
  if (slot_ >= 0) g_slots[slot_].state.store(0);
}

void TempFile::keep() {
  kept_ = true;
  if (slot_ >= 0) g_slots[slot_].state.store(0);
  slot_ = -1;
}

int registered_temporaries() {
  int n = 0;
  for (const Slot& s : g_slots) n += s.state.load() == 2;
  return n;
}

}  // namespace polarcam
