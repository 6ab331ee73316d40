/**
 * @file lane_tracker.h
 * @brief Temporal filtering of the lane boundaries in the road plane (an improvement over the
 * paper, named option `track_lanes`).
 *
 * A dashed marker often shows no paint near the car, or a single far dash that yields a few
 * traced points: frame by frame the side is then lost. The two boundaries of the ego lane are
 * modelled in the road plane (RoadFrame, y left) as curves lateral_i(f) = a_i + b_i f + c_i f^2 over the forward
 * distance f, estimated by recursive least squares with exponential forgetting from the traced
 * points of the recent frames. The two sides' shapes (b_i, c_i) are tied by a soft prior that
 * they are parallel: a side with little evidence (one short dash) takes its shape from the
 * other, while two well-seen sides keep their own (a kerb that leaves the lane before an
 * intersection, a lane that widens). The model bridges dash gaps and short occlusions, and a
 * side is dropped after a number of frames without evidence.
 */
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "rgbd_lane_detector/geometry.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/**
 * @brief Robust straight line lateral = a + b forward through road-plane points (forward,
 * lateral: RoadFrame's x, y): least squares, then twice more over the points within @p gate of
 * the last line.
 * @param[in] points (forward, lateral) points.
 * @param[in] gate inlier distance of the refits (m).
 * @param[out] a,b the line.
 * @return false when the points do not determine a line.
 */
bool fitRobustLine(const std::vector<Eigen::Vector2d>& points, double gate, double& a, double& b);

/// Settings of the tracker.
struct TrackerParams {
  double memory = 0.7;      ///< forgetting factor per frame of the least-squares sums
  int max_age = 10;         ///< frames a side survives without evidence
  double gate = 0.5;        ///< measurements farther than this (m) from an established model are outliers
  int min_points = 5;       ///< traced points a frame needs to count as evidence
  double sample_step = 0.5; ///< spacing of the reported marker points (m, before the 1/f spacing)
};

/**
 * @brief The ego lane's two markers, tracked in the road plane.
 */
class LaneTracker {
 public:
  LaneTracker() { reset(); }
  /// Forget both sides.
  void reset();
  /// Forget side @p i (0 left, 1 right); the other keeps its model.
  void resetSide(int i);
  /// The vehicle crossed side @p from's marker (a lane change): its model becomes the other
  /// side's, and side @p from starts over.
  void handOver(int from);

  /// True when side @p i (0 left, 1 right) has evidence no older than max_age frames.
  bool valid(int i) const { return sides_[i].valid; }
  /// True once a side has two frames of evidence (the model gates its measurements).
  bool established(int i) const { return sides_[i].valid && sides_[i].frames >= 2; }
  /// Frames since side @p i last had evidence (0: this frame).
  int age(int i) const { return sides_[i].age; }
  /// Frames with evidence of side @p i since its model started.
  int frames(int i) const { return sides_[i].frames; }
  /// Lateral position (RoadFrame y, + left) of side @p i at forward distance @p f (m).
  double lateral(int i, double f) const;

  /**
   * @brief Update both sides with this frame's traced points.
   *
   * The camera's own sideways motion and yaw move both markers alike: the model is first moved
   * and turned by the sideways speed and turn rate of the recent frames (a lane change, a drift:
   * a side without evidence follows it), then turned by the slope of this frame's points'
   * disagreement with the established model and moved by their median disagreement (which also
   * update that turn rate and speed), then the points that pass the gate are added.
   * @param[in] frame road frame of this frame's lane plane (invalid: no evidence, sides age).
   * @param[in] left,right traced 3D points of each side (non-finite entries skipped; empty: no
   *            evidence for that side).
   * @param[in] params settings.
   */
  void update(const RoadFrame& frame, const std::vector<Eigen::Vector3f>& left,
              const std::vector<Eigen::Vector3f>& right, const TrackerParams& params);

  /// sample()'s @p beyond for a painted line (m): it continues past where it was seen.
  static constexpr double kPaintExtrapolation = 4.0;
  /// sample()'s @p beyond for a road edge (m): kerbs end at driveways and intersections.
  static constexpr double kEdgeExtrapolation = 2.0;

  /**
   * @brief Points of a side over the forward range of the lane's recent evidence (both sides: a
   * dashed boundary is a boundary along the whole observed lane), but at most @p beyond metres
   * past the side's own evidence at either end, spaced uniformly in 1/f (about uniformly in
   * image rows, like traced centroids). Nothing when that range is shorter than 2 m.
   * @param[in] i side.
   * @param[in] frame road frame to express them in.
   * @param[in] step nominal spacing (m).
   * @param[out] out camera-frame points, near to far (cleared first).
   * @param[in] beyond how far past its own evidence a side is reported (m).
   */
  void sample(int i, const RoadFrame& frame, double step, std::vector<Eigen::Vector3f>& out,
              double beyond = kPaintExtrapolation) const;

 private:
  struct Side {
    std::array<Eigen::Vector2d, 6> extents;  ///< (near, far) of the last frames with evidence
    int num_extents = 0;
    int next_extent = 0;
    int age = 0;     ///< frames since the last evidence
    int frames = 0;  ///< frames with evidence
    bool valid = false;
    double nearest() const;
    double farthest() const;
  };
  /// a_left, a_right, b_left, b_right, c_left, c_right
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  static Vec6 basis(int side, double f);
  void solve();
  void shift(double delta);
  /// The data turned by @p angle (rad, + toward the left) about the camera.
  void rotate(double angle);
  /// Turn of side @p i's measurements against its model (slope of the residuals within
  /// @p gate); false when their forward span or the turn is implausible.
  bool measureTurn(int i, double gate, double& turn);
  /// Keep the points within @p gate of the robust straight line through them.
  static void trimToLine(std::vector<Eigen::Vector2d>& m, double gate);

  std::array<Mat6, 2> A_;  ///< normal equations of each side's evidence
  std::array<Vec6, 2> b_;
  Vec6 coef_;  ///< a_left, a_right, b_left, b_right, c_left, c_right
  std::array<Side, 2> sides_;
  std::array<std::vector<Eigen::Vector2d>, 2> measurements_;
  std::vector<double> residuals_;
  std::vector<Eigen::Vector2d> residual_points_;
  double drift_ = 0.0;  ///< the lane's sideways motion per frame, predicted at each update (m)
  double turn_ = 0.0;   ///< the lane's turn per frame (rad), predicted at each update
};

}  // namespace rgbd_lane_detector
