/**
 * @file lane_detector.h
 * @brief The detector facade: runs every stage of the method in order on one RGB-D frame.
 */
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/fals_normals.h"
#include "rgbd_lane_detector/lane_tracker.h"
#include "rgbd_lane_detector/line_template.h"
#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/template_matching.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/**
 * @brief Lane marker and lane plane detector (Quach et al.), ROS-free.
 *
 * Carries state between frames: the PCA-refined template angles and, with the temporal
 * options, the previous plane. Call reset() when the stream restarts (rosbag loop, seek).
 * Not thread-safe: one detector per thread. Buffers are allocated on the first frame and on
 * size changes only, so with a reused Result the steady state does not allocate.
 */
class LaneDetector {
 public:
  explicit LaneDetector(const Params& params = Params());

  /// Replace the parameters (sanitised); applies from the next detect().
  void setParams(const Params& params);
  const Params& params() const { return params_; }

  /// Forget carried state (template angles, previous plane).
  void reset();

  /**
   * @brief Detect the lane markers and the lane plane in one frame.
   * @param[in] frame colour, registered depth and intrinsics (read in place).
   * @param[out] result reused output; see Result for buffer lifetimes.
   * @return result.status; on anything but Status::kOk the result holds no detection and the
   *         carried state is unchanged.
   */
  Status detect(const Frame& frame, Result& result);

  /// Check a frame without processing it.
  Status validate(const Frame& frame) const;

  /// Templates that the next detect() will use.
  const LineTemplate& leftTemplate() const { return left_template_; }
  const LineTemplate& rightTemplate() const { return right_template_; }

 private:
  void prepareGeometry(const Frame& frame);
  void resampleColour(const Frame& frame);
  void applyPlaneGate(const cv::Range& rows);
  /// road_gate: true when the surface normal at a processing pixel is known and not road-like.
  bool offRoad(const cv::Point& pixel) const;
  void findSeed(cv::Mat& R, bool left, cv::Point& peak, float& value);
  void findBestMatch(const cv::Mat& R, bool left, cv::Point& peak, float& value);
  /// Columns near a side's predicted marker, per row of @p area (band_lo_/band_hi_);
  /// false: no prediction.
  bool predictedBand(int side, const cv::Rect& area);
  bool plausibleMarkerAngle(double angle, bool left) const;
  void buildTrace(const cv::Mat& R, const cv::Point& peak, float peak_value, double angle,
                  MarkerTrace& trace);
  /// 3D point of a processing-image pixel: its own, else the nearest valid depth in its box
  /// on the pixel's ray, else NaN (never a zero depth).
  Eigen::Vector3f pointAt(const cv::Point2f& c) const;
  void fitPlane(Result& result);
  /// fitPlane() with the temporal lane model (track_lanes).
  void fitTracked(Result& result);
  bool planePlausible(const PlaneEstimate& plane) const;
  void snapToPlane(const PlaneEstimate& plane, MarkerTrace& m) const;
  bool laneWidthPlausible(const PlaneEstimate& plane, const MarkerTrace& L,
                          const MarkerTrace& R) const;
  void rejectIncomplete(Result& result) const;
  void updateTemplates(const Result& result);

  Params params_;
  // carried state
  double next_left_angle_ = 0.0;
  double next_right_angle_ = 0.0;
  PlaneEstimate previous_plane_;
  bool templates_dirty_ = true;

  // geometry of the processing image
  cv::Size input_size_;
  cv::Size proc_size_;
  double scale_ = 1.0;
  Intrinsics proc_K_;
  cv::Rect roi_;
  cv::Mat col_map_, row_map_;  ///< CV_32SC1 source column / row of each processing pixel

  // per-frame buffers (allocated on size change only)
  cv::Mat colour_small_;
  cv::Mat half_binary_;
  cv::Mat points_;
  cv::Mat geometric_;
  cv::Mat response_left_, response_right_;

  FalsNormals fals_;
  NccMatcher matcher_;
  LineTemplate left_template_, right_template_;
  std::vector<cv::Point> pca_stack_;
  std::vector<uint8_t> pca_visited_;
  std::vector<cv::Point2f> trace_pixels_;
  std::vector<float> trace_scores_;
  std::vector<Eigen::Vector3f> fit_points_;
  mutable std::vector<double> width_samples_;
  LaneTracker tracker_;
  std::vector<Eigen::Vector3f> samples_;
  const std::vector<Eigen::Vector3f> samples_none_;
  std::vector<int> band_lo_, band_hi_;
  std::vector<int> row_histogram_;
};

}  // namespace rgbd_lane_detector
