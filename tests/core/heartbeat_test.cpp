#include "scanmesh/heartbeat.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

using namespace scanmesh;

TEST(Heartbeat, SaysItIsRunningUntilDestroyedAndNotAfter) {
  std::atomic<int> calls{0};
  std::atomic<double> last{0.0};
  {
    const Heartbeat beat(0.01, [&](double seconds) {
      last = seconds;
      ++calls;
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  const int seen = calls;
  EXPECT_GE(seen, 1);
  EXPECT_GE(last.load(), 0.01);  // the time since it started, not since the last call
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(calls.load(), seen) << "no call after destruction";
}

TEST(Heartbeat, AStepShorterThanThePeriodSaysNothingAndDoesNotWaitForIt) {
  std::atomic<int> calls{0};
  const auto start = std::chrono::steady_clock::now();
  { const Heartbeat beat(3600.0, [&](double) { ++calls; }); }
  EXPECT_EQ(calls.load(), 0);
  // Destruction wakes the thread: far less than the hour-long period (any scheduler delay is far below it).
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 60.0);
}
