/**
 * @file renderer.h
 * @brief Ray-casting renderer of a camera driving along a road, with exact ground truth.
 *
 * Per pixel, rays are intersected with the ground plane, the boxes of the scene (vehicles,
 * overpasses, poles) and the guard rails (vertical surfaces at a constant lateral offset).
 * Colour averages supersample x supersample rays; depth and labels come from the ray through
 * the pixel centre, so they are exact (depth of a road pixel = its plane intersection).
 */
#pragma once

#include <memory>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/types.h"
#include "rgbd_lane_detector_tools/ground_truth.h"
#include "rgbd_lane_detector_tools/synth/road.h"
#include "rgbd_lane_detector_tools/synth/scenario.h"

namespace rgbd_lane_detector {
namespace synth {

/// Camera pose of one frame.
struct CameraPose {
  Eigen::Matrix3d R_wc = Eigen::Matrix3d::Identity();  ///< optical frame -> world rotation
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< world position
  double s = 0.0;                                      ///< road position
  double t = 0.0;      ///< lateral offset from the initial ego lane's centre (m, positive right)
  double yaw = 0.0;    ///< rad, positive right
  double pitch = 0.0;  ///< rad, positive down, relative to the vehicle
  double roll = 0.0;   ///< rad
  double height = 0.0;         ///< camera above the road along the vehicle's up axis (m)
  double vehicle_pitch = 0.0;  ///< rad, nose up: the road's grade under the vehicle
  Eigen::Vector3d base = Eigen::Vector3d::Zero();  ///< world: the road point under the camera
};

/**
 * @brief Rotation world <- base_link of a vehicle with heading @p yaw (rad, positive right, as
 * CameraPose) pitched nose-up by @p pitch: its rows are base_link's x (forward), y (left), z
 * (up) in world coordinates, so p_base = R (p_world - base).
 */
Eigen::Matrix3d baseFromWorld(double yaw, double pitch);

/// Nominal camera mount: the optical frame in base_link (camera_height, pitch_deg, roll_deg).
Eigen::Isometry3d nominalMount(const SceneSettings& settings);

/// Images of one rendered frame.
struct RenderedFrame {
  cv::Mat bgr;         ///< CV_8UC3 colour
  cv::Mat depth;       ///< CV_32FC1 metres after the sensor model, 0 = invalid
  cv::Mat depth_true;  ///< CV_32FC1 exact depth, 0 = sky / beyond max_range
  cv::Mat labels;      ///< CV_8UC1 class ids (LabelClass)
};

class SceneObjects;

/**
 * @brief Renders frames of one scenario. Deterministic: a frame depends only on the settings
 * (seed included) and its index, never on rendering order or threads.
 */
class Renderer {
 public:
  /// @param[in] settings must pass validateSettings().
  explicit Renderer(const SceneSettings& settings);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  const SceneSettings& settings() const { return settings_; }
  const RoadGeometry& road() const { return road_; }
  /// Pinhole intrinsics at the output size (SYNTHIA's, scaled with the width).
  Intrinsics intrinsics() const;
  /// Camera pose of frame @p index.
  CameraPose pose(int index) const;
  /// Ground truth of frame @p index (plane, boundaries, vehicle frame, lane model; see
  /// ground_truth.h for the definitions).
  tools::FrameTruth truth(int index) const;
  /// Render frame @p index (parallel over rows with cv::parallel_for_).
  void render(int index, RenderedFrame& out) const;

 private:
  SceneSettings settings_;
  RoadGeometry road_;
  std::unique_ptr<SceneObjects> objects_;
};

}  // namespace synth
}  // namespace rgbd_lane_detector
