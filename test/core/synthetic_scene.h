// Minimal ray-cast road scenes with exact ground truth, for the core unit tests.
// (The full generator with textures, weather and sensors lives in tools/.)
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {
namespace test {

struct RoadScene {
  int width = 640;
  int height = 380;
  Intrinsics K{266.37, 266.37, 320.0, 190.0};  // SYNTHIA at half resolution
  double camera_height = 1.5;                  // m above the road
  double pitch = 0.08;                         // rad, camera looking down
  double lane_width = 3.6;                     // m between marker centres
  double lateral_offset = 0.0;                 // camera offset from the lane centre (m, + right)
  double marker_width = 0.15;                  // m
  bool left_painted = true;                    // false: that line is not painted (a bare road)
  bool right_painted = true;
  bool left_dashed = false;
  bool right_dashed = false;
  double dash_length = 3.0;                    // m
  double dash_period = 12.0;                   // m
  double travelled = 0.0;                      // m driven: shifts the dash pattern
  int asphalt = 70;
  int paint = 230;
  int sky = 200;
  double max_range = 80.0;                     // depth beyond this is 0 (invalid)
  double min_range = 0.0;                      // depth nearer than this is 0 (a LiDAR's gap)

  /// Road plane in the optical frame: normal . p + distance = 0, normal toward the camera.
  Eigen::Vector3d planeNormal() const;
  double planeDistance() const { return camera_height; }
  /// Lateral position of the left / right marker centre (m, + right of the camera).
  double leftMarkerX() const { return -0.5 * lane_width - lateral_offset; }
  double rightMarkerX() const { return 0.5 * lane_width - lateral_offset; }

  /// Render colour (bgr8), depth (uint16 mm) and optionally float depth (m).
  void render(cv::Mat& bgr, cv::Mat& depth_mm, cv::Mat* depth_m = nullptr) const;
};

/// A box standing on the road (a car, a sidewalk): footprint [x0, x1] x [z0, z1] (m, road
/// coordinates: x right, z forward), height h.
struct DepthBox {
  double x0, x1, z0, z1, h;
};

/// Organised 3D points of a road with boxes on it (depth only, exact or with noise).
struct DepthScene {
  int image_width = 320;
  int image_height = 190;
  Intrinsics K{133.0, 133.0, 160.0, 95.0};
  double height = 1.5;  ///< camera above the road (m)
  double pitch = 0.05;  ///< rad, camera looking down
  double noise = 0.0;   ///< sigma of the depth (m)
  /// how much the road ahead lies below the plane at distance z (a crest; 0: level)
  std::function<double(double)> crest = [](double) { return 0.0; };
  /// how much the road lies below the plane at lateral position x (camber; 0: flat)
  std::function<double(double)> camber = [](double) { return 0.0; };
  std::vector<DepthBox> boxes;
  /// pixels without depth
  std::function<bool(int, int)> hole = [](int, int) { return false; };

  /// The road plane in the optical frame (normal toward the camera).
  Eigen::Vector3d normal() const;
  /// Distance t along the world ray w (x right, y down, z forward) to the first surface.
  double hit(const Eigen::Vector3d& w) const;
  /// CV_32FC3 points (NaN: no depth, beyond 80 m or a hole).
  cv::Mat render() const;
};

}  // namespace test
}  // namespace rgbd_lane_detector
