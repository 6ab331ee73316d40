/**
 * @file stage_timer.h
 * @brief The wall-clock time of a scope added to a stage's timing (StageTimings), so that a stage
 * is timed by one declaration and no timing code runs between the stages.
 */
#pragma once

#include <chrono>

namespace rgbd_lane_detector {

/// Adds the wall-clock time (ms) from its construction to its destruction to @p ms.
class StageTimer {
 public:
  using Clock = std::chrono::steady_clock;
  explicit StageTimer(double& ms) : ms_(ms), start_(Clock::now()) {}
  ~StageTimer() { ms_ += std::chrono::duration<double, std::milli>(Clock::now() - start_).count(); }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  double& ms_;
  Clock::time_point start_;
};

}  // namespace rgbd_lane_detector
