/**
 * @file sequence_writer.h
 * @brief Writes rendered frames in the SYNTHIA-SEQS folder layout (INTERFACE.md "Data on disk").
 *
 * @code
 * <dir>/RGB/Stereo_Left/Omni_F/000000.png        colour (8-bit BGR PNG)
 * <dir>/Depth/Stereo_Left/Omni_F/000000.png      uint16 centimetres, same value in 3 channels, 0
 * invalid <dir>/GT/LABELS/Stereo_Left/Omni_F/000000.png  class id in the R channel (scenario.h
 * LabelClass) <dir>/GT/LANES/ground_truth.json               plane and ego marker lines per frame
 * <dir>/CameraParams/intrinsics.txt              f, cx, cy, baseline (one per line)
 * <dir>/scenario.json                            every generator setting (written last)
 * @endcode
 */
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/types.h"
#include "rgbd_lane_detector_tools/ground_truth.h"
#include "rgbd_lane_detector_tools/synth/renderer.h"
#include "rgbd_lane_detector_tools/synth/scenario.h"

namespace rgbd_lane_detector {
namespace synth {

/// Relative paths of the SYNTHIA-SEQS layout.
struct SynthiaLayout {
  static constexpr const char* kRgb = "RGB/Stereo_Left/Omni_F";
  static constexpr const char* kDepth = "Depth/Stereo_Left/Omni_F";
  static constexpr const char* kLabels = "GT/LABELS/Stereo_Left/Omni_F";
  static constexpr const char* kLanes = "GT/LANES/ground_truth.json";
  static constexpr const char* kIntrinsics = "CameraParams/intrinsics.txt";
  static constexpr const char* kScenario = "scenario.json";
  /// File name of frame @p index ("%06d.png").
  static std::string frameName(int index);
};

/// Depth in metres (CV_32FC1, 0 / NaN invalid) to SYNTHIA's uint16 centimetres in 3 channels.
void encodeDepthCentimetres(const cv::Mat& depth_m, cv::Mat& out);
/// Class ids (CV_8UC1) to a 3-channel image with the id in R (channel 2 of BGR).
void encodeLabels(const cv::Mat& labels, cv::Mat& out);

/**
 * @brief Writes one sequence folder.
 */
class SequenceWriter {
 public:
  /**
   * @brief Create the folders (removes a previous scenario.json, so an interrupted run never
   * looks complete).
   * @return false with @p error when a folder cannot be created.
   */
  bool open(const std::string& dir, const SceneSettings& settings, const Intrinsics& K,
            std::string& error);
  /// Write the images of one frame and keep its ground truth.
  bool write(int index, const RenderedFrame& frame, const tools::FrameTruth& truth,
             std::string& error);
  /// Write ground_truth.json, intrinsics.txt and finally scenario.json.
  bool finish(std::string& error);

 private:
  std::string dir_;
  SceneSettings settings_;
  Intrinsics K_;
  tools::SequenceTruth truth_;
  cv::Mat depth_buf_, label_buf_;
};

/// True when @p dir holds a complete sequence generated with exactly @p settings
/// (same scenario.json text, including the generator version, and every frame's files).
bool sequenceUpToDate(const std::string& dir, const SceneSettings& settings);

}  // namespace synth
}  // namespace rgbd_lane_detector
