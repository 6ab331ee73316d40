/**
 * @file dataset.h
 * @brief Readers of RGB-D sequences on disk: SYNTHIA-SEQS folders, TUM RGB-D folders, the
 * KITTI stereo frames of ../shared/realdata, TUM-style numbered frames and rosbags.
 *
 * Every reader yields frames ready for LaneDetector::detect(): colour, registered depth
 * (CV_16UC1 with a scale, or CV_32FC1 metres with NaN invalid) and intrinsics. KITTI folders
 * give the LiDAR depth, or depth computed from their colour stereo pair (DatasetOptions::depth
 * = "sgbm"), with the LiDAR kept as the reference.
 */
#pragma once

#include <istream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/types.h"
#include "rgbd_lane_detector_tools/stereo/stereo_matcher.h"

namespace rgbd_lane_detector {
namespace tools {

/// One RGB-D frame read from a dataset.
struct DatasetFrame {
  int index = 0;       ///< frame number in the source (file number when numeric, else position)
  std::string name;    ///< file stem or bag stamp
  double stamp = 0.0;  ///< seconds (source stamp, or index / rate)
  cv::Mat colour;      ///< 8-bit colour
  PixelFormat format = PixelFormat::kBgr8;
  cv::Mat depth;  ///< CV_16UC1 (depth_scale m/unit) or CV_32FC1 metres (NaN / 0 invalid)
  double depth_scale = 0.001;
  Intrinsics intrinsics;
  /// The dataset's LiDAR depth (KITTI) whatever @ref depth holds (it is the same image unless
  /// the depth is computed from the stereo pair): CV_16UC1 (lidar_depth_scale m/unit, 0 none)
  /// or CV_32FC1 metres (NaN none). Empty when the dataset has no LiDAR.
  cv::Mat lidar_depth;
  double lidar_depth_scale = 1.0;
  double baseline = 0.0;      ///< stereo baseline (m) of a stereo dataset (KITTI), else 0
  /// Distortion (OpenCV k1, k2, p1, p2, k3) of the image as stored, when it is raw: colour and
  /// depth here are already undistorted to @ref intrinsics; empty for rectified images. Points
  /// given in the stored image's pixels (hand labels) go through cv::undistortPoints with it.
  cv::Mat distortion;
  /// The dataset's own road plane n . p + d = 0 (optical frame, n up) when it ships one (the
  /// street corpus's calib.yaml: RANSAC on the LiDAR road points 2-25 m ahead within 3.5 m of the
  /// optical axis); referenceRoadPlane() returns it instead of fitting one.
  bool has_road_plane = false;
  Eigen::Vector3d road_plane_normal = Eigen::Vector3d(0.0, -1.0, 0.0);
  double road_plane_distance = 0.0;
  std::string depth_source = "sensor";  ///< "lidar", "sgbm" or "sensor" (RGB-D camera, renderer)
  /// The frame as the detector's input (headers onto this frame's images).
  Frame toFrame() const;
  /**
   * @brief The depth to check results against: the LiDAR when the frame has one, else the
   * frame's own depth.
   * @param[out] depth header onto that image.
   * @param[out] scale metres per unit of a CV_16UC1 @p depth.
   */
  void referenceDepth(cv::Mat& depth, double& scale) const;
  /**
   * @brief The measured road: the reference depth's points (referenceDepth()) in the road check
   * region (plane_check.h: below the horizon, the central columns), up to 40 m.
   * @param[out] points optical-frame points (cleared first).
   */
  void referenceRoadPoints(std::vector<Eigen::Vector3d>& points) const;
  /**
   * @brief The plane a detected road plane and hand labels are checked against: the dataset's
   * own (has_road_plane), else a RANSAC plane (5 cm inliers) of referenceRoadPoints().
   * @return false when the depth shows no plane there.
   */
  bool referenceRoadPlane(Eigen::Vector3d& normal, double& distance) const;
};

/// How to open a dataset.
struct DatasetOptions {
  std::string path;           ///< folder or .bag file
  std::string type = "auto";  ///< auto, synthia, tum, tum_frames, kitti, streets, stereo_lidar, bag
  std::string camera_info;    ///< camera_info YAML overriding the intrinsics (optional)
  double depth_scale = 0.0;   ///< metres per unit of 16-bit depth; 0: the format's default
  std::string colour_topic = "rgb/image_rect_color";  ///< bag topics (suffix match)
  std::string depth_topic = "depth_registered/image_rect";
  std::string info_topic = "rgb/camera_info";
  double sync_tolerance = 0.02;  ///< s, colour/depth pairing in bags and TUM lists
  int first = 0;                 ///< skip frames before this position
  int step = 1;                  ///< take every step-th frame
  int max_frames = -1;           ///< stop after this many frames (-1: all)
  /// Depth given to the detector: "dataset" (the folder's own: KITTI's LiDAR, the sensor's
  /// depth of the others) or "sgbm" (StereoSGBM on the colour stereo pair; KITTI folders with
  /// right images).
  std::string depth = "dataset";
  SgbmParams sgbm;  ///< matcher settings for depth = "sgbm"
};

/**
 * @brief Sequential reader. next() returns frames in order; false at the end or on an error,
 * which error() then describes (empty at a normal end).
 */
class DatasetReader {
 public:
  virtual ~DatasetReader() = default;
  /// Format name ("synthia", "tum", "tum_frames", "kitti", "bag").
  virtual const char* kind() const = 0;
  /// Frames that next() will return (after first/step/max_frames); -1 when unknown.
  virtual int size() const = 0;
  /// Read the next frame.
  virtual bool next(DatasetFrame& frame) = 0;
  /// Lane ground truth file of the dataset (SYNTHIA GT/LANES), or empty.
  virtual std::string groundTruthPath() const { return std::string(); }
  /// True when the frames are unrelated snapshots (the KITTI and TUM frame sets), not a drive:
  /// the detector's carried state (adapted templates, lane model) must be reset between them.
  virtual bool independentFrames() const { return false; }
  const std::string& error() const { return error_; }

 protected:
  std::string error_;
};

/// Format of a path: "synthia", "tum", "tum_frames", "kitti", "bag", or "" when unknown.
std::string detectDatasetType(const std::string& path);

/**
 * @brief Open a dataset.
 * @return the reader, or null with @p error naming the problem (missing folder, no frames,
 * unreadable intrinsics...).
 */
std::unique_ptr<DatasetReader> openDataset(const DatasetOptions& options, std::string& error);

/**
 * @brief Intrinsics from a ROS camera_info YAML (camera_calibration_parsers); P is used when
 * set (rectified images), else K.
 */
bool readCameraInfoYaml(const std::string& path, Intrinsics& K, cv::Size* size, std::string& error);

/// Intrinsics from a SYNTHIA CameraParams/intrinsics.txt (f cx cy [baseline], any whitespace).
bool readSynthiaIntrinsics(const std::string& path, Intrinsics& K, double* baseline,
                           std::string& error);

/**
 * @brief KITTI rectified intrinsics and colour baseline: calib_cam_to_cam.txt of the raw data
 * (P_rect_02 / P_rect_03) or calib.txt of the object / odometry format (P2 / P3).
 */
bool readKittiCalibration(const std::string& path, Intrinsics& K, double& baseline,
                          std::string& error);

// Text parsers behind the file readers above (the file versions open the file and call these;
// fuzz/fuzz_readers.cpp drives them). @p source names the input in error messages.

/**
 * @brief readCameraInfoYaml() on text: @p format is "yaml" or "yml" (or "ini", the other format
 * of camera_calibration_parsers).
 */
bool parseCameraInfo(const std::string& text, const std::string& format, const std::string& source,
                     Intrinsics& K, cv::Size* size, std::string& error);

/// readSynthiaIntrinsics() on a stream.
bool parseSynthiaIntrinsics(std::istream& in, const std::string& source, Intrinsics& K,
                            double* baseline, std::string& error);

/// readKittiCalibration() on a stream.
bool parseKittiCalibration(std::istream& in, const std::string& source, Intrinsics& K,
                           double& baseline, std::string& error);

/// A TUM rgb.txt / depth.txt list: `stamp file` lines, '#' comments; malformed lines skipped.
using TumList = std::vector<std::pair<double, std::string>>;
void parseTumList(std::istream& in, TumList& list);

/// One colour/depth pair of a TUM sequence (file names relative to the sequence folder).
struct TumPair {
  double stamp = 0.0;  ///< colour stamp
  std::string colour, depth;
};

/// A TUM associations.txt: `t1 f1 t2 f2` lines in either order (the depth file is the one
/// whose name holds "depth"); '#' comments, malformed lines skipped.
void parseTumAssociations(std::istream& in, std::vector<TumPair>& pairs);

/**
 * @brief Pair each colour entry with the nearest depth entry, one to one, in list order, when
 * within @p tolerance seconds (both lists sorted by stamp, as TUM writes them).
 */
void associateTumLists(const TumList& rgb, const TumList& depth, double tolerance,
                       std::vector<TumPair>& pairs);

/**
 * @brief KITTI disparity PNG (uint16, disparity = value / 256, 0 = none) to depth, through the
 * core's disparityToDepth().
 * @param[out] depth CV_32FC1 Z = fx * B / disparity (NaN where no disparity).
 */
void kittiDisparityToDepth(const cv::Mat& disparity, double fx, double baseline, cv::Mat& depth);

}  // namespace tools
}  // namespace rgbd_lane_detector
