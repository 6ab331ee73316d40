// demo_probe: times the detector graph from the outside, on one host and one clock.
//
// Latency of a frame = wall time at which this node receives the lane_plane output with
// stamp S - wall time at which it received the input colour image with stamp S (the nodelet
// copies the input stamp to every output). Both times come from this process's steady clock,
// so clocks never need to agree across processes and sim time (rosbag play --clock) does not
// matter. The two subscriptions use TCP_NODELAY and their own callback queue and thread, so
// neither Nagle's algorithm nor the overlay encoding below delays a timestamp.
//
// Optionally writes every debug_image overlay to an MJPG video and every N-th one as PNG.
//
// Private parameters:
//   ~latency_csv (string, required) file of "in|out,<stamp ns>,<wall s>,<plane valid>" lines
//   ~video       (string, "")  MJPG .avi of debug_image ("" = do not subscribe to it)
//   ~images_dir  (string, "")  folder of PNG overlays ("" = none)
//   ~image_every (int, 30)     write every N-th overlay as PNG
//   ~video_fps   (double, 10)  frame rate written into the video
#include <chrono>
#include <cstdio>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>

#include <rgbd_lane_detector/LanePlane.h>

namespace {

double wallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

class Probe {
 public:
  explicit Probe(std::FILE* csv) : csv_(csv) {}

  void inputCallback(const sensor_msgs::ImageConstPtr& msg) {
    const double t = wallSeconds();
    std::fprintf(csv_, "in,%lu,%.6f,\n", static_cast<unsigned long>(msg->header.stamp.toNSec()), t);
    ++inputs_;
  }

  void planeCallback(const rgbd_lane_detector::LanePlaneConstPtr& msg) {
    const double t = wallSeconds();
    std::fprintf(csv_, "out,%lu,%.6f,%d\n", static_cast<unsigned long>(msg->header.stamp.toNSec()), t,
                 msg->valid ? 1 : 0);
    ++outputs_;
  }

  void debugCallback(const sensor_msgs::ImageConstPtr& msg) {
    if (msg->encoding != "bgr8") {
      ROS_WARN_THROTTLE(5.0, "demo_probe: debug_image is %s, expected bgr8: skipped", msg->encoding.c_str());
      return;
    }
    const cv::Mat image(static_cast<int>(msg->height), static_cast<int>(msg->width), CV_8UC3,
                        const_cast<uint8_t*>(msg->data.data()), msg->step);
    if (!video_path_.empty()) {
      if (!video_.isOpened() && !video_failed_) {
        video_.open(video_path_, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), video_fps_, image.size());
        video_failed_ = !video_.isOpened();
        if (video_failed_) ROS_WARN("demo_probe: cannot open video %s", video_path_.c_str());
      }
      if (video_.isOpened()) video_.write(image);
    }
    if (!images_dir_.empty() && image_every_ > 0 && overlays_ % image_every_ == 0) {
      char name[32];
      std::snprintf(name, sizeof(name), "/overlay_%04d.png", overlays_);
      cv::imwrite(images_dir_ + name, image);
    }
    ++overlays_;
  }

  void finish() {
    video_.release();
    std::fflush(csv_);
  }

  std::string video_path_, images_dir_;
  int image_every_ = 30;
  double video_fps_ = 10.0;
  int inputs_ = 0, outputs_ = 0, overlays_ = 0;

 private:
  std::FILE* csv_;
  cv::VideoWriter video_;
  bool video_failed_ = false;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "demo_probe");
  ros::NodeHandle nh, pnh("~");
  std::string csv_path;
  pnh.param<std::string>("latency_csv", csv_path, "");
  if (csv_path.empty()) {
    ROS_FATAL("demo_probe: ~latency_csv is required");
    return 2;
  }
  std::FILE* csv = std::fopen(csv_path.c_str(), "w");
  if (!csv) {
    ROS_FATAL("demo_probe: cannot write %s", csv_path.c_str());
    return 1;
  }
  std::setvbuf(csv, nullptr, _IOLBF, 0);  // line buffered: a killed probe loses nothing
  std::fprintf(csv, "# kind,stamp_ns,wall_s,plane_valid\n");

  Probe probe(csv);
  pnh.param<std::string>("video", probe.video_path_, "");
  pnh.param<std::string>("images_dir", probe.images_dir_, "");
  pnh.param("image_every", probe.image_every_, 30);
  pnh.param("video_fps", probe.video_fps_, 10.0);

  // Timing: own queue and thread, TCP_NODELAY (small lane_plane messages must not wait).
  ros::CallbackQueue timing_queue;
  ros::NodeHandle timing_nh(nh);
  timing_nh.setCallbackQueue(&timing_queue);
  const ros::TransportHints no_delay = ros::TransportHints().tcpNoDelay();
  ros::Subscriber sub_in =
      timing_nh.subscribe("rgb/image_rect_color", 100, &Probe::inputCallback, &probe, no_delay);
  ros::Subscriber sub_out = timing_nh.subscribe("lane_plane", 100, &Probe::planeCallback, &probe, no_delay);
  ros::AsyncSpinner timing_spinner(1, &timing_queue);
  timing_spinner.start();

  // Overlays on the global queue (video encoding must not delay the timing thread).
  ros::Subscriber sub_debug;
  if (!probe.video_path_.empty() || !probe.images_dir_.empty())
    sub_debug = nh.subscribe("debug_image", 10, &Probe::debugCallback, &probe);

  ros::spin();
  timing_spinner.stop();
  probe.finish();
  std::fclose(csv);
  std::fprintf(stderr, "demo_probe: %d input frames, %d lane_plane outputs, %d overlays\n", probe.inputs_,
               probe.outputs_, probe.overlays_);
  return 0;
}
