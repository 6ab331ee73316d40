/**
 * @file lane_tracker.h
 * @brief Temporal filtering of the lane markers in the road plane (an improvement over the
 * paper, named option `track_lanes`).
 *
 * A dashed marker often shows no paint near the car, or a single far dash that yields a few
 * traced points: frame by frame the side is then lost. Each side is modelled in the road plane
 * as lateral(f) = a + b f + c f^2 over the forward distance f, estimated by recursive least
 * squares with exponential forgetting from the traced points of the recent frames. The model
 * bridges dash gaps and short occlusions, and is dropped after a number of frames without
 * evidence.
 */
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/// Road-plane coordinates: origin below the camera, forward (optical axis projected into the
/// plane) and lateral (right) axes.
struct PlaneFrame {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d forward = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d lateral = Eigen::Vector3d::UnitX();
  bool valid = false;

  /// Frame of a valid plane (invalid when the optical axis is perpendicular to the plane).
  static PlaneFrame fromPlane(const PlaneEstimate& plane);
  /// (forward, lateral) of a camera-frame point.
  Eigen::Vector2d toPlane(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d q = p - origin;
    return Eigen::Vector2d(forward.dot(q), lateral.dot(q));
  }
  /// Camera-frame point of plane coordinates.
  Eigen::Vector3d toCamera(double f, double l) const { return origin + f * forward + l * lateral; }
};

/// Settings of the tracker.
struct TrackerParams {
  double memory = 0.7;      ///< forgetting factor per frame of the least-squares sums
  int max_age = 10;         ///< frames a side survives without evidence
  double gate = 0.5;        ///< measurements farther than this (m) from an established model are outliers
  int min_points = 5;       ///< traced points a frame needs to count as evidence
  double sample_step = 0.5; ///< spacing of the reported marker points (m)
};

/// Lane marker model of one side.
class SideModel {
 public:
  void reset();
  /// True when the model has evidence no older than max_age frames.
  bool valid() const { return valid_; }
  int age() const { return age_; }
  double lateral(double f) const;
  /// Forward range covered by the evidence of the recent frames.
  double nearest() const;
  double farthest() const;

  /**
   * @brief One frame: forget, then add the measurements (plane coordinates) that pass the gate.
   * @return number of measurements accepted.
   */
  int update(const std::vector<Eigen::Vector2d>& measurements, const TrackerParams& params);

 private:
  static Eigen::Vector3d basis(double f);
  void solve();
  Eigen::Matrix3d A_ = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d coef_ = Eigen::Vector3d::Zero();
  std::array<Eigen::Vector2d, 6> extents_;  ///< (near, far) of the last frames with evidence
  int num_extents_ = 0;
  int next_extent_ = 0;
  int age_ = 0;
  int frames_with_evidence_ = 0;
  bool valid_ = false;
};

/**
 * @brief Both sides of the ego lane, tracked in the road plane.
 */
class LaneTracker {
 public:
  void reset();
  SideModel& side(int i) { return sides_[i]; }
  const SideModel& side(int i) const { return sides_[i]; }

  /**
   * @brief Update one side with this frame's traced points.
   * @param[in] i 0 left, 1 right.
   * @param[in] frame plane frame of this frame's lane plane.
   * @param[in] points traced 3D points (non-finite entries skipped).
   * @param[in] params settings.
   * @param[in,out] scratch buffer reused across calls.
   * @return measurements accepted.
   */
  int update(int i, const PlaneFrame& frame, const std::vector<Eigen::Vector3f>& points,
             const TrackerParams& params, std::vector<Eigen::Vector2d>& scratch);

  /**
   * @brief Points of a side's model over the forward range of the lane's recent evidence (both
   * sides: a dashed boundary is a boundary along the whole observed lane).
   * @param[in] i side.
   * @param[in] frame plane frame to express them in.
   * @param[in] step spacing (m).
   * @param[out] out camera-frame points, near to far (cleared first).
   */
  void sample(int i, const PlaneFrame& frame, double step, std::vector<Eigen::Vector3f>& out) const;

 private:
  std::array<SideModel, 2> sides_;
};

}  // namespace rgbd_lane_detector
