/**
 * @file bag_writer.h
 * @brief Writes RGB-D frames to a rosbag with the nodelet's input topics (INTERFACE.md):
 * `<ns>/rgb/image_rect_color` (bgr8 or rgb8), `<ns>/depth_registered/image_rect` (16UC1 mm,
 * or 32FC1 m), `<ns>/rgb/camera_info`, and optionally a latched `/tf_static`.
 */
#pragma once

#include <memory>
#include <string>

#include "rgbd_lane_detector_tools/dataset/dataset.h"

namespace rosbag {
class Bag;
}

namespace rgbd_lane_detector {
namespace tools {

/// Settings of the bag output.
struct BagWriterOptions {
  std::string ns = "/camera";  ///< topic namespace
  std::string frame_id = "camera_color_optical_frame";
  double rate = 10.0;              ///< Hz of the synthesised stamps
  double start_time = 1.7e9;       ///< s, stamp of the first frame (fixed: reproducible bags)
  bool use_source_stamps = false;  ///< keep the dataset's stamps (TUM, bags) instead
  bool rgb8 = false;               ///< colour as rgb8 instead of bgr8
  bool depth_float = false;        ///< depth as 32FC1 metres instead of 16UC1 millimetres
  bool compress = false;           ///< LZ4 chunk compression
  std::string tf_parent;           ///< parent frame of a /tf_static transform (empty: none)
  /// camera position (m) and orientation (rad, REP-103 roll/pitch/yaw of a x-forward camera
  /// body; positive pitch looks down) in tf_parent.
  double tf_x = 0.0, tf_y = 0.0, tf_z = 1.5, tf_roll = 0.0, tf_pitch = 0.0, tf_yaw = 0.0;
};

/**
 * @brief Rosbag writer of DatasetFrames.
 */
class BagWriter {
 public:
  BagWriter();
  ~BagWriter();
  /// Create the bag. @return false with @p error when it cannot be written.
  bool open(const std::string& path, const BagWriterOptions& options, std::string& error);
  /// Append one frame (colour, depth, camera_info; /tf_static before the first).
  bool write(const DatasetFrame& frame, std::string& error);
  /// Close the bag (also done by the destructor).
  void close();
  int written() const { return count_; }

  /// Depth of any supported type as 16UC1 millimetres (0 invalid; beyond 65.535 m invalid).
  static void depthToMillimetres(const cv::Mat& depth, double scale, cv::Mat& out);
  /// Depth of any supported type as 32FC1 metres (NaN invalid).
  static void depthToMetres(const cv::Mat& depth, double scale, cv::Mat& out);

 private:
  std::unique_ptr<rosbag::Bag> bag_;
  BagWriterOptions options_;
  int count_ = 0;
};

}  // namespace tools
}  // namespace rgbd_lane_detector
