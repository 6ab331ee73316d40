#include "input_sync.h"

#include <algorithm>
#include <cstdio>

#include <boost/bind/bind.hpp>

namespace rgbd_lane_detector {
namespace {

/// The package of image_transport_plugins that provides a transport's plugins (null: unknown).
const char* transportPackage(const std::string& transport) {
  if (transport == "compressed") return "compressed_image_transport";
  if (transport == "compressedDepth") return "compressed_depth_image_transport";
  if (transport == "theora") return "theora_image_transport";
  return nullptr;
}

/// Time a message waited between its receipt and its subscriber callback (ms; 0 when the event
/// has no receipt time). Only camera_info's events carry the receipt: image_transport calls the
/// image callbacks with the message alone, and their events are made at the call.
double queueWaitMs(const ros::MessageEvent<const sensor_msgs::CameraInfo>& event) {
  const ros::Time receipt = event.getReceiptTime();
  if (receipt.isZero()) return 0.0;
  return std::max(0.0, (ros::Time::now() - receipt).toSec() * 1e3);
}

}  // namespace

std::string InputSynchroniser::Jump::text(bool tf) const {
  char back[32];
  std::snprintf(back, sizeof(back), "%.3f", seconds_back);
  return std::string("Input stamps went back ") + back +
         " s (rosbag loop or a restarted camera clock?): reset the detector state (lane tracker, "
         "templates, previous plane), the synchroniser queues" + (tf ? " and the tf buffer" : "") +
         (not_logged > 0
              ? " (" + std::to_string(not_logged) + " more jumps since the last line)"
              : std::string());
}

InputSynchroniser::InputSynchroniser(bool approximate, int queue_size, Callbacks callbacks,
                                     double max_interval_s)
    : approximate_(approximate), queue_size_(std::max(1, queue_size)),
      max_interval_s_(std::max(0.0, max_interval_s)), callbacks_(std::move(callbacks)) {
  // subscriber -> bookkeeping -> pass-through -> synchroniser: the pass-throughs let a jump
  // replace the synchroniser from inside a subscriber's callback
  colour_.registerCallback(
      boost::function<void(const ImageEvent&)>([this](const ImageEvent& e) { colourIn(e); }));
  depth_.registerCallback(
      boost::function<void(const ImageEvent&)>([this](const ImageEvent& e) { depthIn(e); }));
  makeSynchroniser();
}

InputSynchroniser::~InputSynchroniser() { unsubscribe(); }

void InputSynchroniser::subscribe(image_transport::ImageTransport& it, ros::NodeHandle& nh,
                                  ros::NodeHandle& pnh) {
  // transport hints from ~image_transport and ~depth_image_transport (e.g. compressedDepth)
  const image_transport::TransportHints colour_hints("raw", ros::TransportHints(), pnh,
                                                     "image_transport");
  const image_transport::TransportHints depth_hints("raw", ros::TransportHints(), pnh,
                                                    "depth_image_transport");
  colour_.subscribe(it, "rgb/image_rect_color", queue_size_, colour_hints);
  depth_.subscribe(it, "depth_registered/image_rect", queue_size_, depth_hints);
  if (!info_) {
    info_.reset(new message_filters::Subscriber<CameraInfo>);
    info_->registerCallback(boost::function<void(const CameraInfoEvent&)>(
        [this](const CameraInfoEvent& e) { infoIn(e); }));
  }
  info_->subscribe(nh, "rgb/camera_info", queue_size_);
}

void InputSynchroniser::unsubscribe() {
  colour_.unsubscribe();
  depth_.unsubscribe();
  if (info_) info_->unsubscribe();
}

void InputSynchroniser::colourIn(const ImageEvent& event) {
  if (callbacks_.colour_received) callbacks_.colour_received(*event.getMessage());
  if (accept(kColour, event.getMessage()->header.stamp)) pass_colour_.add(event);
}

void InputSynchroniser::depthIn(const ImageEvent& event) {
  if (callbacks_.depth_received) callbacks_.depth_received(*event.getMessage());
  if (accept(kDepth, event.getMessage()->header.stamp)) pass_depth_.add(event);
}

void InputSynchroniser::infoIn(const CameraInfoEvent& event) {
  if (callbacks_.info_received) callbacks_.info_received(*event.getMessage(), queueWaitMs(event));
  if (!accept(kInfo, event.getMessage()->header.stamp)) return;
  if (callbacks_.camera_info) callbacks_.camera_info(*event.getMessage());
  pass_info_.add(event);
}

void InputSynchroniser::makeSynchroniser() {
  using namespace boost::placeholders;
  // the old one (if any) is destroyed first: it disconnects from the pass-throughs
  auto frame = [this](const sensor_msgs::ImageConstPtr& colour,
                      const sensor_msgs::ImageConstPtr& depth,
                      const sensor_msgs::CameraInfoConstPtr& info) {
    if (callbacks_.frame) callbacks_.frame(colour, depth, info);
  };
  if (approximate_) {
    approximate_sync_.reset();
    approximate_sync_.reset(new message_filters::Synchronizer<ApproximatePolicy>(
        ApproximatePolicy(queue_size_), pass_colour_, pass_depth_, pass_info_));
    // a depth image from another moment than its colour image is registered to the wrong road
    if (max_interval_s_ > 0.0)
      approximate_sync_->setMaxIntervalDuration(ros::Duration(max_interval_s_));
    approximate_sync_->registerCallback(boost::bind<void>(frame, _1, _2, _3));
  } else {
    exact_sync_.reset();
    exact_sync_.reset(new message_filters::Synchronizer<ExactPolicy>(
        ExactPolicy(queue_size_), pass_colour_, pass_depth_, pass_info_));
    exact_sync_->registerCallback(boost::bind<void>(frame, _1, _2, _3));
  }
}

bool InputSynchroniser::accept(size_t input, const ros::Time& stamp) {
  const StampJumpDetector::Verdict verdict =
      jumps_.update(input, static_cast<int64_t>(stamp.toNSec()));
  if (verdict == StampJumpDetector::Verdict::kStale) return false;  // from before the last jump
  if (verdict == StampJumpDetector::Verdict::kOutOfOrder) {
    static const char* const kNames[kInputs] = {"colour image", "depth image", "camera_info"};
    if (callbacks_.out_of_order)
      callbacks_.out_of_order(kNames[input], static_cast<double>(jumps_.lastOutOfOrderNs()) * 1e-9);
    return false;
  }
  if (verdict == StampJumpDetector::Verdict::kCurrent) return true;
  // Time went back (rosbag loop, a camera clock restarting): the images synchronised from now
  // on are this epoch's only
  makeSynchroniser();
  Jump jump;
  jump.seconds_back = static_cast<double>(jumps_.lastJumpNs()) * 1e-9;
  const ros::WallTime now = ros::WallTime::now();  // wall time: sim time itself went back
  if (now - last_jump_log_ < ros::WallDuration(1.0)) {
    ++jumps_not_logged_;  // a stream going back and forth: at most one line a second
  } else {
    jump.log = true;
    jump.not_logged = jumps_not_logged_;
    last_jump_log_ = now;
    jumps_not_logged_ = 0;
  }
  if (callbacks_.jumped) callbacks_.jumped(jump);
  return true;
}

std::string transportProblem(const std::string& param, const std::string& transport,
                             const std::vector<std::string>& loadable) {
  if (transport == "raw") return "";  // built into image_transport
  const bool found = std::any_of(loadable.begin(), loadable.end(), [&](const std::string& l) {
    return l.size() > transport.size() &&
           l.compare(l.size() - transport.size() - 1, std::string::npos, "/" + transport) == 0;
  });
  if (found) return "";
  std::string names;
  for (const std::string& l : loadable) names += (names.empty() ? "" : ", ") + l;
  std::string problem = "Image transport '" + transport + "' (parameter ~" + param +
                        ") is not installed: image_transport has no '" + transport +
                        "' subscriber plugin here (loadable: " + names + ").";
  if (const char* package = transportPackage(transport))
    problem += std::string(" It is provided by the package ") + package +
               " (ROS Noetic: ros-noetic-image-transport-plugins).";
  return problem + " Install it, or set ~" + param + " to raw.";
}

std::string missingTransports(const std::string& image_transport,
                              const std::string& depth_image_transport,
                              const std::function<std::vector<std::string>()>& loadable) {
  std::string missing;
  std::vector<std::string> names;  // looked up once, if needed
  const std::pair<const char*, const std::string*> params[] = {
      {"image_transport", &image_transport}, {"depth_image_transport", &depth_image_transport}};
  for (const auto& param : params) {
    if (*param.second == "raw") continue;
    if (names.empty()) names = loadable();
    const std::string problem = transportProblem(param.first, *param.second, names);
    if (!problem.empty()) missing += (missing.empty() ? "" : " ") + problem;
  }
  return missing;
}

}  // namespace rgbd_lane_detector
