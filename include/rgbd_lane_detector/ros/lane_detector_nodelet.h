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
#include <message_filters/pass_through.h>
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
#include "rgbd_lane_detector/lane_grid.h"
#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

class FrameAccounting;  // src/ros/frame_accounting.h (private to the nodelet)
enum class FrameOutcome : uint8_t;
class StampJumpDetector;  // src/ros/stamp_jump_detector.h (private to the nodelet)

class LaneDetectorNodelet : public nodelet::Nodelet {
 public:
  LaneDetectorNodelet() = default;
  ~LaneDetectorNodelet() override;

 private:
  using Image = sensor_msgs::Image;
  using CameraInfo = sensor_msgs::CameraInfo;
  using ImageEvent = ros::MessageEvent<const Image>;
  using CameraInfoEvent = ros::MessageEvent<const CameraInfo>;
  using ApproximatePolicy =
      message_filters::sync_policies::ApproximateTime<Image, Image, CameraInfo>;
  using ExactPolicy = message_filters::sync_policies::ExactTime<Image, Image, CameraInfo>;
  using ReconfigureServer = dynamic_reconfigure::Server<LaneDetectorConfig>;

  /// Which outputs have subscribers this frame (lazy publishing).
  struct Wanted {
    bool plane = false, markings = false, points = false, markers = false, model = false;
    bool centre = false;  ///< lane_centre_line
    bool grid = false;    ///< lane_grid
    bool left = false, right = false, geometric = false, debug = false;
    bool any() const {
      return plane || markings || points || markers || model || centre || grid || left || right ||
             geometric || debug;
    }
  };

  enum Input : size_t { kColourInput, kDepthInput, kInfoInput, kInputs };

  void onInit() override;
  /// Throws (after a fatal log naming the plugin and its package) when ~image_transport or
  /// ~depth_image_transport names a transport whose plugin is not installed.
  void checkTransports(ros::NodeHandle& pnh);
  /// (Re)create the synchroniser on the pass-throughs: empty queues.
  void makeSynchroniser();
  /// Every input message's stamp: a jump back in time resets what depends on time, once.
  /// @return false for a late message from before the last jump (not to be synchronised)
  bool acceptInput(size_t input, const ros::Time& stamp);
  void readInitialConfig(ros::NodeHandle& pnh);
  /// Subscribe to the inputs when any output has a subscriber, unsubscribe when none has.
  void connectCb();
  void configCallback(LaneDetectorConfig& config, uint32_t level);
  void frameCallback(const sensor_msgs::ImageConstPtr& colour,
                     const sensor_msgs::ImageConstPtr& depth,
                     const sensor_msgs::CameraInfoConstPtr& info);
  /// The frame's fate; @p detail names a drop's problem (static text) or stays null.
  /// On camera_info: LaneDetector::prepare() when the camera's size or intrinsics change.
  void prepareDetector(const CameraInfo& info);
  FrameOutcome processFrame(const Image& colour, const Image& depth, const CameraInfo& info,
                            const char*& detail);
  /// Every colour frame the nodelet receives: counted in accounting_, then acceptInput().
  void colourReceived(const ImageEvent& event);
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
  /// Bad input: a throttled error naming the problem; returns @p outcome with @p detail = problem.
  FrameOutcome dropFrame(FrameOutcome outcome, const char* problem, const char*& detail,
                         const Image& colour, const Image& depth);
  void processingDiagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat);

  // --- inputs (declared before the synchronisers, which hold references to them) ---------------
  std::shared_ptr<image_transport::ImageTransport> it_;
  image_transport::SubscriberFilter sub_colour_;
  image_transport::SubscriberFilter sub_depth_;
  message_filters::Subscriber<CameraInfo> sub_info_;
  message_filters::PassThrough<Image> pass_colour_, pass_depth_;
  message_filters::PassThrough<CameraInfo> pass_info_;
  std::unique_ptr<message_filters::Synchronizer<ApproximatePolicy>> approximate_sync_filter_;
  std::unique_ptr<message_filters::Synchronizer<ExactPolicy>> exact_sync_filter_;
  bool approximate_sync_ = true;
  int queue_size_ = 5;
  std::unique_ptr<StampJumpDetector> jumps_;  ///< input stamps going back (frame callbacks only)
  ros::WallTime last_jump_log_;               ///< when a jump was last logged
  uint64_t jumps_not_logged_ = 0;             ///< jumps since then (a stream going back and forth)
  std::mutex connect_mutex_;

  // --- outputs -----------------------------------------------------------------------------
  ros::Publisher pub_plane_, pub_markings_, pub_points_, pub_markers_, pub_model_, pub_centre_;
  ros::Publisher pub_grid_;  ///< lane_grid (nav_msgs/OccupancyGrid)
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
  LaneGrid lane_grid_;  ///< built from result_.lane_model for lane_grid and the debug inset
  Params frame_params_;  ///< parameters the detector runs with
  uint64_t applied_version_ = 0;
  cv::Mat depth_swap_;  ///< byte-swapped depth (foreign-endian streams only)
  cv::Size prepared_size_;      ///< camera the detector was last prepared for
  Intrinsics prepared_K_;
  bool first_frame_pending_ = false;  ///< log the first detect() after prepare()

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
  std::unique_ptr<FrameAccounting> accounting_;  ///< every colour frame's fate (thread-safe)
};

}  // namespace rgbd_lane_detector
