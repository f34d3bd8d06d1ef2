#include "scanmesh/heartbeat.h"

#include <chrono>

namespace scanmesh {

Heartbeat::Heartbeat(double period_seconds, std::function<void(double)> say) {
  if (!say || !(period_seconds > 0.0)) return;
  thread_ = std::thread([this, period_seconds, say = std::move(say)] {
    const auto start = std::chrono::steady_clock::now();
    const auto period = std::chrono::duration<double>(period_seconds);
    auto next = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
    std::unique_lock<std::mutex> lock(mutex_);
    while (!wake_.wait_until(lock, next, [this] { return stop_; })) {
      say(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
    }
  });
}

Heartbeat::~Heartbeat() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

}  // namespace scanmesh
