/**
 * @file geometry.h
 * @brief The core's geometry, written once: a pixel ray meeting the road plane, distances to the
 * plane, the road-aligned frame (REP-103), a least-squares line's sums. Pixel rays and projection are Intrinsics::ray()
 * and Intrinsics::project() (types.h).
 */
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/// The nearest column to @p x in an image @p width pixels wide, halves rounded toward the centre
/// column: a mirrored x (width - 1 - x) gives the mirrored column. (std::lround takes every half
/// to the right, so a line on a mirrored road would be read a pixel off.)
inline int roundColumn(double x, int width) {
  return 2.0 * x >= width - 1 ? static_cast<int>(std::ceil(x - 0.5))
                              : static_cast<int>(std::floor(x + 0.5));
}

/**
 * @brief The sums of a least-squares straight line y = a + b x, added point by point, and its
 * closed-form fit. Products are taken in the points' own type (float pixel coordinates multiply
 * as floats), sums in double.
 */
struct LineSums {
  double n = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  template <typename T>
  void add(T x, T y) {
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  /// The line's @p a and @p b; where the spread of x (n sxx - sx^2) is at most @p min_spread,
  /// b = 0 and a the mean of y, and false.
  bool fit(double min_spread, double& a, double& b) const {
    const double den = n * sxx - sx * sx;
    const bool spread = std::fabs(den) > min_spread;
    b = spread ? (n * sxy - sx * sy) / den : 0.0;
    a = (sy - b * sx) / n;
    return spread;
  }
};

/// Signed distance of a point to a plane (positive on the camera side).
inline double planeDistance(const PlaneEstimate& plane, const Eigen::Vector3d& p) {
  return plane.normal.dot(p) + plane.distance;
}

/// Signed distance of a float point to a plane (positive on the camera side), in double.
inline double planeDistance(const PlaneEstimate& plane, const Eigen::Vector3f& p) {
  return planeDistance(plane, Eigen::Vector3d(p.cast<double>()));
}

/**
 * @brief Where a pixel ray meets the plane.
 * @param[in] plane a valid plane (n pointing toward the camera, d > 0).
 * @param[in] ray a ray with z = 1 (Intrinsics::ray()).
 * @param[out] depth the z (= the ray's scale) of the meeting point; untouched on false.
 * @return false where the ray does not meet the plane in front of the camera (n . ray >= -1e-9:
 *         parallel to the road or above the horizon).
 */
inline bool rayPlaneDepth(const PlaneEstimate& plane, const Eigen::Vector3d& ray, double& depth) {
  const double den = plane.normal.dot(ray);
  if (!(den < -1e-9)) return false;
  depth = -plane.distance / den;
  return true;
}

/**
 * @brief Pixels that @p metres across the road span where @p ray meets the plane:
 * metres fx / depth, computed as ((metres fx) (-n . ray)) / d. 0 where the ray does not meet the
 * plane (rayPlaneDepth()).
 */
inline double roadPixelsAcross(const Intrinsics& K, const PlaneEstimate& plane,
                               const Eigen::Vector3d& ray, double metres) {
  const double den = plane.normal.dot(ray);
  return den < -1e-9 ? metres * K.fx * (-den) / plane.distance : 0.0;
}

/**
 * @brief Pixels per metre across the road where @p ray meets the plane: fx / depth, computed as
 * fx (-n . ray) / d (roadPixelsAcross() of 1 m: 1 fx is fx exactly). 0 where the ray does not
 * meet the plane (rayPlaneDepth()).
 */
inline double roadPixelsPerMetre(const Intrinsics& K, const PlaneEstimate& plane,
                                 const Eigen::Vector3d& ray) {
  return roadPixelsAcross(K, plane, ray, 1.0);
}

/**
 * @brief The road-aligned frame under the camera, REP-103: x forward (the optical axis projected
 * on the road), y left, z up (the plane normal); its origin is the foot of the perpendicular from
 * the camera centre to the road, so the camera is at (0, 0, d).
 */
class RoadFrame {
 public:
  /// Invalid (isometry identity, toRoad() meaningless).
  RoadFrame() = default;

  /// The frame of a valid plane; invalid for an invalid plane or one the optical axis is
  /// perpendicular to.
  static RoadFrame fromPlane(const PlaneEstimate& plane);

  bool valid() const { return valid_; }
  const Eigen::Vector3d& origin() const { return origin_; }    ///< in the optical frame
  const Eigen::Vector3d& forward() const { return forward_; }  ///< x, in the optical frame
  const Eigen::Vector3d& left() const { return left_; }        ///< y, in the optical frame
  const Eigen::Vector3d& up() const { return up_; }            ///< z, in the optical frame

  /// (x forward, y left) of an optical-frame point (its foot on the road).
  Eigen::Vector2d toRoad(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d q = p - origin_;
    return Eigen::Vector2d(forward_.dot(q), left_.dot(q));
  }
  /// Optical-frame point of the road point (x forward, y left).
  Eigen::Vector3d toCamera(double x, double y) const { return origin_ + x * forward_ + y * left_; }
  /// The isometry that takes optical-frame points to road-frame points (x, y, height); identity
  /// when invalid.
  Eigen::Isometry3d roadFromCamera() const;

 private:
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d forward_ = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d left_ = -Eigen::Vector3d::UnitX();
  Eigen::Vector3d up_ = -Eigen::Vector3d::UnitY();
  double height_ = 0.0;
  bool valid_ = false;
};

}  // namespace rgbd_lane_detector
