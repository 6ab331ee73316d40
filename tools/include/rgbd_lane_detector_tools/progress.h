/**
 * @file progress.h
 * @brief A one-line progress bar on stderr, redrawn in place with '\r'.
 */
#pragma once

#include <chrono>
#include <string>

namespace rgbd_lane_detector {
namespace tools {

/**
 * @brief Progress bar: "label [=====>    ]  120/300  40%  25.1 fps  ETA 7s  extra".
 * Redraws at most 10 times a second; finish() prints the final state and a newline.
 */
class ProgressBar {
 public:
  /**
   * @param[in] label text before the bar.
   * @param[in] total number of steps; <= 0 when unknown (no bar, counts only).
   * @param[in] enabled false: print nothing (--quiet).
   */
  ProgressBar(std::string label, int total, bool enabled = true);
  ~ProgressBar();
  /// Set the number of steps done and an optional status text.
  void update(int done, const std::string& extra = std::string());
  /// Draw the final state and end the line (idempotent).
  void finish();

 private:
  void draw();
  std::string label_;
  int total_;
  bool enabled_;
  bool finished_ = false;
  int done_ = 0;
  std::string extra_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool drawn_ = false;
  int last_drawn_done_ = -1;
};

}  // namespace tools
}  // namespace rgbd_lane_detector
