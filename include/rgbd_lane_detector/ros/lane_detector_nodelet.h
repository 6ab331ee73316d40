/**
 * @file lane_detector_nodelet.h
 * @brief Nodelet wrapping the ROS-free LaneDetector: synchronised colour, depth and
 * camera_info in; lane plane, markings, points, response maps, overlay and rviz markers out.
 * See docs/NODELET.md for topics and parameters.
 */
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/publisher.h>
#include <dynamic_reconfigure/server.h>
#include <image_transport/image_transport.h>
#include <image_transport/subscriber_filter.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <Eigen/Geometry>
#include <boost/thread/recursive_mutex.hpp>

#include <rgbd_lane_detector/LaneDetectorConfig.h>

#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

class LaneDetectorNodelet : public nodelet::Nodelet {
 public:
  LaneDetectorNodelet() = default;
  ~LaneDetectorNodelet() override;

 private:
  using Image = sensor_msgs::Image;
  using CameraInfo = sensor_msgs::CameraInfo;
  using ApproximatePolicy =
      message_filters::sync_policies::ApproximateTime<Image, Image, CameraInfo>;
  using ExactPolicy = message_filters::sync_policies::ExactTime<Image, Image, CameraInfo>;
  using ReconfigureServer = dynamic_reconfigure::Server<LaneDetectorConfig>;

  /// Which outputs have subscribers this frame (lazy publishing).
  struct Wanted {
    bool plane = false, markings = false, points = false, markers = false, model = false;
    bool left = false, right = false, geometric = false, debug = false;
    bool any() const {
      return plane || markings || points || markers || model || left || right || geometric ||
             debug;
    }
  };

  /// Frames dropped for one reason (static text, compared by address then by content).
  struct DropCount {
    const char* reason = nullptr;
    uint64_t count = 0;
  };
  /// A colour frame received and not yet emitted by the synchroniser (identity and stamp).
  struct PendingFrame {
    const void* msg = nullptr;
    ros::Time stamp;
  };
  static constexpr size_t kMaxDropReasons = 24;  ///< the last slot counts every further reason
  static constexpr size_t kPendingCapacity = 256;

  /// Per-frame statistics for the diagnostics (guarded by stats_mutex_). Every colour frame
  /// received is, at any time, exactly one of: processed, dropped (by reason), skipped, not
  /// synchronised, or waiting (in `pending`); see docs/NODELET.md.
  struct Stats {
    uint64_t received = 0;           ///< colour frames received by the nodelet (total)
    uint64_t synchronised = 0;       ///< sets emitted by the synchroniser (total)
    uint64_t processed = 0;          ///< frames published (total)
    uint64_t dropped = 0;            ///< frames dropped (total, the sum of drop_counts)
    uint64_t skipped = 0;            ///< synchronised after the last output subscriber left
    uint64_t not_synchronised = 0;   ///< received, then overtaken by a later synchronised frame
    uint64_t ring_overflow = 0;      ///< part of not_synchronised: evicted from a full `pending`
    uint64_t late_synchronised = 0;  ///< emitted after being counted as not synchronised
    uint64_t untracked = 0;          ///< emitted but never received (never expected)
    uint64_t lost_before = 0;        ///< gaps in the colour header.seq while subscribed
    bool seq_restart = true;         ///< next colour seq starts a new run (subscribe, seq back)
    uint32_t last_seq = 0;
    DropCount drop_counts[kMaxDropReasons];
    PendingFrame pending[kPendingCapacity];  ///< ring in arrival order
    size_t pending_head = 0, pending_count = 0;
    uint64_t window_count = 0;      ///< processed since the last diagnostics update
    uint64_t window_dropped = 0;    ///< dropped since the last diagnostics update
    double window_callback_ms = 0;  ///< sum of whole-callback times in the window
    double window_detect_ms = 0;    ///< sum of core detect() times in the window
    double window_max_ms = 0;       ///< slowest callback in the window
    const char* last_drop = "";     ///< static description of the last drop
  };

  void onInit() override;
  void readInitialConfig(ros::NodeHandle& pnh);
  /// Subscribe to the inputs when any output has a subscriber, unsubscribe when none has.
  void connectCb();
  void configCallback(LaneDetectorConfig& config, uint32_t level);
  void frameCallback(const sensor_msgs::ImageConstPtr& colour,
                     const sensor_msgs::ImageConstPtr& depth,
                     const sensor_msgs::CameraInfoConstPtr& info);
  /// The frame's fate: nullptr processed, kSkippedFrame skipped, else the drop reason.
  const char* processFrame(const Image& colour, const Image& depth, const CameraInfo& info);
  /// Every colour frame the nodelet receives (before the synchroniser): counts, seq gaps, ring.
  void colourReceived(const sensor_msgs::ImageConstPtr& colour);
  /// Account one synchronised frame with its fate (processFrame's result) and callback time.
  void accountFrame(const Image& colour, const char* outcome, double callback_ms);
  Wanted wantedOutputs() const;
  /// Copy the latest reconfigured Params and the up axis into the detector when they changed.
  /// @return false (frame to skip) when the up axis is requested but unavailable.
  bool updateDetectorParams(const std::string& optical_frame);
  /// The lane model's vehicle frame for this frame (tf lookup of lane_model_frame, else the
  /// road-aligned fallback once the plane is known) and the odometry motion since the last one.
  void setVehicleFrame(const std_msgs::Header& header, Frame& frame);
  /// Transform from the optical frame into the output frame; false (frame to skip) if missing.
  bool outputTransform(const std_msgs::Header& header, Eigen::Isometry3d& T, std::string& frame_id);
  void publishOutputs(const Wanted& wanted, const Frame& frame,
                      const std_msgs::Header& image_header, const std_msgs::Header& out_header,
                      const Eigen::Isometry3d& T);
  /// Bad input: a throttled error naming the problem; returns @p problem (static text).
  const char* dropFrame(const char* problem, const Image& colour, const Image& depth);
  void processingDiagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat);

  // --- inputs (declared before the synchronisers, which hold references to them) ---------------
  std::shared_ptr<image_transport::ImageTransport> it_;
  image_transport::SubscriberFilter sub_colour_;
  image_transport::SubscriberFilter sub_depth_;
  message_filters::Subscriber<CameraInfo> sub_info_;
  std::unique_ptr<message_filters::Synchronizer<ApproximatePolicy>> approximate_sync_;
  std::unique_ptr<message_filters::Synchronizer<ExactPolicy>> exact_sync_;
  int queue_size_ = 5;
  std::mutex connect_mutex_;

  // --- outputs -----------------------------------------------------------------------------
  ros::Publisher pub_plane_, pub_markings_, pub_points_, pub_markers_, pub_model_;
  image_transport::Publisher pub_left_, pub_right_, pub_geometric_, pub_debug_;

  // --- parameters: written by configCallback, read by frameCallback ------------------------------
  boost::recursive_mutex config_mutex_;  ///< the reconfigure server's own lock
  std::unique_ptr<ReconfigureServer> reconfigure_server_;
  std::mutex params_mutex_;
  Params params_;                ///< latest sanitised config (guarded by params_mutex_)
  uint64_t params_version_ = 0;  ///< bumped by every config change (guarded)

  // --- frame state (frame callbacks are serialised on the nodelet's callback queue) -----------
  LaneDetector detector_;
  Result result_;
  Params frame_params_;  ///< parameters the detector runs with
  uint64_t applied_version_ = 0;
  ros::Time last_stamp_;
  cv::Mat depth_swap_;  ///< byte-swapped depth (foreign-endian streams only)

  // --- tf -----------------------------------------------------------------------------------
  std::string target_frame_;  ///< output frame; empty: the colour optical frame
  std::string up_frame_;      ///< frame whose +z is the road's up axis; empty: camera -y
  double tf_timeout_ = 0.05;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  // --- lane model: its vehicle frame and odometry ------------------------------------------
  std::string lane_model_frame_;  ///< vehicle frame (REP-103); "" or unknown: the road frame
  std::string odom_frame_;        ///< fixed frame for the motion between frames; "": none
  bool vehicle_frame_found_ = false;  ///< the last frame's vehicle frame came from tf
  std::string model_frame_id_;    ///< frame_id of the last lane model
  ros::Time last_model_stamp_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> road_frame_broadcaster_;

  // --- diagnostics (declared so that the timer goes first, the updater last) ------------------
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  double min_rate_ = 1.0, max_rate_ = 100.0;
  std::unique_ptr<diagnostic_updater::TopicDiagnostic> rate_diagnostic_;
  ros::Timer diagnostics_timer_;
  std::mutex stats_mutex_;
  Stats stats_;
};

}  // namespace rgbd_lane_detector
