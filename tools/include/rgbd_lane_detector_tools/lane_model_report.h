/**
 * @file lane_model_report.h
 * @brief Collects the lane-model scores (lane_model_scoring.h) of evaluate_sequences per
 * sequence and mode, writes them per boundary to a CSV and as the Markdown tables of
 * docs/RESULTS.md, with the must-show figures checked. ROS-free.
 */
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "rgbd_lane_detector_tools/lane_model_scoring.h"

namespace rgbd_lane_detector {
namespace tools {

/// Targets of issue 14 ("must show"), checked in the report.
struct LaneModelTargets {
  double median_10 = 0.05;        ///< m: ego boundaries' lateral error at 10 m, median
  double p95_10 = 0.15;           ///< m: ... 95th percentile
  double median_40 = 0.25;        ///< m: ... at 40 m, median
  double curvature = 2e-4;        ///< 1/m: curvature error on the curve sequence, median
  double kind = 95.0;             ///< %: kind accuracy of matched boundaries
  double colour = 95.0;           ///< %: colour accuracy of matched paint boundaries
  double lane_change_worst = 0.5; ///< m: farthest published boundary on the lane change
  double confidence = 0.9;        ///< a confidence of at least this ...
  double confidence_correct = 85.0;  ///< % ... is right at least this often
};

/// Lane-model scores of several sequences and modes, and their report.
class LaneModelReport {
 public:
  /**
   * @param[in] csv per-boundary rows are written here (nullptr: none); the header at once.
   * @param[in] curve_sequence name of the curve scenario's sequence (curvature target).
   * @param[in] lane_change_sequence name of the lane-change sequence (worst-distance target).
   */
  explicit LaneModelReport(std::ostream* csv = nullptr, std::string curve_sequence = "curve",
                           std::string lane_change_sequence = "lane_change");

  /// Add frame @p frame of @p sequence scored for @p mode.
  void add(const std::string& sequence, const std::string& mode, int frame,
           const LaneModelScore& score);

  /// Nothing added yet.
  bool empty() const { return entries_.empty(); }

  /**
   * @brief The Markdown tables: ego lateral errors, geometry, kind and colour, F1, the worst
   * published boundary, the reliability table (pooled over the sequences) and the must-show
   * figures, per mode.
   * @param[out] md the text.
   * @param[in] title_suffix appended to the section titles (e.g. ", held out: seed 2").
   */
  void writeMarkdown(std::ostream& md, const std::string& title_suffix = "") const;

  /// All sequences of @p mode pooled.
  LaneModelSummary pooled(const std::string& mode) const;
  /// The summary of one sequence and mode (nullptr when absent).
  const LaneModelSummary* find(const std::string& sequence, const std::string& mode) const;

  LaneModelTargets targets;

 private:
  struct Entry {
    std::string sequence, mode;
    LaneModelSummary summary;
  };
  /// The modes added, in order of appearance.
  std::vector<std::string> modes() const;
  /// The must-show table of @p mode (all its sequences pooled; the curve and lane-change ones).
  void writeMustShow(std::ostream& md, const std::string& mode, const std::string& suffix) const;

  std::vector<Entry> entries_;
  std::ostream* csv_;
  std::string curve_, lane_change_;
};

}  // namespace tools
}  // namespace rgbd_lane_detector
