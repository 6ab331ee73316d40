// StageTimer: the time of its scope, added to the stage's timing.
#include <chrono>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/stage_timer.h"

namespace rgbd_lane_detector {
namespace {

TEST(StageTimer, AddsTheTimeOfItsScope) {
  double ms = 0.0;
  const auto before = StageTimer::Clock::now();
  {
    const StageTimer timer(ms);
    // 2 ms from a moment after the timer started: its scope lasts at least that long
    const auto inside = StageTimer::Clock::now();
    while (StageTimer::Clock::now() - inside < std::chrono::milliseconds(2)) {
    }
  }
  const double outer =
      std::chrono::duration<double, std::milli>(StageTimer::Clock::now() - before).count();
  EXPECT_GE(ms, 2.0);
  EXPECT_LE(ms, outer);  // no more than the time around it
}

TEST(StageTimer, AccumulatesOverScopes) {
  double ms = 5.0;
  { const StageTimer timer(ms); }
  EXPECT_GE(ms, 5.0);
  const double once = ms;
  { const StageTimer timer(ms); }
  EXPECT_GE(ms, once);
}

}  // namespace
}  // namespace rgbd_lane_detector
