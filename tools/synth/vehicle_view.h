// What the vehicle itself puts into the camera's view (private to the synth library): its bonnet
// in the bottom rows, and the rings of a roof LiDAR projected into the image.
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "frame_context.h"
#include "rgbd_lane_detector/types.h"
#include "rgbd_lane_detector_tools/synth/scenario.h"

namespace rgbd_lane_detector {
namespace synth {

constexpr double kRad = M_PI / 180.0;
constexpr double kBonnetLength = 1.8;  // m, camera to the bonnet's front edge

// The vehicle's bonnet as the camera sees it: its edge at row (1 - bonnet) * height on the
// principal column, curving down by a third of the bonnet's height toward the image's sides; a
// dark painted hood, flat in the optical frame, its front edge kBonnetLength ahead.
class Bonnet {
 public:
  Bonnet(const SceneSettings& s, const Intrinsics& K)
      : on_(s.bonnet > 0.0), top_((1.0 - s.bonnet) * s.height), drop_(s.bonnet * s.height / 3.0),
        cx_(K.cx), cy_(K.cy), half_width_(0.5 * s.width), height_(s.height),
        paint_(cv::Vec3d(0.04, 0.04, 0.045)), sky_(s.sky_horizon) {}
  double edge(double u) const {
    const double a = (u - cx_) / half_width_;
    return top_ + drop_ * a * a;
  }
  bool hides(double u, double v) const { return on_ && v >= edge(u); }
  /// Whether any part of pixel (x, y) lies on the bonnet.
  bool touches(int x, int y) const {
    return on_ && y + 0.5 >= edge(std::min(x + 0.5, std::max(x - 0.5, cx_)));
  }
  /// Optical depth of the bonnet at row @p v.
  double depth(double v) const {
    return kBonnetLength * std::max(1.0, top_ - cy_) / std::max(1.0, v - cy_);
  }
  /// Linear RGB of the bonnet at row @p v: its paint in the ambient light, and the sky mirrored
  /// at grazing angles near its edge.
  cv::Vec3d colour(double v, const FrameContext& ctx) const {
    const double grazing = std::exp(-(v - top_) / std::max(1.0, 0.3 * (height_ - top_)));
    const cv::Vec3d& a = ctx.ambient_light;
    return cv::Vec3d(paint_[0] * a[0], paint_[1] * a[1], paint_[2] * a[2]) +
           sky_ * (0.15 * grazing);
  }

 private:
  bool on_;
  double top_, drop_, cx_, cy_, half_width_, height_;
  cv::Vec3d paint_, sky_;
};

// The rings of a spinning LiDAR seen from the camera: a ray gets a return when its world
// elevation lies within half a pixel of a ring's and its azimuth within half a pixel of a
// firing's.
class LidarRings {
 public:
  LidarRings(const SceneSettings& s, const Intrinsics& K)
      : beams_(s.lidar_beams), low_(s.lidar_low_deg * kRad),
        step_(s.lidar_beams > 1 ? (s.lidar_high_deg - s.lidar_low_deg) * kRad / (s.lidar_beams - 1)
                                : 1.0),
        az_step_(s.lidar_azimuth_deg * kRad), half_el_(0.5 / K.fy), half_az_(0.5 / K.fx) {}
  bool hits(const Eigen::Vector3d& dir) const {
    const Eigen::Vector3d n = dir.normalized();
    const double el = std::asin(std::max(-1.0, std::min(1.0, n.y())));
    const double k = std::round((el - low_) / step_);
    if (k < 0 || k >= beams_ || std::fabs(el - (low_ + k * step_)) > half_el_) return false;
    if (az_step_ <= 2.0 * half_az_) return true;  // a firing in every pixel column
    const double az = std::atan2(n.x(), n.z());
    return std::fabs(az - std::round(az / az_step_) * az_step_) <= half_az_;
  }

 private:
  int beams_;
  double low_, step_, az_step_, half_el_, half_az_;
};

}  // namespace synth
}  // namespace rgbd_lane_detector
