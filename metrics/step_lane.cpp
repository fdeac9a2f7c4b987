#include "metrics/step_lane.hpp"

namespace polarcam {

StepLane::StepLane(Consumer consume) : consume_(std::move(consume)) {
  for (auto& b : buf_) b.resize(kBlock);
  cur_ = buf_[0].data();
  th_ = std::thread([this] { run(); });
}

StepLane::~StepLane() {
  {
    std::lock_guard<std::mutex> lk(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  if (th_.joinable()) th_.join();
}

void StepLane::hand_over() {
  std::unique_lock<std::mutex> lk(mu_);
  len_[given_ % kBlocks] = fill_;
  ++given_;
  cv_.notify_all();
  // the next block to fill must not be one the consumer still holds
  cv_.wait(lk, [&] { return given_ - taken_ < kBlocks || stop_; });
  cur_ = buf_[given_ % kBlocks].data();
  fill_ = 0;
}

void StepLane::close() {
  if (!th_.joinable()) return;
  if (fill_ > 0) hand_over();
  {
    std::lock_guard<std::mutex> lk(mu_);
    closing_ = true;
  }
  cv_.notify_all();
  th_.join();
  if (err_) std::rethrow_exception(err_);
}

void StepLane::run() {
  for (;;) {
    uint64_t b;
    {
      std::unique_lock<std::mutex> lk(mu_);
      cv_.wait(lk, [&] { return taken_ < given_ || closing_ || stop_; });
      if (stop_ || taken_ == given_) return;  // stopped, or closing with nothing left
      b = taken_;
    }
    if (!err_) {
      try {
        consume_(buf_[b % kBlocks].data(), len_[b % kBlocks]);
      } catch (...) {
        err_ = std::current_exception();  // the rest is dropped; close() rethrows it
      }
    }
    {
      std::lock_guard<std::mutex> lk(mu_);
      ++taken_;
    }
    cv_.notify_all();
  }
}

}  // namespace polarcam
