// DisparityToDepthNodelet: stereo_msgs/DisparityImage (stereo_image_proc, ZED, ...) to the
// depth image the lane detector takes, depth_image_proc style: thin glue around the core's
// disparityToDepth() (Z = f T / d), lazy subscription, throttled errors on bad input.
//
// Subscribes  disparity                     stereo_msgs/DisparityImage
// Publishes   depth_registered/image_rect   sensor_msgs/Image 32FC1 metres, NaN where invalid,
//             registered to the left rectified image (the disparity image's header).
// Parameters  ~queue_size (int, 5)          subscriber queue
#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>

#include <boost/make_shared.hpp>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/image_encodings.h>
#include <stereo_msgs/DisparityImage.h>

#include "rgbd_lane_detector/disparity_depth.h"
#include "rgbd_lane_detector/ros/conversions.h"

namespace rgbd_lane_detector {

class DisparityToDepthNodelet : public nodelet::Nodelet {
 public:
  void onInit() override;

 private:
  void connectCb();
  void disparityCallback(const stereo_msgs::DisparityImageConstPtr& msg);
  /// Whether @p depth has a finite pixel (usually found in its middle row at once).
  static bool anyDepth(const cv::Mat& depth);
  /// A depth image without one: a throttled warning saying why (T's sign, or the range).
  void warnNoDepth(const cv::Mat& disparity, const DisparityModel& model);

  std::shared_ptr<image_transport::ImageTransport> it_;
  std::mutex connect_mutex_;  // guards sub_ against connectCb running while onInit advertises
  ros::Subscriber sub_;
  image_transport::Publisher pub_depth_;
  int queue_size_ = 5;
  cv::Mat swap_buffer_;  // disparities of the other byte order (callbacks are serialised)
};

void DisparityToDepthNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  getPrivateNodeHandle().param("queue_size", queue_size_, 5);
  queue_size_ = std::max(1, queue_size_);
  it_ = std::make_shared<image_transport::ImageTransport>(nh);
  // Advertise under the connect mutex: connectCb may run as soon as the publisher exists.
  const image_transport::SubscriberStatusCallback connect_cb =
      [this](const image_transport::SingleSubscriberPublisher&) { connectCb(); };
  std::lock_guard<std::mutex> lock(connect_mutex_);
  pub_depth_ = it_->advertise("depth_registered/image_rect", 1, connect_cb, connect_cb);
}

// Subscribe to the disparity only while someone wants the depth.
void DisparityToDepthNodelet::connectCb() {
  std::lock_guard<std::mutex> lock(connect_mutex_);
  if (pub_depth_.getNumSubscribers() == 0) {
    sub_.shutdown();
  } else if (!sub_) {
    sub_ = getNodeHandle().subscribe("disparity", queue_size_,
                                     &DisparityToDepthNodelet::disparityCallback, this);
  }
}

void DisparityToDepthNodelet::disparityCallback(const stereo_msgs::DisparityImageConstPtr& msg) {
  cv::Mat disparity;
  DisparityModel model;
  if (const char* problem = conversions::disparityFromMsg(*msg, disparity, model, swap_buffer_)) {
    NODELET_ERROR_THROTTLE(5.0, "Dropping disparity image: %s", problem);
    return;
  }
  // stereo_msgs: the outer header is kept for synchronisers; image.header is the one to use
  const std_msgs::Header& header =
      msg->image.header.frame_id.empty() && msg->image.header.stamp.isZero() ? msg->header
                                                                              : msg->image.header;
  auto depth_msg = boost::make_shared<sensor_msgs::Image>();
  cv::Mat depth = conversions::prepareImage(disparity.rows, disparity.cols, CV_32FC1,
                                            sensor_msgs::image_encodings::TYPE_32FC1, header,
                                            *depth_msg);
  if (const char* problem = disparityToDepth(disparity, model, depth)) {  // checked above
    NODELET_ERROR_THROTTLE(5.0, "Dropping disparity image: %s", problem);
    return;
  }
  if (!anyDepth(depth)) warnNoDepth(disparity, model);
  pub_depth_.publish(depth_msg);
}

// Rows from the middle of the image outward: a pixel with a depth ends the search there at once.
bool DisparityToDepthNodelet::anyDepth(const cv::Mat& depth) {
  for (int i = 0; i < depth.rows; ++i) {
    const int y = depth.rows / 2 + (i % 2 ? -(i + 1) / 2 : i / 2);
    const float* z = depth.ptr<float>(y);
    if (std::any_of(z, z + depth.cols, [](float v) { return !std::isnan(v); })) return true;
  }
  return false;
}

void DisparityToDepthNodelet::warnNoDepth(const cv::Mat& disparity, const DisparityModel& model) {
  const DisparityCounts counts = countDisparities(disparity, model);
  if (counts.wrong_sign > 0)
    NODELET_WARN_THROTTLE(5.0,
                          "No pixel of the disparity image gives a positive depth: f T / d < 0 on "
                          "%d pixels within its valid range (f %.1f, T %.4f m). The sign of T "
                          "does not match the disparities' (d = x_l - x_r > 0 needs T > 0)",
                          counts.wrong_sign, model.focal, model.baseline);
  else
    NODELET_WARN_THROTTLE(5.0,
                          "No pixel of the disparity image is valid (min_disparity %.1f, "
                          "max_disparity %.1f, delta_d %.3f, its valid_window): the depth is NaN "
                          "everywhere",
                          model.min_disparity, model.max_disparity, model.delta_d);
}

}  // namespace rgbd_lane_detector

PLUGINLIB_EXPORT_CLASS(rgbd_lane_detector::DisparityToDepthNodelet, nodelet::Nodelet)
