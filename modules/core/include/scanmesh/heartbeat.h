#pragma once
// "Still running" lines for long calls that report nothing themselves (PCL's greedy projection and
// Poisson take minutes on large clouds and print no progress).
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace scanmesh {

/// How often a long step without progress lines of its own says it is still running, seconds: the
/// pipeline's stages and the PCL meshing calls inside a stage use the same period.
constexpr double kHeartbeatSeconds = 10.0;

/// While alive, calls `say(seconds since construction)` every `period_seconds` from a thread of its own.
/// A step shorter than the period says nothing; destruction stops and joins the thread at once (it does
/// not wait for the period to end). `say` must not race with the caller: use it around a call during
/// which the caller itself says nothing.
class Heartbeat {
 public:
  Heartbeat(double period_seconds, std::function<void(double)> say);
  ~Heartbeat();
  Heartbeat(const Heartbeat&) = delete;
  Heartbeat& operator=(const Heartbeat&) = delete;

 private:
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace scanmesh
