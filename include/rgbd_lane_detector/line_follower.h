/**
 * @file line_follower.h
 * @brief Following a traced line row by row onto the paint's centre (or a road edge onto where
 * the road ends), across dash gaps, and centring a double line (the boundary classifier's line
 * following).
 */
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/band_profile.h"
#include "rgbd_lane_detector/classifier_input.h"
#include "rgbd_lane_detector/params.h"

namespace rgbd_lane_detector {

/**
 * @brief Follows lines row by row (BoundaryClassifier::followLine(), followEdge(),
 * centreDoubleLine() document the methods). Reuses its buffers (no allocation in steady state).
 */
class LineFollower {
 public:
  /// m either side of a traced line's column where followLine() seeks its paint by default
  static constexpr double kTraceReach = 0.15;
  /// Pixels of a line the per-line buffers are reserved for (they grow past them once, on a
  /// taller image).
  static constexpr size_t kReservedPixels = 4096;
  LineFollower();

  /// Paint row by row from the trace (BoundaryClassifier::followLine()).
  int followLine(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                 std::vector<Eigen::Vector3f>& points, const Params& p, double max_gap,
                 double max_range, double reach = kTraceReach, bool painted = false,
                 bool seed_line = false);

  /// A road edge row by row from the trace (BoundaryClassifier::followEdge()).
  int followEdge(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                 std::vector<Eigen::Vector3f>& points, bool left, const Params& p, double max_gap,
                 double max_range, double reach = 0.7);

  /// A double line moved onto its centre (BoundaryClassifier::centreDoubleLine()).
  bool centreDoubleLine(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                        std::vector<Eigen::Vector3f>& points, const Params& p);

 private:
  /// The row walk of followLine() and followEdge(): @p find(v, u, ppm, from_trace, column,
  /// steers) seeks the boundary on row v near column u (ppm pixels per metre across the road; u
  /// predicted from the trace, or from the steering rows found); steers: the row found may
  /// predict the next rows' column (set false for a band that is not paint-like). @p seed_line:
  /// the trace is the straight line through a seed, which continues below it until the rows
  /// found there form a stretch of paint.
  template <typename FindInRow>
  int followRows(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                 std::vector<Eigen::Vector3f>& points, double max_gap, double max_range,
                 bool seed_line, FindInRow&& find);

  BandProfile profile_;
  std::vector<cv::Point2f> followed_;       ///< rows found from the trace's nearest row on
  std::vector<cv::Point2f> followed_near_;  ///< rows found below the trace's start
  std::vector<double> follow_f_;  ///< forward distance (m) of each row found in one direction
  std::vector<char> follow_steers_;  ///< whether each of them steers the line (paint-like)
  std::vector<float> twin_[2];    ///< centreDoubleLine(): offsets (m) of the second band, per side
};

}  // namespace rgbd_lane_detector
