#include "rgbd_lane_detector/geometry.h"

namespace rgbd_lane_detector {

RoadFrame RoadFrame::fromPlane(const PlaneEstimate& plane) {
  RoadFrame f;
  if (!plane.valid) return f;
  const Eigen::Vector3d& n = plane.normal;
  const Eigen::Vector3d fwd = Eigen::Vector3d::UnitZ() - n * n.z();
  if (fwd.norm() < 1e-6) return f;
  f.forward_ = fwd.normalized();
  f.left_ = n.cross(f.forward_).normalized();
  f.up_ = n;
  f.origin_ = -plane.distance * n;
  f.height_ = plane.distance;
  f.valid_ = true;
  return f;
}

Eigen::Isometry3d RoadFrame::roadFromCamera() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (!valid_) return T;
  Eigen::Matrix3d R;  // rows: the road frame's axes in the optical frame
  R.row(0) = forward_.transpose();
  R.row(1) = left_.transpose();
  R.row(2) = up_.transpose();
  T.linear() = R;
  T.translation() = Eigen::Vector3d(0.0, 0.0, height_);  // the camera is d above the origin
  return T;
}

}  // namespace rgbd_lane_detector
