/**
 * @file ground_truth.h
 * @brief Per-frame lane ground truth of a sequence (GT/LANES/ground_truth.json).
 *
 * JSON written and read with cv::FileStorage:
 * @code
 * { "frames": [ { "index": 0, "plane_normal": [nx, ny, nz], "plane_distance": d,
 *                 "has_lane": 1, "left": [[x, y, z], ...], "right": [[x, y, z], ...] }, ... ] }
 * @endcode
 * Coordinates are metres in the camera optical frame (x right, y down, z forward). The plane
 * is n . p + d = 0 with n the unit normal pointing toward the camera (d > 0, the camera
 * height). "left"/"right" are the ego lane's marker centre lines, near to far (empty when the
 * line is not painted). has_lane is 1 when both are painted (cv::FileStorage has no bool type;
 * JSON readers see 1/0).
 */
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace rgbd_lane_detector {
namespace tools {

/// Ground truth of one frame.
struct FrameTruth {
  int index = 0;
  Eigen::Vector3d normal = Eigen::Vector3d(0, -1, 0);
  double distance = 0.0;
  bool has_lane = false;
  std::vector<Eigen::Vector3d> left;   ///< ego left marker centre line, near to far
  std::vector<Eigen::Vector3d> right;  ///< ego right marker centre line, near to far
};

/// Ground truth of a sequence, indexed by frame.
struct SequenceTruth {
  std::vector<FrameTruth> frames;
  /// Truth of frame @p index, or nullptr.
  const FrameTruth* find(int index) const;
};

/**
 * @brief Write ground truth as JSON.
 * @return false with @p error on an I/O failure.
 */
bool writeGroundTruth(const std::string& path, const SequenceTruth& truth, std::string& error);

/**
 * @brief Read ground truth written by writeGroundTruth().
 * @return false with @p error when the file is missing or malformed.
 */
bool readGroundTruth(const std::string& path, SequenceTruth& truth, std::string& error);

}  // namespace tools
}  // namespace rgbd_lane_detector
