// Thin ROS wrapper of the core detector: parameters, synchronised inputs, lazy outputs.
// Every message <-> core conversion lives in conversions.cpp.
#include "rgbd_lane_detector/ros/lane_detector_nodelet.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>
#include <stdexcept>

#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2/exceptions.h>
#include <tf2_eigen/tf2_eigen.h>
#include <visualization_msgs/MarkerArray.h>
#include <boost/bind/bind.hpp>
#include <boost/make_shared.hpp>

#include <rgbd_lane_detector/LaneMarkings.h>
#include <rgbd_lane_detector/LaneModel.h>
#include <rgbd_lane_detector/LanePlane.h>

#include "frame_accounting.h"
#include "rgbd_lane_detector/lane_model.h"
#include "rgbd_lane_detector/overlay.h"
#include "rgbd_lane_detector/ros/conversions.h"
#include "stamp_jump_detector.h"

namespace rgbd_lane_detector {
namespace {

using Clock = std::chrono::steady_clock;
using namespace boost::placeholders;
namespace conv = conversions;

constexpr double kThrottle = 5.0;  // s between repeated per-frame warnings / errors

/// The package of image_transport_plugins that provides a transport's plugins (null: unknown).
const char* transportPackage(const std::string& transport) {
  if (transport == "compressed") return "compressed_image_transport";
  if (transport == "compressedDepth") return "compressed_depth_image_transport";
  if (transport == "theora") return "theora_image_transport";
  return nullptr;
}

}  // namespace

LaneDetectorNodelet::~LaneDetectorNodelet() {
  diagnostics_timer_.stop();
  // no input callback after this point (they use the members destroyed next)
  std::lock_guard<std::mutex> lock(connect_mutex_);
  sub_colour_.unsubscribe();
  sub_depth_.unsubscribe();
  sub_info_.unsubscribe();
}

void LaneDetectorNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  it_ = std::make_shared<image_transport::ImageTransport>(nh);
  accounting_.reset(new FrameAccounting);

  // A configured image transport whose plugin is missing fails here, naming it (otherwise the
  // first output subscriber would make the nodelet subscribe and fail silently, with no frames).
  checkTransports(pnh);

  // Inputs: subscriber -> bookkeeping -> pass-through -> synchroniser. The bookkeeping counts
  // every colour frame, checks every stamp for a jump back in time and drops the late messages
  // from before a jump; the pass-throughs let a jump replace the synchroniser from inside a
  // subscriber's callback. The subscriptions themselves are made in connectCb.
  sub_colour_.registerCallback(boost::function<void(const ImageEvent&)>(
      boost::bind(&LaneDetectorNodelet::colourReceived, this, _1)));
  sub_depth_.registerCallback(boost::function<void(const ImageEvent&)>([this](const ImageEvent& e) {
    if (acceptInput(kDepthInput, e.getMessage()->header.stamp)) pass_depth_.add(e);
  }));
  sub_info_.registerCallback(
      boost::function<void(const CameraInfoEvent&)>([this](const CameraInfoEvent& e) {
        if (!acceptInput(kInfoInput, e.getMessage()->header.stamp)) return;
        prepareDetector(*e.getMessage());  // before its frame can be synchronised
        pass_info_.add(e);
      }));
  jumps_.reset(new StampJumpDetector(kInputs));
  pnh.param("queue_size", queue_size_, 5);
  queue_size_ = std::max(1, queue_size_);
  pnh.param("approximate_sync", approximate_sync_, true);
  makeSynchroniser();

  // tf: only when an output frame, an up frame or the lane model's vehicle frame is requested.
  pnh.param<std::string>("target_frame", target_frame_, "");
  pnh.param<std::string>("up_frame", up_frame_, "");
  pnh.param<std::string>("lane_model_frame", lane_model_frame_, "base_link");
  pnh.param<std::string>("odom_frame", odom_frame_, "");
  pnh.param("tf_timeout", tf_timeout_, 0.05);
  tf_timeout_ = std::max(0.0, tf_timeout_);
  if (!target_frame_.empty() || !up_frame_.empty() || !lane_model_frame_.empty()) {
    tf_buffer_.reset(new tf2_ros::Buffer);
    tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_));
  }

  // Parameters: initial values from the parameter server (and the mode preset), then every
  // change through dynamic_reconfigure. setCallback() runs configCallback once.
  readInitialConfig(pnh);
  reconfigure_server_.reset(new ReconfigureServer(config_mutex_, pnh));
  reconfigure_server_->setCallback(boost::bind(&LaneDetectorNodelet::configCallback, this, _1, _2));
  {
    std::lock_guard<std::mutex> lock(params_mutex_);
    frame_params_ = params_;
    applied_version_ = params_version_;
  }
  detector_.setParams(frame_params_);

  // Diagnostics: output rate and stamp delay, per-frame processing time and drops.
  updater_.reset(new diagnostic_updater::Updater(nh, pnh, getName()));
  std::string hardware_id;
  pnh.param<std::string>("diagnostic_hardware_id", hardware_id, "none");
  updater_->setHardwareID(hardware_id);
  pnh.param("diagnostic_min_rate", min_rate_, 1.0);
  pnh.param("diagnostic_max_rate", max_rate_, 100.0);
  double max_delay = 1.0;
  pnh.param("diagnostic_max_delay", max_delay, 1.0);
  rate_diagnostic_.reset(new diagnostic_updater::TopicDiagnostic(
      "output rate", *updater_,
      diagnostic_updater::FrequencyStatusParam(&min_rate_, &max_rate_, 0.1, 10),
      diagnostic_updater::TimeStampStatusParam(-1.0, max_delay)));
  updater_->add("processing", this, &LaneDetectorNodelet::processingDiagnostics);
  diagnostics_timer_ = nh.createTimer(ros::Duration(std::max(0.05, updater_->getPeriod())),
                                      [this](const ros::TimerEvent&) { updater_->force_update(); });

  // Outputs. Advertise under the connect mutex so that connectCb, which may run as soon as
  // the first publisher exists, never sees the others half-assigned (as image_proc does).
  ros::SubscriberStatusCallback connect_cb = boost::bind(&LaneDetectorNodelet::connectCb, this);
  image_transport::SubscriberStatusCallback image_connect_cb =
      boost::bind(&LaneDetectorNodelet::connectCb, this);
  std::lock_guard<std::mutex> lock(connect_mutex_);
  pub_plane_ = nh.advertise<LanePlane>("lane_plane", 5, connect_cb, connect_cb);
  pub_markings_ = nh.advertise<LaneMarkings>("lane_markings", 5, connect_cb, connect_cb);
  pub_points_ = nh.advertise<sensor_msgs::PointCloud2>("lane_points", 5, connect_cb, connect_cb);
  pub_markers_ = nh.advertise<visualization_msgs::MarkerArray>("lane_visualization", 5, connect_cb,
                                                               connect_cb);
  pub_model_ = nh.advertise<LaneModel>("lane_model", 5, connect_cb, connect_cb);
  pub_centre_ = nh.advertise<nav_msgs::Path>("lane_centre_line", 5, connect_cb, connect_cb);
  pub_grid_ = nh.advertise<nav_msgs::OccupancyGrid>("lane_grid", 5, connect_cb, connect_cb);
  pub_left_ = it_->advertise("response/left", 1, image_connect_cb, image_connect_cb);
  pub_right_ = it_->advertise("response/right", 1, image_connect_cb, image_connect_cb);
  pub_geometric_ = it_->advertise("response/geometric", 1, image_connect_cb, image_connect_cb);
  pub_debug_ = it_->advertise("debug_image", 1, image_connect_cb, image_connect_cb);
  NODELET_INFO("Lane detector ready (%s sync, output frame: %s, up axis: %s)",
               approximate_sync_ ? "approximate" : "exact",
               target_frame_.empty() ? "colour optical frame" : target_frame_.c_str(),
               up_frame_.empty() ? "camera -y" : ("+z of " + up_frame_).c_str());
}

void LaneDetectorNodelet::checkTransports(ros::NodeHandle& pnh) {
  std::string missing;
  std::vector<std::string> loadable;  // "<package>/<transport>", looked up once if needed
  for (const char* param : {"image_transport", "depth_image_transport"}) {
    std::string transport;
    pnh.param<std::string>(param, transport, "raw");
    if (transport == "raw") continue;  // built into image_transport
    if (loadable.empty()) loadable = it_->getLoadableTransports();
    const bool found = std::any_of(loadable.begin(), loadable.end(), [&](const std::string& l) {
      return l.size() > transport.size() &&
             l.compare(l.size() - transport.size() - 1, std::string::npos, "/" + transport) == 0;
    });
    if (found) continue;
    std::string names;
    for (const std::string& l : loadable) names += (names.empty() ? "" : ", ") + l;
    const char* package = transportPackage(transport);
    missing += std::string(missing.empty() ? "" : " ") + "Image transport '" + transport +
               "' (parameter ~" + param + ") is not installed: image_transport has no '" +
               transport + "' subscriber plugin here (loadable: " + names + ").";
    if (package)
      missing += std::string(" It is provided by the package ") + package +
                 " (ROS Noetic: ros-noetic-image-transport-plugins).";
    missing += std::string(" Install it, or set ~") + param + " to raw.";
  }
  if (missing.empty()) return;
  NODELET_FATAL("%s", missing.c_str());
  throw std::runtime_error(missing);  // the manager (or lane_detector_node) refuses to load us
}

void LaneDetectorNodelet::makeSynchroniser() {
  // the old one (if any) is destroyed first: it disconnects from the pass-throughs
  if (approximate_sync_) {
    approximate_sync_filter_.reset();
    approximate_sync_filter_.reset(new message_filters::Synchronizer<ApproximatePolicy>(
        ApproximatePolicy(queue_size_), pass_colour_, pass_depth_, pass_info_));
    approximate_sync_filter_->registerCallback(
        boost::bind(&LaneDetectorNodelet::frameCallback, this, _1, _2, _3));
  } else {
    exact_sync_filter_.reset();
    exact_sync_filter_.reset(new message_filters::Synchronizer<ExactPolicy>(
        ExactPolicy(queue_size_), pass_colour_, pass_depth_, pass_info_));
    exact_sync_filter_->registerCallback(
        boost::bind(&LaneDetectorNodelet::frameCallback, this, _1, _2, _3));
  }
}

bool LaneDetectorNodelet::acceptInput(size_t input, const ros::Time& stamp) {
  const StampJumpDetector::Verdict verdict =
      jumps_->update(input, static_cast<int64_t>(stamp.toNSec()));
  if (verdict == StampJumpDetector::Verdict::kStale) return false;  // from before the last jump
  if (verdict == StampJumpDetector::Verdict::kCurrent) return true;
  // Time went back (rosbag loop, a camera clock restarting): everything that depends on time
  // starts again, said in one line. The images synchronised from now on are this epoch's only.
  detector_.reset();  // lane tracker, lane model, adapted templates, previous plane
  last_model_stamp_ = ros::Time();  // no odometry prediction across the jump
  makeSynchroniser();
  if (tf_buffer_) tf_buffer_->clear();  // transforms of the old epoch (static ones are kept)
  const ros::WallTime now = ros::WallTime::now();  // wall time: sim time itself went back
  if (now - last_jump_log_ < ros::WallDuration(1.0)) {
    ++jumps_not_logged_;  // a stream going back and forth: at most one line a second
    return true;
  }
  NODELET_WARN(
      "Input stamps went back %.3f s (rosbag loop or a restarted camera clock?): reset "
      "the detector state (lane tracker, templates, previous plane), the synchroniser "
      "queues%s%s",
      static_cast<double>(jumps_->lastJumpNs()) * 1e-9, tf_buffer_ ? " and the tf buffer" : "",
      jumps_not_logged_ > 0
          ? (" (" + std::to_string(jumps_not_logged_) + " more jumps since the last line)").c_str()
          : "");
  last_jump_log_ = now;
  jumps_not_logged_ = 0;
  return true;
}

void LaneDetectorNodelet::readInitialConfig(ros::NodeHandle& pnh) {
  // `mode` (improved, the default, | paper) gives the initial value of every parameter that is
  // not set explicitly; explicit private parameters win (as in loadParamsYaml: preset, then keys).
  std::string mode;
  pnh.param<std::string>("mode", mode, "improved");
  Params preset_params, other_params;
  if (!paramsForMode(mode, preset_params)) {
    NODELET_ERROR("Unknown mode '%s' (expected improved or paper): improved", mode.c_str());
    mode = "improved";
    preset_params = Params::improved();
  }
  paramsForMode(mode == "improved" ? "paper" : "improved", other_params);
  LaneDetectorConfig preset = LaneDetectorConfig::__getDefault__();
  LaneDetectorConfig other = preset;
  conv::paramsToConfig(preset_params, preset);
  conv::paramsToConfig(other_params, other);
  std::string overridden;
  for (const auto& param : LaneDetectorConfig::__getParamDescriptions__()) {
    if (!pnh.hasParam(param->name)) {
      param->toServer(pnh, preset);
      continue;
    }
    dynamic_reconfigure::Config preset_value, other_value;
    param->toMessage(preset_value, preset);
    param->toMessage(other_value, other);
    if (!(preset_value == other_value)) overridden += " " + param->name;
  }
  NODELET_INFO(
      "Mode '%s': preset values for the parameters not given%s%s", mode.c_str(),
      overridden.empty() ? "" : "; given explicitly, overriding the preset:", overridden.c_str());
}

void LaneDetectorNodelet::connectCb() {
  std::lock_guard<std::mutex> lock(connect_mutex_);
  if (!wantedOutputs().any()) {
    NODELET_DEBUG("No subscribers: unsubscribing from the inputs");
    sub_colour_.unsubscribe();
    sub_depth_.unsubscribe();
    sub_info_.unsubscribe();
  } else if (!sub_colour_.getSubscriber()) {
    NODELET_DEBUG("Subscribing to the inputs");
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    // transport hints from ~image_transport and ~depth_image_transport (e.g. compressedDepth)
    const image_transport::TransportHints colour_hints("raw", ros::TransportHints(), pnh,
                                                       "image_transport");
    const image_transport::TransportHints depth_hints("raw", ros::TransportHints(), pnh,
                                                      "depth_image_transport");
    sub_colour_.subscribe(*it_, "rgb/image_rect_color", queue_size_, colour_hints);
    sub_depth_.subscribe(*it_, "depth_registered/image_rect", queue_size_, depth_hints);
    sub_info_.subscribe(nh, "rgb/camera_info", queue_size_);
    accounting_->restartSequence();  // seq gaps across an unsubscribed period are not losses
  }
}

void LaneDetectorNodelet::configCallback(LaneDetectorConfig& config, uint32_t /*level*/) {
  std::lock_guard<std::mutex> lock(params_mutex_);
  Params p = params_;  // keeps the non-reconfigurable fields (up axis)
  if (conv::configToParams(config, p) != 0)
    NODELET_ERROR_ONCE(
        "Some dynamic_reconfigure parameters have no core Params field (cfg and "
        "params_io.h disagree): they are ignored");
  p = sanitize(p);
  conv::paramsToConfig(p, config);  // show the repaired values (odd windows...) in the GUI
  params_ = p;
  ++params_version_;
}

LaneDetectorNodelet::Wanted LaneDetectorNodelet::wantedOutputs() const {
  Wanted w;
  w.plane = pub_plane_.getNumSubscribers() > 0;
  w.markings = pub_markings_.getNumSubscribers() > 0;
  w.points = pub_points_.getNumSubscribers() > 0;
  w.markers = pub_markers_.getNumSubscribers() > 0;
  w.model = pub_model_.getNumSubscribers() > 0;
  w.centre = pub_centre_.getNumSubscribers() > 0;
  w.grid = pub_grid_.getNumSubscribers() > 0;
  w.left = pub_left_.getNumSubscribers() > 0;
  w.right = pub_right_.getNumSubscribers() > 0;
  w.geometric = pub_geometric_.getNumSubscribers() > 0;
  w.debug = pub_debug_.getNumSubscribers() > 0;
  return w;
}

bool LaneDetectorNodelet::updateDetectorParams(const std::string& optical_frame) {
  Params p;
  bool changed = false;
  {
    std::lock_guard<std::mutex> lock(params_mutex_);
    if (params_version_ != applied_version_) {
      p = params_;
      applied_version_ = params_version_;
      changed = true;
    }
  }
  if (!changed) p = frame_params_;
  if (!up_frame_.empty()) {
    try {
      const Eigen::Vector3d up =
          conv::upAxisFromTransform(tf2::transformToEigen(tf_buffer_->lookupTransform(
              optical_frame, up_frame_, ros::Time(0), ros::Duration(tf_timeout_))));
      p.up_x = up.x();
      p.up_y = up.y();
      p.up_z = up.z();
    } catch (const tf2::TransformException& e) {
      NODELET_WARN_THROTTLE(kThrottle,
                            "Skipping frame: no transform from up_frame '%s' to '%s': %s",
                            up_frame_.c_str(), optical_frame.c_str(), e.what());
      return false;
    }
  }
  const Params& q = frame_params_;
  constexpr double kUpTolerance = 1e-6;  // a static mount gives the same axis every frame
  if (changed || std::fabs(p.up_x - q.up_x) > kUpTolerance ||
      std::fabs(p.up_y - q.up_y) > kUpTolerance || std::fabs(p.up_z - q.up_z) > kUpTolerance) {
    detector_.setParams(p);
    frame_params_ = detector_.params();
  }
  return true;
}

void LaneDetectorNodelet::setVehicleFrame(const std_msgs::Header& header, Frame& frame) {
  frame.has_vehicle_frame = false;
  vehicle_frame_found_ = false;
  model_frame_id_ = header.frame_id + "_road";
  if (!frame_params_.lane_model) return;
  if (!lane_model_frame_.empty() && tf_buffer_) {
    try {
      frame.vehicle_from_camera = tf2::transformToEigen(tf_buffer_->lookupTransform(
          lane_model_frame_, header.frame_id, header.stamp, ros::Duration(tf_timeout_)));
      frame.has_vehicle_frame = true;
      vehicle_frame_found_ = true;
      model_frame_id_ = lane_model_frame_;
    } catch (const tf2::TransformException& e) {
      NODELET_WARN_THROTTLE(kThrottle,
                            "lane_model in the road frame '%s' under the camera: no transform "
                            "from '%s' to lane_model_frame '%s': %s",
                            model_frame_id_.c_str(), header.frame_id.c_str(),
                            lane_model_frame_.c_str(), e.what());
    }
  }
  // the vehicle's motion since the last frame, from odometry, moves the model
  if (vehicle_frame_found_ && !odom_frame_.empty() && !last_model_stamp_.isZero() &&
      header.stamp > last_model_stamp_) {
    try {
      detector_.predictMotion(tf2::transformToEigen(tf_buffer_->lookupTransform(
          lane_model_frame_, last_model_stamp_, lane_model_frame_, header.stamp, odom_frame_,
          ros::Duration(tf_timeout_))));
    } catch (const tf2::TransformException& e) {
      NODELET_WARN_THROTTLE(kThrottle, "lane_model without motion prediction: %s", e.what());
    }
  }
  last_model_stamp_ = header.stamp;
}

bool LaneDetectorNodelet::outputTransform(const std_msgs::Header& header, Eigen::Isometry3d& T,
                                          std::string& frame_id) {
  T.setIdentity();
  if (target_frame_.empty() || target_frame_ == header.frame_id) {
    frame_id = header.frame_id;
    return true;
  }
  try {
    T = tf2::transformToEigen(tf_buffer_->lookupTransform(
        target_frame_, header.frame_id, header.stamp, ros::Duration(tf_timeout_)));
  } catch (const tf2::TransformException& e) {
    NODELET_WARN_THROTTLE(
        kThrottle, "Skipping frame: no transform from '%s' to target_frame '%s' at %.3f: %s",
        header.frame_id.c_str(), target_frame_.c_str(), header.stamp.toSec(), e.what());
    return false;
  }
  frame_id = target_frame_;
  return true;
}

void LaneDetectorNodelet::prepareDetector(const CameraInfo& info) {
  // New camera (start, resolution or calibration change): allocate and plan the detector now,
  // so that the first frame costs about a steady-state one. A driver re-estimating its
  // calibration (sameCamera()) is the same camera: its frames keep the prepared intrinsics
  // (processFrame()), so the detector neither re-plans nor loses its tracks on every message.
  const Intrinsics K = conv::intrinsicsFromCameraInfo(info);
  const cv::Size size(static_cast<int>(info.width), static_cast<int>(info.height));
  if (size == prepared_size_ && conv::sameCamera(prepared_K_, K)) return;
  prepared_size_ = size;
  prepared_K_ = K;
  const Clock::time_point start = Clock::now();
  const Status status = detector_.prepare(size, K);
  if (status != Status::kOk) return;  // the frames will be dropped, naming the problem
  // A rectified image comes with its camera's camera_info (D of the raw lens, P of the
  // rectified image): only a colour topic that is not a rectified one is a problem
  const std::string colour_topic = sub_colour_.getTopic();
  if (conv::hasDistortion(info) && colour_topic.find("rect") == std::string::npos)
    NODELET_WARN("camera_info has distortion coefficients (model '%s') and the colour topic '%s' "
                 "is not a rectified image: the detector reads images as rectified (pinhole P, "
                 "else K), so lines toward the image edges come out displaced. Feed it rectified "
                 "images (image_proc: image_rect_color).",
                 info.distortion_model.c_str(), colour_topic.c_str());
  NODELET_INFO("Detector prepared for %dx%d frames in %.1f ms (fx %.3f, fy %.3f, cx %.3f, cy %.3f)",
               size.width, size.height,
               std::chrono::duration<double, std::milli>(Clock::now() - start).count(), K.fx, K.fy,
               K.cx, K.cy);
  first_frame_pending_ = true;
}

void LaneDetectorNodelet::frameCallback(const sensor_msgs::ImageConstPtr& colour,
                                        const sensor_msgs::ImageConstPtr& depth,
                                        const sensor_msgs::CameraInfoConstPtr& info) {
  const Clock::time_point start = Clock::now();
  const char* detail = nullptr;
  const FrameOutcome outcome = processFrame(*colour, *depth, *info, detail);
  const double callback_ms =
      std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  accounting_->synchronised(colour.get(), static_cast<int64_t>(colour->header.stamp.toNSec()),
                            outcome, detail, callback_ms, result_.timings.total);
}

FrameOutcome LaneDetectorNodelet::processFrame(const Image& colour, const Image& depth,
                                               const CameraInfo& info, const char*& detail) {
  const Wanted wanted = wantedOutputs();
  if (!wanted.any()) return FrameOutcome::kSkipped;  // the last subscriber left meanwhile
  const std_msgs::Header& image_header = colour.header;

  if (!updateDetectorParams(image_header.frame_id)) return FrameOutcome::kNoUpTransform;
  Frame frame;
  if (const char* problem = conv::frameFromMsgs(colour, depth, info, frame, depth_swap_))
    return dropFrame(FrameOutcome::kBadMessage, problem, detail, colour, depth);
  if (frame.colour.size() == prepared_size_ && conv::sameCamera(prepared_K_, frame.intrinsics))
    frame.intrinsics = prepared_K_;  // calibration jitter (prepareDetector())
  const Status valid = detector_.validate(frame);
  if (valid != Status::kOk)
    return dropFrame(FrameOutcome::kInvalidFrame, statusMessage(valid), detail, colour, depth);
  std_msgs::Header out_header = image_header;
  Eigen::Isometry3d T;
  if (!outputTransform(image_header, T, out_header.frame_id))
    return FrameOutcome::kNoTargetTransform;
  setVehicleFrame(image_header, frame);

  // G everywhere only for the response/geometric image; R needs it where M >= tau_G only
  detector_.setFullGeometricMap(wanted.geometric);
  Status status;
  try {
    status = detector_.detect(frame, result_);
  } catch (const std::exception& e) {  // never expected: the frame was validated
    NODELET_ERROR_THROTTLE(kThrottle, "Dropping frame: detector failed: %s", e.what());
    return FrameOutcome::kDetectorException;
  }
  if (status != Status::kOk)
    return dropFrame(FrameOutcome::kInvalidFrame, statusMessage(status), detail, colour, depth);
  if (first_frame_pending_) {  // the first frame after prepare(): measured by measure_nodelet.sh
    first_frame_pending_ = false;
    NODELET_INFO("First frame after prepare: detect() %.2f ms", result_.timings.total);
  }
  publishOutputs(wanted, frame, image_header, out_header, T);
  rate_diagnostic_->tick(image_header.stamp);
  return FrameOutcome::kProcessed;
}

void LaneDetectorNodelet::publishOutputs(const Wanted& wanted, const Frame& frame,
                                         const std_msgs::Header& image_header,
                                         const std_msgs::Header& out_header,
                                         const Eigen::Isometry3d& T) {
  // Messages are allocated per publish (ROS 1 shares them with intra-process subscribers).
  if (wanted.plane) {
    auto msg = boost::make_shared<LanePlane>();
    conv::fillLanePlane(result_, out_header, T, *msg);
    pub_plane_.publish(msg);
  }
  if (wanted.markings) {
    auto msg = boost::make_shared<LaneMarkings>();
    conv::fillLaneMarkings(result_, out_header, T, *msg);
    pub_markings_.publish(msg);
  }
  if (wanted.points) {
    auto msg = boost::make_shared<sensor_msgs::PointCloud2>();
    conv::fillLanePoints(result_, out_header, T, *msg);
    pub_points_.publish(msg);
  }
  std_msgs::Header model_header = image_header;
  model_header.frame_id = model_frame_id_;
  if (wanted.model || wanted.centre) {
    auto msg = boost::make_shared<LaneModel>();
    conv::fillLaneModel(result_.lane_model, model_header, *msg);
    // the centre line on its own topic, for rviz's Path display and path followers
    if (wanted.centre) pub_centre_.publish(boost::make_shared<nav_msgs::Path>(msg->centre_line));
    if (wanted.model) pub_model_.publish(msg);
  }
  // the lane grid: for lane_grid and the debug image's inset (its buffer is reused)
  const bool grid_inset = wanted.debug && frame_params_.lane_model;
  if (wanted.grid || grid_inset)
    lane_grid_.build(result_.lane_model, laneGridSettings(frame_params_));
  if (wanted.grid) {
    auto msg = boost::make_shared<nav_msgs::OccupancyGrid>();
    conv::fillOccupancyGrid(lane_grid_, model_header, *msg);
    pub_grid_.publish(msg);
  }
  if (wanted.markers) {
    auto msg = boost::make_shared<visualization_msgs::MarkerArray>();
    conv::fillLaneMarkers(result_, out_header, T, *msg);
    conv::appendLaneModelMarkers(result_.lane_model, model_header, *msg);
    pub_markers_.publish(msg);
  }
  if ((wanted.model || wanted.centre || wanted.markers || wanted.grid) && !vehicle_frame_found_ &&
      result_.plane.valid) {
    // the road-aligned fallback frame, so that rviz and users can place the model
    geometry_msgs::TransformStamped tf = tf2::eigenToTransform(RoadFrame::fromPlane(result_.plane).roadFromCamera().inverse());
    tf.header = image_header;
    tf.child_frame_id = model_frame_id_;
    if (!road_frame_broadcaster_) road_frame_broadcaster_.reset(new tf2_ros::TransformBroadcaster);
    road_frame_broadcaster_->sendTransform(tf);
  }
  // Images stay in the camera's optical frame (they are pixels of that camera), at the
  // processing resolution for the response maps.
  const std::pair<bool, std::pair<const cv::Mat*, image_transport::Publisher*>> maps[] = {
      {wanted.left, {&result_.response_left, &pub_left_}},
      {wanted.right, {&result_.response_right, &pub_right_}},
      {wanted.geometric, {&result_.geometric, &pub_geometric_}}};
  for (const auto& m : maps) {
    if (!m.first) continue;
    auto msg = boost::make_shared<sensor_msgs::Image>();
    conv::floatMapToImage(*m.second.first, image_header, *msg);
    m.second.second->publish(msg);
  }
  if (wanted.debug) {
    auto msg = boost::make_shared<sensor_msgs::Image>();
    cv::Mat out = conv::prepareImage(frame.colour.rows, frame.colour.cols, CV_8UC3,
                                     sensor_msgs::image_encodings::BGR8, image_header, *msg);
    const uchar* data = out.data;
    drawOverlay(frame.colour, frame.format, frame.intrinsics, result_, frame_params_, out);
    if (grid_inset) drawLaneGridInset(lane_grid_, out);
    if (out.data != data) {  // drawn elsewhere (size changed): copy into the message
      const cv::Mat drawn = out;
      out = conv::prepareImage(drawn.rows, drawn.cols, CV_8UC3, sensor_msgs::image_encodings::BGR8,
                               image_header, *msg);
      drawn.copyTo(out);
    }
    pub_debug_.publish(msg);
  }
}

FrameOutcome LaneDetectorNodelet::dropFrame(FrameOutcome outcome, const char* problem,
                                            const char*& detail, const Image& colour,
                                            const Image& depth) {
  NODELET_ERROR_THROTTLE(kThrottle, "Dropping frame: %s [colour %s %ux%u, depth %s %ux%u]", problem,
                         colour.encoding.c_str(), colour.width, colour.height,
                         depth.encoding.c_str(), depth.width, depth.height);
  detail = problem;
  return outcome;
}

void LaneDetectorNodelet::colourReceived(const ImageEvent& event) {
  const sensor_msgs::ImageConstPtr& colour = event.getMessage();
  accounting_->received(colour.get(), static_cast<int64_t>(colour->header.stamp.toNSec()),
                        colour->header.seq);
  if (acceptInput(kColourInput, colour->header.stamp)) pass_colour_.add(event);
}

void LaneDetectorNodelet::processingDiagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  bool subscribed;
  {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    subscribed = static_cast<bool>(sub_colour_.getSubscriber());
  }
  const FrameAccounting::Report r = accounting_->report();
  const double n = static_cast<double>(std::max<uint64_t>(r.window_processed, 1));
  if (r.window_dropped > 0)
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%lu frame(s) dropped: %s",
                  static_cast<unsigned long>(r.window_dropped), r.last_drop);
  else if (!subscribed)
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "Idle: no subscribers");
  else if (r.window_processed == 0)
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "Waiting for frames");
  else
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::OK, "%.1f ms per frame",
                  r.window_callback_ms / n);
  // Cumulative accounting of every colour frame received (docs/NODELET.md):
  // received == processed + dropped + skipped + not synchronised + waiting.
  stat.add("Inputs subscribed", subscribed);
  stat.add("Frames received", r.received);
  stat.add("Frames synchronised", r.synchronised);
  stat.add("Frames processed", r.processed);
  stat.add("Frames dropped", r.dropped);
  stat.add("Frames skipped (no subscriber)", r.skipped);
  stat.add("Frames not synchronised", r.not_synchronised);
  stat.add("Frames waiting", r.waiting);
  stat.add("Frames unaccounted", r.unaccounted());
  stat.add("Frames lost before the nodelet", r.lost_before);
  stat.add("Pending ring overflows", r.ring_overflow);
  stat.add("Frames synchronised late", r.late_synchronised);
  if (r.untracked > 0) stat.add("Frames synchronised untracked", r.untracked);
  for (size_t k = 0; k < r.drop_reasons; ++k)
    stat.add(std::string("Dropped: ") + r.drops[k].reason, r.drops[k].count);
  stat.add("Last drop reason", std::string(r.last_drop));
  stat.addf("Mean processing time (ms)", "%.3f", r.window_callback_ms / n);
  stat.addf("Mean detector time (ms)", "%.3f", r.window_detect_ms / n);
  stat.addf("Mean ROS overhead (ms)", "%.3f", (r.window_callback_ms - r.window_detect_ms) / n);
  stat.addf("Max processing time (ms)", "%.3f", r.window_max_ms);
}

}  // namespace rgbd_lane_detector

#include <pluginlib/class_list_macros.hpp>
PLUGINLIB_EXPORT_CLASS(rgbd_lane_detector::LaneDetectorNodelet, nodelet::Nodelet)
