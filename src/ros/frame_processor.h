/**
 * @file frame_processor.h
 * @brief The nodelet's processor: reconfigured parameters -> a prepared LaneDetector -> one
 * synchronised set of messages read in place -> detect() -> the frame's outcome. No ROS
 * communication and no logging (the nodelet logs what it returns), so it runs in a gtest
 * without a roscore. Not thread-safe but for setParams(): frames are processed one at a time.
 * Private to the nodelet library.
 */
#pragma once

#include <cstdint>
#include <mutex>
#include <string>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "frame_accounting.h"
#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

class FrameProcessor {
 public:
  /// What prepare() did for a new camera.
  struct Preparation {
    cv::Size size;
    Intrinsics K;
    double ms = 0.0;  ///< LaneDetector::prepare()'s wall time
    std::string warning;  ///< a raw (distorted) image on a topic that is not a rectified one
    std::string error;    ///< LaneDetector::prepare() threw (its text); the frames are dropped
  };

  /// @param params the initial parameters (already sanitised), applied at once.
  explicit FrameProcessor(const Params& params = Params());

  /// The latest reconfigured parameters (any thread; sanitised by the caller): the next
  /// applyParams() hands them to the detector.
  void setParams(const Params& params);

  /**
   * @brief New camera (start, resolution or calibration change): plan the detector now, so that
   * the first frame costs about a steady-state one. A calibration within sameCamera() of the
   * prepared one is the same camera (nothing happens).
   * @param[in] colour_topic the colour image's topic (for Preparation::warning).
   * @return true when the detector was prepared successfully (@p out filled).
   */
  bool prepare(const sensor_msgs::CameraInfo& info, const std::string& colour_topic,
               Preparation& out);

  /**
   * @brief Parameters for the next frame: the reconfigured ones when they changed, with the
   * road's up axis @p up when given (null: the reconfigured up axis). setParams() on the
   * detector only when something changed (a static mount gives the same axis every frame).
   */
  void applyParams(const Eigen::Vector3d* up);

  /**
   * @brief Read the messages into @p frame (in place) and validate it.
   * @param[out] problem static text of the problem, else null.
   * @return kProcessed when the frame can be detected, kBadMessage or kInvalidFrame.
   */
  FrameOutcome load(const sensor_msgs::Image& colour, const sensor_msgs::Image& depth,
                    const sensor_msgs::CameraInfo& info, Frame& frame, const char*& problem);

  /**
   * @brief Run the detector on a loaded frame. A frame stamped more than setMaxFrameGap() after
   * the last detected one first starts the detector's state again (restartGap() says so).
   * @param[in] stamp_ns the frame's stamp (ns).
   * @param[in] motion the vehicle's motion since the last frame (null: none).
   * @param[in] full_geometric the whole G map (for response/geometric), see LaneDetector.
   * @param[out] problem static text for kInvalidFrame; exceptionText() for kDetectorException.
   * @return kProcessed, kInvalidFrame or kDetectorException.
   */
  FrameOutcome detect(const Frame& frame, int64_t stamp_ns, const Eigen::Isometry3d* motion,
                      bool full_geometric, const char*& problem);

  /**
   * @brief The longest time between two detected frames over which the tracks are kept (s;
   * 0: any). Over a longer gap no frame was seen (a paused driver, lost frames, a missing
   * transform) while the vehicle drove on: the lane tracker and the lane model, counting frames,
   * would gate the new road's lines with an old lane.
   */
  void setMaxFrameGap(double seconds) { max_gap_ns_ = static_cast<int64_t>(seconds * 1e9); }

  /// The gap (s) after which the last detect() started the state again; 0 when it did not.
  double restartGap() const { return restart_gap_s_; }

  /// True once for the first detect() after a prepare() (the nodelet logs its time).
  bool firstFrameAfterPrepare();

  /// Time went back, or the inputs were paused: the detector's state (tracks, templates,
  /// previous plane) starts again.
  void reset() {
    detector_.reset();
    detected_ = false;
  }

  const Params& params() const { return frame_params_; }
  const Result& result() const { return result_; }
  const std::string& exceptionText() const { return exception_text_; }

 private:
  LaneDetector detector_;
  Result result_;
  Params frame_params_;  ///< what the detector runs with
  std::mutex params_mutex_;
  Params params_;                ///< latest reconfigured (guarded by params_mutex_)
  uint64_t params_version_ = 0;  ///< bumped by every setParams() (guarded)
  uint64_t applied_version_ = 0;
  cv::Mat depth_swap_;  ///< byte-swapped depth (foreign-endian streams only)
  cv::Size prepared_size_;
  Intrinsics prepared_K_;
  bool first_frame_pending_ = false;
  std::string exception_text_;
  int64_t max_gap_ns_ = 0;        ///< setMaxFrameGap() (0: none)
  bool detected_ = false;         ///< a frame was detected since the last reset
  int64_t last_detected_ns_ = 0;  ///< its stamp
  double restart_gap_s_ = 0.0;
};

}  // namespace rgbd_lane_detector
