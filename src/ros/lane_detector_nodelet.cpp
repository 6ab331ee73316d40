// The lane detector nodelet: thin glue over one-job classes (docs/NODELET.md). InputSynchroniser
// (inputs) -> FrameProcessor (detector) with FrameTransforms (tf, never waiting) -> LaneOutputs
// (lazy publishers); NodeDiagnostics (frame accounting), DetectorReconfigure, NodeParams.
#include <chrono>
#include <memory>
#include <mutex>
#include <stdexcept>

#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "detector_config.h"
#include "frame_processor.h"
#include "frame_transforms.h"
#include "input_sync.h"
#include "lane_outputs.h"
#include "node_diagnostics.h"
#include "node_params.h"
#include "rgbd_lane_detector/ros/conversions.h"

namespace rgbd_lane_detector {

constexpr double kThrottle = 5.0;  // s between repeated per-frame warnings / errors

class LaneDetectorNodelet : public nodelet::Nodelet {
 public:
  ~LaneDetectorNodelet() override {
    if (diagnostics_) diagnostics_->stop();  // its timer first; then no input callback
    std::lock_guard<std::mutex> lock(connect_mutex_);
    if (inputs_) inputs_->unsubscribe();
  }

 private:
  using Image = sensor_msgs::Image;
  using CameraInfo = sensor_msgs::CameraInfo;
  using Lookup = FrameTransforms::Lookup;

  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    params_ = NodeParams::read(pnh);
    it_ = std::make_shared<image_transport::ImageTransport>(nh);
    // a configured transport whose plugin is missing fails the load here, naming it (else the
    // first output subscriber would make the nodelet subscribe and fail silently)
    const std::string missing =
        missingTransports(params_.image_transport, params_.depth_image_transport,
                          [this] { return it_->getLoadableTransports(); });
    if (!missing.empty()) {
      NODELET_FATAL("%s", missing.c_str());
      throw std::runtime_error(missing);  // the manager (or lane_detector_node) refuses us
    }
    const FrameTransforms::Frames frames = FrameTransforms::framesOf(params_);
    if (FrameTransforms::needsTf(frames)) {
      tf_buffer_.reset(new tf2_ros::Buffer);
      tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_));
    }
    transforms_.reset(new FrameTransforms(frames, tf_buffer_.get()));

    // detector parameters: the mode preset for those not given, then dynamic_reconfigure
    const ModePreset preset = applyModePreset(pnh, params_.mode);
    if (!preset.known)
      NODELET_ERROR("Unknown mode '%s' (expected improved or paper): improved", params_.mode.c_str());
    if (!preset.invalid.empty())
      NODELET_ERROR("Parameters whose value is none of theirs (the mode's value is used):%s",
                    preset.invalid.c_str());
    NODELET_INFO("%s", preset.text().c_str());
    reconfigure_.reset(new DetectorReconfigure(pnh, [this](const Params& p, int unmapped) {
      if (unmapped != 0)
        NODELET_ERROR_ONCE("Some dynamic_reconfigure parameters have no core Params field (cfg "
                           "and params_io.h disagree): they are ignored");
      processor_.setParams(p);
    }));
    processor_.applyParams(nullptr);  // the initial parameters, before any frame
    processor_.setMaxFrameGap(params_.max_frame_gap);

    diagnostics_.reset(new NodeDiagnostics(nh, pnh, getName(), params_, [this] {
      std::lock_guard<std::mutex> lock(connect_mutex_);
      return inputs_->subscribed();
    }));
    InputSynchroniser::Callbacks in;
    in.colour_received = [this](const Image& colour) { diagnostics_->received(colour); };
    in.depth_received = [this](const Image& depth) {
      diagnostics_->accounting().depthReceived(depth.header.seq);
    };
    in.info_received = [this](const CameraInfo& info, double wait_ms) {
      diagnostics_->accounting().cameraInfoReceived(info.header.seq, wait_ms);
    };
    in.camera_info = [this](const CameraInfo& info) { prepare(info); };
    in.frame = [this](const sensor_msgs::ImageConstPtr& colour,
                      const sensor_msgs::ImageConstPtr& depth,
                      const sensor_msgs::CameraInfoConstPtr& info) {
      const NodeDiagnostics::CallbackStart start = NodeDiagnostics::CallbackStart::now();
      const char* detail = nullptr;
      const FrameOutcome outcome = processFrame(*colour, *depth, *info, detail);
      diagnostics_->synchronised(*colour, outcome, detail, start, processor_.result().timings.total);
    };
    in.jumped = [this](const InputSynchroniser::Jump& jump) {
      processor_.reset();    // lane tracker, lane model, adapted templates, previous plane
      transforms_->reset();  // odometry start, the tf buffer's dynamic transforms
      if (jump.log) NODELET_WARN("%s", jump.text(tf_buffer_ != nullptr).c_str());
    };
    in.out_of_order = [this](const char* input, double seconds_back) {
      NODELET_WARN_THROTTLE(kThrottle,
                            "Dropping a %s stamped %.3f s before the one received before it "
                            "(out of order; a step back of %.1f s or more restarts tracking)",
                            input, seconds_back, StampJumpDetector::kMinJumpNs * 1e-9);
    };
    inputs_.reset(new InputSynchroniser(params_.approximate_sync, params_.queue_size, in,
                                        params_.max_sync_interval));

    // Advertise under the connect mutex so that connectCb, which may run as soon as the first
    // publisher exists, never sees the others half-assigned (as image_proc does).
    std::lock_guard<std::mutex> lock(connect_mutex_);
    outputs_.setMarkerLifetime(params_.max_frame_gap);  // as long as the lane is kept unseen
    outputs_.advertise(nh, *it_, [this] { connectCb(); });
    NODELET_INFO("Lane detector ready (%s sync, output frame: %s, up axis: %s)",
                 params_.approximate_sync ? "approximate" : "exact",
                 params_.target_frame.empty() ? "colour optical frame" : params_.target_frame.c_str(),
                 params_.up_frame.empty() ? "camera -y" : ("+z of " + params_.up_frame).c_str());
  }

  /// Subscribe to the inputs when any output has a subscriber, unsubscribe when none has.
  void connectCb() {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    if (!outputs_.wanted().any()) {
      NODELET_DEBUG("No subscribers: unsubscribing from the inputs");
      inputs_->unsubscribe();
    } else if (!inputs_->subscribed()) {
      NODELET_DEBUG("Subscribing to the inputs");
      // after a pause the tracked lane is another road's (the vehicle drove on unseen): the
      // lane tracker and model start again, as after a jump back in time
      processor_.reset();
      inputs_->subscribe(*it_, getNodeHandle(), getPrivateNodeHandle());
      diagnostics_->accounting().restartSequence();  // gaps while unsubscribed are not losses
    }
  }

  /// Every camera_info, before its frame can be synchronised: a new camera prepares the detector.
  void prepare(const CameraInfo& info) {
    FrameProcessor::Preparation p;
    if (!processor_.prepare(info, inputs_->colourTopic(), p)) {
      if (!p.error.empty())
        NODELET_ERROR_THROTTLE(kThrottle, "Preparing the detector for a %ux%u camera failed: %s",
                               info.width, info.height, p.error.c_str());
      return;
    }
    if (!p.warning.empty()) NODELET_WARN("%s", p.warning.c_str());
    NODELET_INFO("Detector prepared for %dx%d frames in %.1f ms (fx %.3f, fy %.3f, cx %.3f, cy %.3f)",
                 p.size.width, p.size.height, p.ms, p.K.fx, p.K.fy, p.K.cx, p.K.cy);
  }

  /// One synchronised set: its fate, with @p detail naming a drop's problem (static text).
  FrameOutcome processFrame(const Image& colour, const Image& depth, const CameraInfo& info,
                            const char*& detail) {
    const Wanted wanted = outputs_.wanted();
    if (!wanted.any()) return FrameOutcome::kSkipped;  // the last subscriber left meanwhile
    // the optical frame: tf2 names frames without a leading '/' (and warns at every lookup of
    // one with it), and a frame without a name has no transform and no road frame under it
    std_msgs::Header image = colour.header;
    image.frame_id = conversions::tfFrameId(colour.header.frame_id);
    const std::string& optical = image.frame_id;
    if (optical.empty())
      return drop(FrameOutcome::kBadMessage,
                  "the colour image has no header.frame_id (the optical frame of the outputs)",
                  colour, depth);
    LaneOutputs::Headers h{image, image, image};
    const std::string depth_frame = conversions::tfFrameId(depth.header.frame_id);
    if (!depth_frame.empty() && depth_frame != optical)
      NODELET_WARN_ONCE("The depth image is in frame '%s', the colour image in '%s': the depth "
                        "must be registered to the colour camera, pixel for pixel "
                        "(depth_image_proc/register, or the driver's aligned depth)",
                        depth_frame.c_str(), optical.c_str());
    std::string why;
    Eigen::Vector3d up;
    const bool use_up = !params_.up_frame.empty();
    if (use_up && !transforms_->upAxis(h.image.frame_id, up, why)) {
      NODELET_WARN_THROTTLE(kThrottle, "Skipping frame: %s", why.c_str());
      return FrameOutcome::kNoUpTransform;
    }
    processor_.applyParams(use_up ? &up : nullptr);
    Frame frame;
    FrameOutcome outcome = processor_.load(colour, depth, info, frame, detail);
    if (outcome != FrameOutcome::kProcessed) return drop(outcome, detail, colour, depth);
    Eigen::Isometry3d T;
    const Lookup output = transforms_->outputTransform(h.image, T, h.out.frame_id, why);
    if (output == Lookup::kMissing) {
      NODELET_WARN_THROTTLE(kThrottle, "Skipping frame: %s", why.c_str());
      return FrameOutcome::kNoTargetTransform;
    }
    if (output == Lookup::kLatest) NODELET_WARN_THROTTLE(kThrottle, "%s", why.c_str());
    FrameTransforms::Vehicle vehicle;
    transforms_->vehicleFrame(h.image, processor_.params().lane_model, vehicle);
    if (!vehicle.warning.empty()) NODELET_WARN_THROTTLE(kThrottle, "%s", vehicle.warning.c_str());
    if (!vehicle.motion_warning.empty())
      NODELET_WARN_THROTTLE(kThrottle, "%s", vehicle.motion_warning.c_str());
    vehicle.applyTo(frame, h.model);

    outcome = processor_.detect(frame, static_cast<int64_t>(h.image.stamp.toNSec()),
                                vehicle.has_motion ? &vehicle.motion : nullptr, wanted.geometric,
                                detail);
    if (processor_.restartGap() > 0.0)
      NODELET_WARN_THROTTLE(kThrottle,
                            "No frame was detected for %.1f s (more than ~max_frame_gap, %.1f s): "
                            "the lane tracker and the lane model start again (a stream slower "
                            "than 1 / max_frame_gap needs a larger one; 0 keeps them over any gap)",
                            processor_.restartGap(), params_.max_frame_gap);
    if (outcome == FrameOutcome::kDetectorException) {
      NODELET_ERROR_THROTTLE(kThrottle, "Dropping frame: detector failed: %s",
                             processor_.exceptionText().c_str());
      return outcome;
    }
    if (outcome != FrameOutcome::kProcessed) return drop(outcome, detail, colour, depth);
    if (processor_.firstFrameAfterPrepare())  // measured by measure_nodelet.sh
      NODELET_INFO("First frame after prepare: detect() %.2f ms", processor_.result().timings.total);
    outputs_.publish(wanted, frame, processor_.result(), processor_.params(), h, T, vehicle.found);
    diagnostics_->tick(h.image.stamp);
    return FrameOutcome::kProcessed;
  }

  /// Bad input: a throttled error naming the problem; the frame is dropped.
  FrameOutcome drop(FrameOutcome outcome, const char* problem, const Image& colour,
                    const Image& depth) {
    NODELET_ERROR_THROTTLE(kThrottle, "Dropping frame: %s [colour %s %ux%u, depth %s %ux%u]",
                           problem, colour.encoding.c_str(), colour.width, colour.height,
                           depth.encoding.c_str(), depth.width, depth.height);
    return outcome;
  }

  // declared in the order they may be used in: destroyed the other way round
  NodeParams params_;
  std::shared_ptr<image_transport::ImageTransport> it_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<FrameTransforms> transforms_;
  FrameProcessor processor_;  ///< frame callbacks (serialised on the nodelet's queue) + setParams
  std::unique_ptr<DetectorReconfigure> reconfigure_;
  LaneOutputs outputs_;
  std::mutex connect_mutex_;  ///< the inputs' subscription vs connection callbacks
  std::unique_ptr<NodeDiagnostics> diagnostics_;
  std::unique_ptr<InputSynchroniser> inputs_;
};

}  // namespace rgbd_lane_detector

#include <pluginlib/class_list_macros.hpp>
PLUGINLIB_EXPORT_CLASS(rgbd_lane_detector::LaneDetectorNodelet, nodelet::Nodelet)
