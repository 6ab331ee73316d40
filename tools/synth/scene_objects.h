// Scene content of the synthetic renderer (private to the synth library): oriented boxes
// (vehicles, overpasses, poles) placed per frame, and the ray / box tests.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector_tools/synth/road.h"
#include "rgbd_lane_detector_tools/synth/scenario.h"

namespace rgbd_lane_detector {
namespace synth {

/// Material of a box.
enum class BoxKind { kCar, kTruck, kConcrete, kPole };

/// An oriented box standing on or above the ground (yaw rotation only).
struct Box {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< world <- box (x lateral, y up, z along)
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d half = Eigen::Vector3d::Ones();
  BoxKind kind = BoxKind::kCar;
  cv::Vec3d albedo{0.5, 0.5, 0.5};  ///< RGB
  uint8_t label = kLabelCar;
  bool stripes = false;
  bool casts_shadow = true;
  // per-frame culling
  cv::Rect2d screen;  ///< conservative image rectangle (pixels)
  Eigen::Vector4d shadow_aabb =
      Eigen::Vector4d::Zero();  ///< ground footprint of its shadow: xmin, xmax, zmin, zmax
};

/// Ray / box intersection result.
struct BoxHit {
  double lambda = 0.0;
  int axis = 0;       ///< axis of the entered face (0 x, 1 y, 2 z)
  double sign = 1.0;  ///< face normal along that axis in box coordinates
  Eigen::Vector3d local = Eigen::Vector3d::Zero();  ///< hit point in box coordinates
};

/**
 * @brief Slab test of a ray o + l d, l in (min_l, max_l).
 * @return true with the entry point when the ray enters the box in that interval.
 */
bool intersectBox(const Box& box, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double min_l,
                  double max_l, BoxHit& hit);

/// A vehicle moving along a lane (layout drawn from std::mt19937 of the seed).
struct VehicleSpec {
  int lane = 1;            ///< lane index, 0 = ego, negative left
  double s0 = 20.0;        ///< position relative to the camera at t = 0 (m)
  double rel_speed = 0.0;  ///< m/s relative to the camera (shared by a lane: no overtaking)
  double lateral = 0.0;    ///< offset from the lane centre (m)
  double length = 4.5, width = 1.8, height = 1.5;
  cv::Vec3d colour{0.5, 0.5, 0.5};
  bool truck = false;
  bool lead = false;  ///< ego-lane car ahead with an oscillating gap
  bool oncoming = false;  ///< drives the other way (faces the camera)
};

/**
 * @brief Places every box of the scene at a given frame.
 */
class SceneObjects {
 public:
  SceneObjects(const SceneSettings& s, const RoadGeometry& road);
  /**
   * @brief Boxes present around the camera at frame @p index.
   * @param[in] cam_s camera road position.
   * @param[out] out boxes (culling fields not set).
   */
  void boxesAt(int index, double cam_s, std::vector<Box>& out) const;
  const std::vector<VehicleSpec>& vehicles() const { return vehicles_; }

  /// Road position of the overpass decks' starts near @p s (empty when none).
  void overpassesNear(double s, double before, double after, std::vector<double>& starts) const;

 private:
  void addVehicle(const VehicleSpec& v, double s, std::vector<Box>& out) const;
  const SceneSettings& s_;
  const RoadGeometry& road_;
  std::vector<VehicleSpec> vehicles_;
};

}  // namespace synth
}  // namespace rgbd_lane_detector
