/**
 * @file input_sync.h
 * @brief The nodelet's inputs: colour and depth (image_transport, with the ~image_transport /
 * ~depth_image_transport hints) and camera_info, each through the stamp bookkeeping (jumps back
 * in time, StampJumpDetector) into an ApproximateTime or ExactTime synchroniser. Lazy: the
 * owner subscribes and unsubscribes (under its connect mutex). The entry points colourIn(),
 * depthIn() and infoIn() are what the subscribers call; a gtest feeds them without a roscore.
 * Private to the nodelet library.
 */
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <image_transport/image_transport.h>
#include <image_transport/subscriber_filter.h>
#include <message_filters/pass_through.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "stamp_jump_detector.h"

namespace rgbd_lane_detector {

class InputSynchroniser {
 public:
  using Image = sensor_msgs::Image;
  using CameraInfo = sensor_msgs::CameraInfo;
  using ImageEvent = ros::MessageEvent<const Image>;
  using CameraInfoEvent = ros::MessageEvent<const CameraInfo>;

  /// A jump back in time, once per jump: the owner resets what depends on time.
  struct Jump {
    double seconds_back = 0.0;
    bool log = false;          ///< at most one line a second (a stream going back and forth)
    uint64_t not_logged = 0;   ///< jumps since the last logged one (when log)
    /// The log line; @p tf: whether a tf buffer was cleared too.
    std::string text(bool tf) const;
  };
  struct Callbacks {
    /// Every colour image received (before the bookkeeping: frame accounting).
    std::function<void(const Image&)> colour_received;
    /// Every depth image received (frame accounting: seq gaps).
    std::function<void(const Image&)> depth_received;
    /// Every camera_info received, and the time it waited in the callback queue (ms, receipt to
    /// callback; 0 when the receipt is unknown).
    std::function<void(const CameraInfo&, double)> info_received;
    /// Every camera_info of the current epoch, before its frame can be synchronised.
    std::function<void(const CameraInfo&)> camera_info;
    /// A synchronised set.
    std::function<void(const sensor_msgs::ImageConstPtr&, const sensor_msgs::ImageConstPtr&,
                       const sensor_msgs::CameraInfoConstPtr&)>
        frame;
    /// Stamps went back (after the synchroniser was replaced, before the message passes on).
    std::function<void(const Jump&)> jumped;
    /// A message dropped for a stamp less than StampJumpDetector::kMinJumpNs before its input's
    /// latest (out of order: no jump); @p input names the topic, @p seconds_back how far.
    std::function<void(const char* input, double seconds_back)> out_of_order;
  };

  /// @param max_interval_s ApproximateTime's largest spread of a set's stamps (s; 0: no limit).
  InputSynchroniser(bool approximate, int queue_size, Callbacks callbacks,
                    double max_interval_s = 0.0);
  ~InputSynchroniser();

  /// Subscribe the three inputs (colour and depth with the transports of @p pnh's hints).
  void subscribe(image_transport::ImageTransport& it, ros::NodeHandle& nh, ros::NodeHandle& pnh);
  void unsubscribe();
  bool subscribed() const { return static_cast<bool>(colour_.getSubscriber()); }
  std::string colourTopic() const { return colour_.getTopic(); }

  // The subscribers' callbacks (public for the tests).
  void colourIn(const ImageEvent& event);
  void depthIn(const ImageEvent& event);
  void infoIn(const CameraInfoEvent& event);

 private:
  enum Input : size_t { kColour, kDepth, kInfo, kInputs };
  using ApproximatePolicy =
      message_filters::sync_policies::ApproximateTime<Image, Image, CameraInfo>;
  using ExactPolicy = message_filters::sync_policies::ExactTime<Image, Image, CameraInfo>;

  /// (Re)create the synchroniser on the pass-throughs: empty queues.
  void makeSynchroniser();
  /// @return false for a late message from before the last jump (not to be synchronised)
  bool accept(size_t input, const ros::Time& stamp);

  const bool approximate_;
  const int queue_size_;
  const double max_interval_s_;
  Callbacks callbacks_;
  // declared before the synchronisers, which hold references to them
  image_transport::SubscriberFilter colour_, depth_;
  /// made at the first subscribe(): message_filters::Subscriber holds a NodeHandle
  std::unique_ptr<message_filters::Subscriber<CameraInfo>> info_;
  message_filters::PassThrough<Image> pass_colour_, pass_depth_;
  message_filters::PassThrough<CameraInfo> pass_info_;
  std::unique_ptr<message_filters::Synchronizer<ApproximatePolicy>> approximate_sync_;
  std::unique_ptr<message_filters::Synchronizer<ExactPolicy>> exact_sync_;
  StampJumpDetector jumps_{kInputs};
  ros::WallTime last_jump_log_;  ///< when a jump was last logged
  uint64_t jumps_not_logged_ = 0;
};

/**
 * @brief What is wrong with a configured image transport (empty: nothing): the transport is
 * not among @p loadable ("<package>/<transport>" names, image_transport's), said with the
 * parameter, the loadable ones and the package that provides it.
 */
std::string transportProblem(const std::string& param, const std::string& transport,
                             const std::vector<std::string>& loadable);

/// transportProblem() of ~image_transport and ~depth_image_transport together (empty: none);
/// @p loadable is asked only when a transport is not raw.
std::string missingTransports(const std::string& image_transport,
                              const std::string& depth_image_transport,
                              const std::function<std::vector<std::string>()>& loadable);

}  // namespace rgbd_lane_detector
