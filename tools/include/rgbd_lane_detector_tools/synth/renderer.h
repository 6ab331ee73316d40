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
  double t = 0.0;      ///< lateral offset from the ego lane centre (m, positive right)
  double yaw = 0.0;    ///< rad, positive right
  double pitch = 0.0;  ///< rad, positive down
  double roll = 0.0;   ///< rad
};

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
  /// Ground-truth plane and ego marker centre lines of frame @p index.
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
