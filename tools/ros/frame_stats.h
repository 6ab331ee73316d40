/**
 * @file frame_stats.h
 * @brief ROS-free bookkeeping of FramePlayerNodelet: which published frames came back as an
 * output, and the latency of each (now - header.stamp at receipt), summarised as
 * mean / p50 / p99 / max. Frames are keyed by their stamp (nanoseconds), which the player makes
 * unique and the detector copies into every output.
 */
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace rgbd_lane_detector {
namespace tools {

/// Summary of a run (counts and latency in milliseconds).
struct FrameSummary {
  int64_t published = 0;   ///< frames published while measuring (after the warm-up)
  int64_t outputs = 0;     ///< of those, frames whose output arrived (each counted once)
  int64_t lost = 0;        ///< published - outputs
  int64_t duplicates = 0;  ///< outputs received again for a frame already counted
  int64_t unknown = 0;     ///< outputs whose stamp is no frame published while measuring
  int64_t warmup_published = 0;  ///< frames published during the warm-up
  int64_t warmup_outputs = 0;    ///< of those, frames whose output arrived
  double mean_ms = 0.0, p50_ms = 0.0, p99_ms = 0.0, max_ms = 0.0;
};

/**
 * @brief Published frames and their outputs. Not thread-safe: the caller holds a mutex.
 * published() before the output can arrive (the player records a frame before publishing it).
 */
class FrameStats {
 public:
  /// @param expected frames expected, to reserve (no allocation per frame below it).
  explicit FrameStats(size_t expected = 0) {
    latencies_ms_.reserve(expected);
    frames_.reserve(expected * 2 + 16);
  }
  /// A frame with stamp @p stamp_ns was published; @p warmup: during the warm-up.
  void published(int64_t stamp_ns, bool warmup) {
    frames_[stamp_ns] = warmup ? kWarmup : kWaiting;
    if (warmup)
      ++summary_.warmup_published;
    else
      ++summary_.published;
  }
  /// An output of the frame with stamp @p stamp_ns arrived @p latency_ms after its stamp.
  void output(int64_t stamp_ns, double latency_ms) {
    const auto it = frames_.find(stamp_ns);
    if (it == frames_.end()) {
      ++summary_.unknown;
      return;
    }
    switch (it->second) {
      case kWarmup:
        ++summary_.warmup_outputs;
        it->second = kWarmupDone;
        return;
      case kWaiting:
        ++summary_.outputs;
        it->second = kDone;
        latencies_ms_.push_back(latency_ms);
        return;
      default:
        ++summary_.duplicates;
        return;
    }
  }
  /// Frames (measured ones) whose output has not arrived yet.
  int64_t outstanding() const { return summary_.published - summary_.outputs; }
  /// Every frame published so far, warm-up included, has its output.
  bool allBack() const {
    return summary_.published == summary_.outputs &&
           summary_.warmup_published == summary_.warmup_outputs;
  }
  FrameSummary summary() const {
    FrameSummary s = summary_;
    s.lost = s.published - s.outputs;
    if (!latencies_ms_.empty()) {
      std::vector<double> v = latencies_ms_;
      std::sort(v.begin(), v.end());
      double sum = 0.0;
      for (double x : v) sum += x;
      s.mean_ms = sum / static_cast<double>(v.size());
      s.p50_ms = quantile(v, 0.50);
      s.p99_ms = quantile(v, 0.99);
      s.max_ms = v.back();
    }
    return s;
  }
  /// Nearest-rank quantile of sorted values (q in [0, 1]).
  static double quantile(const std::vector<double>& sorted, double q) {
    if (sorted.empty()) return 0.0;
    const double rank = q * static_cast<double>(sorted.size());
    size_t i = static_cast<size_t>(rank);
    if (static_cast<double>(i) < rank) ++i;  // ceil
    if (i > 0) --i;                          // 1-based rank to index
    return sorted[std::min(i, sorted.size() - 1)];
  }

 private:
  enum State : uint8_t { kWarmup, kWarmupDone, kWaiting, kDone };
  std::unordered_map<int64_t, State> frames_;
  std::vector<double> latencies_ms_;
  FrameSummary summary_;
};

}  // namespace tools
}  // namespace rgbd_lane_detector
