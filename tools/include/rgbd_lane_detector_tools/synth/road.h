/**
 * @file road.h
 * @brief Road geometry in the ground plane: a straight line or a constant-curvature arc, with
 * road coordinates (s along the reference line, t lateral, positive right) and painted lines.
 *
 * World frame: x right, y up, z forward at s = 0; the ground is the plane y = 0, so the
 * ground-truth plane stays exact on curves (markers are circles in that plane).
 */
#pragma once

#include <vector>

#include <Eigen/Core>

#include "rgbd_lane_detector_tools/synth/scenario.h"

namespace rgbd_lane_detector {
namespace synth {

/// One painted line at a constant lateral offset.
struct MarkerLine {
  double offset = 0.0;  ///< t of the line centre (m, positive right of the reference line)
  double width = 0.15;
  bool dashed = false;
  double dash_length = 3.0;
  double period = 12.0;  ///< dash + gap
  double phase = 0.0;    ///< s of a dash start
};

/**
 * @brief Road layout: geometry of the reference line (the ego lane centre) and its lines.
 */
class RoadGeometry {
 public:
  RoadGeometry() = default;
  explicit RoadGeometry(const SceneSettings& s);

  double curvature() const { return curvature_; }
  /// Ground point (x, z) of road coordinates (s, t).
  Eigen::Vector2d point(double s, double t) const;
  /// Heading (yaw, rad, positive right) of the reference line at @p s.
  double heading(double s) const { return curvature_ * s; }
  /**
   * @brief Road coordinates of a ground point.
   * @param[in] s_ref on an arc, the answer is the s closest to this (unwraps full turns).
   */
  void coordinates(double x, double z, double s_ref, double& s, double& t) const;
  /**
   * @brief First ray parameter in (min_l, max_l) where a ray in the x-z plane reaches the
   * lateral offset @p t_line (a vertical surface: a plane, or a cylinder on an arc).
   * @return false when the ray does not reach it in that interval.
   */
  bool rayToLateral(double ox, double oz, double dx, double dz, double t_line, double min_l,
                    double max_l, double& lambda) const;

  const std::vector<MarkerLine>& markers() const { return markers_; }
  int egoLeft() const { return ego_left_; }    ///< index in markers() or -1
  int egoRight() const { return ego_right_; }  ///< index in markers() or -1
  /// Index of the line painted at (s, t), or -1.
  int markerAt(double s, double t) const;
  /// Lateral offsets of the outer road edges (centres of the outermost lines' positions).
  double leftEdge() const { return left_edge_; }
  double rightEdge() const { return right_edge_; }
  /// Lateral offset of the centre of lane @p lane (0 ego, negative left).
  double laneCentre(int lane) const { return lane * lane_width_; }

 private:
  double curvature_ = 0.0;
  double radius_ = 0.0;  ///< signed 1 / curvature
  double lane_width_ = 3.6;
  double left_edge_ = 0.0, right_edge_ = 0.0;
  std::vector<MarkerLine> markers_;
  int ego_left_ = -1, ego_right_ = -1;
};

}  // namespace synth
}  // namespace rgbd_lane_detector
