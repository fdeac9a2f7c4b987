#pragma once
// A lane of steps to a thread of its own: the producer pushes one byte a step, the consumer (a function called with
// blocks of bytes, in order, on the lane's thread) measures them. The producer waits only when the consumer is a
// few blocks behind, so memory stays constant. Used to run the area meter beside the deviation
// (error_metrics.hpp): each measure sees every step in order, so the results are those of one thread.
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace polarcam {

class StepLane {
 public:
  using Consumer = std::function<void(const uint8_t* steps, size_t count)>;
  explicit StepLane(Consumer consume);
  ~StepLane();  // stops the consumer (what it has not taken is dropped) and joins its thread
  StepLane(const StepLane&) = delete;
  StepLane& operator=(const StepLane&) = delete;

  void push(uint8_t s) {
    cur_[fill_++] = s;
    if (fill_ == kBlock) hand_over();
  }
  // Hands the rest over and waits until the consumer has taken every step; rethrows what the consumer threw.
  void close();

 private:
  static constexpr size_t kBlock = size_t{1} << 15, kBlocks = 4;
  void hand_over();
  void run();

  Consumer consume_;
  std::vector<uint8_t> buf_[kBlocks];
  size_t len_[kBlocks] = {};
  uint8_t* cur_ = nullptr;
  size_t fill_ = 0;
  // blocks [taken_, given_) (modulo kBlocks) are the consumer's; the producer fills block given_ % kBlocks
  uint64_t given_ = 0, taken_ = 0;
  bool closing_ = false, stop_ = false;
  std::exception_ptr err_;
  std::mutex mu_;
  std::condition_variable cv_;
  std::thread th_;
};

}  // namespace polarcam
