// FramePlayerNodelet: a driver-like publisher for measuring the way in (issue 23, item 4).
//
// Preloads RGB-D frames (a dataset read with the tools' readers, by default the real RADIATE fog
// drive of ../shared/realdata; a generated road when the data is absent), resized to the
// requested size with the intrinsics scaled, and publishes colour, registered depth and
// camera_info at a fixed rate from a steady timer, as a camera driver does: every frame a freshly
// allocated message filled from the preloaded buffer, stamped now, published as a ConstPtr (a
// nodelet in the same manager receives the same object: zero-copy). It subscribes to the
// detector's output (lane_plane) and measures each frame's latency (now - header.stamp at
// receipt) and which frames never came back; the summary goes to the log (one line starting
// "FramePlayer summary:", key=value pairs) and to the latched topic ~summary
// (diagnostic_msgs/DiagnosticStatus, the same keys). Parameters: tools/README.md, "FramePlayerNodelet".
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include <boost/make_shared.hpp>
#include <diagnostic_msgs/DiagnosticStatus.h>
#include <geometry_msgs/TransformStamped.h>
#include <nodelet/nodelet.h>
#include <opencv2/imgproc.hpp>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "frame_stats.h"
#include "rgbd_lane_detector/LanePlane.h"
#include "frame_source.h"
#include "rgbd_lane_detector/ros/conversions.h"

namespace rgbd_lane_detector {
namespace tools {

namespace {

/// One preloaded frame, already in its published encodings.
struct Preloaded {
  cv::Mat colour;  ///< CV_8UC3 in colour_encoding's channel order
  cv::Mat depth;   ///< CV_16UC1 mm or CV_32FC1 m
};

}  // namespace

class FramePlayerNodelet : public nodelet::Nodelet {
 public:
  ~FramePlayerNodelet() override {
    timer_.stop();
    drain_timer_.stop();
    finish("shutdown");
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    pnh.param<std::string>("dataset", dataset_, "");
    pnh.param<std::string>("dataset_type", dataset_type_, "auto");
    pnh.param<std::string>("frame_filter", frame_filter_, "");
    pnh.param("frames", max_frames_, 30);
    pnh.param("width", width_, 1920);
    pnh.param("height", height_, 1080);
    pnh.param("rate", rate_, 30.0);
    pnh.param<std::string>("colour_encoding", colour_encoding_, "rgb8");
    pnh.param<std::string>("depth_encoding", depth_encoding_, "16UC1");
    pnh.param<std::string>("frame_id", frame_id_, "camera_color_optical_frame");
    pnh.param("duration", duration_, 0.0);
    pnh.param("count", count_, 0);
    pnh.param("warmup", warmup_, 2.0);
    pnh.param("drain_timeout", drain_timeout_, 2.0);
    pnh.param("lockstep", lockstep_, false);
    pnh.param("lockstep_timeout", lockstep_timeout_, 10.0);
    pnh.param("publish_tf", publish_tf_, false);
    pnh.param("wait_for_output", wait_for_output_, true);
    pnh.param<std::string>("tf_parent", tf_parent_, "base_link");
    pnh.param("camera_height", camera_height_, 1.5);
    pnh.param("queue_size", queue_size_, 5);
    pnh.param("output_queue_size", output_queue_size_, 100);
    rate_ = std::max(0.1, rate_);
    max_frames_ = std::max(1, max_frames_);
    if (colour_encoding_ != "rgb8" && colour_encoding_ != "bgr8") {
      NODELET_ERROR("colour_encoding '%s' unsupported (rgb8, bgr8): using rgb8",
                    colour_encoding_.c_str());
      colour_encoding_ = "rgb8";
    }
    if (depth_encoding_ != "16UC1" && depth_encoding_ != "32FC1") {
      NODELET_ERROR("depth_encoding '%s' unsupported (16UC1, 32FC1): using 16UC1",
                    depth_encoding_.c_str());
      depth_encoding_ = "16UC1";
    }

    const auto t0 = std::chrono::steady_clock::now();
    preload();
    NODELET_INFO("FramePlayer: %zu frames of %s preloaded at %dx%d (%s, %s) in %.1f s; %.1f Hz%s",
                 frames_.size(), source_.c_str(), width_, height_, colour_encoding_.c_str(),
                 depth_encoding_.c_str(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                 rate_, lockstep_ ? ", lockstep" : "");
    info_ = makeCameraInfo();

    if (publish_tf_) {
      // a driver set-up's static mount (robot_state_publisher): base_link -> optical frame,
      // camera level at camera_height (optical z forward = base x, optical x = -base y)
      tf_broadcaster_.reset(new tf2_ros::StaticTransformBroadcaster());
      geometry_msgs::TransformStamped t;
      t.header.stamp = ros::Time::now();
      t.header.frame_id = tf_parent_;
      t.child_frame_id = frame_id_;
      t.transform.translation.z = camera_height_;
      t.transform.rotation.x = -0.5;
      t.transform.rotation.y = 0.5;
      t.transform.rotation.z = -0.5;
      t.transform.rotation.w = 0.5;
      tf_broadcaster_->sendTransform(t);
    }

    const size_t expected =
        static_cast<size_t>((duration_ > 0 ? duration_ + warmup_ : 60.0) * rate_) + count_ + 64;
    stats_ = FrameStats(expected);
    pub_colour_ = nh.advertise<sensor_msgs::Image>("rgb/image_rect_color", queue_size_);
    pub_depth_ = nh.advertise<sensor_msgs::Image>("depth_registered/image_rect", queue_size_);
    pub_info_ = nh.advertise<sensor_msgs::CameraInfo>("rgb/camera_info", queue_size_);
    pub_summary_ = pnh.advertise<diagnostic_msgs::DiagnosticStatus>("summary", 1, true);
    // outputs on the multi-threaded handle: measured while the timer publishes
    sub_output_ = getMTNodeHandle().subscribe("lane_plane", output_queue_size_,
                                              &FramePlayerNodelet::outputCallback, this);
    timer_ = nh.createSteadyTimer(ros::WallDuration(1.0 / rate_), &FramePlayerNodelet::tick,
                                  this);
  }

  // Frames of the source in the published encodings (converted once, here).
  void preload() {
    FrameSourceOptions o;
    o.dataset = dataset_;
    o.type = dataset_type_;
    o.filter = frame_filter_;
    o.max_frames = max_frames_;
    o.width = width_;
    o.height = height_;
    std::vector<DatasetFrame> frames;
    std::string warning;
    loadFrameSource(o, frames, source_, warning);
    if (!warning.empty())
      NODELET_WARN("FramePlayer: %s: publishing %s", warning.c_str(), source_.c_str());
    const bool want_rgb = colour_encoding_ == "rgb8";
    for (const DatasetFrame& f : frames) {
      Preloaded p;
      if ((f.format == PixelFormat::kRgb8) != want_rgb)
        cv::cvtColor(f.colour, p.colour, cv::COLOR_BGR2RGB);  // the swap is its own inverse
      else
        p.colour = f.colour;
      if (depth_encoding_ == "16UC1") {
        cv::Mat mm = f.depth * 1000.0;  // metres, NaN invalid
        mm.setTo(0, mm != mm);
        mm.convertTo(p.depth, CV_16UC1);  // saturates beyond 65.535 m
      } else {
        p.depth = f.depth;
      }
      frames_.push_back(std::move(p));
    }
    K_ = frames.front().intrinsics;
    width_ = frames.front().colour.cols;
    height_ = frames.front().colour.rows;
  }

  sensor_msgs::CameraInfo makeCameraInfo() const {
    std_msgs::Header header;
    header.frame_id = frame_id_;
    return conversions::cameraInfoFromIntrinsics(K_, width_, height_, header);
  }

  static boost::shared_ptr<sensor_msgs::Image> fill(const cv::Mat& m, const std::string& encoding,
                                                    const std_msgs::Header& header) {
    auto msg = boost::make_shared<sensor_msgs::Image>();
    msg->header = header;
    msg->height = static_cast<uint32_t>(m.rows);
    msg->width = static_cast<uint32_t>(m.cols);
    msg->encoding = encoding;
    msg->is_bigendian = 0;
    msg->step = static_cast<uint32_t>(m.cols * m.elemSize());
    const size_t bytes = static_cast<size_t>(msg->step) * m.rows;
    // one allocation and one copy, as a driver copying its device buffer
    msg->data.assign(m.data, m.data + bytes);  // the preloaded images are continuous
    return msg;
  }

  bool inputsConnected() const {
    return pub_colour_.getNumSubscribers() > 0 && pub_depth_.getNumSubscribers() > 0 &&
           pub_info_.getNumSubscribers() > 0 &&
           (!wait_for_output_ || sub_output_.getNumPublishers() > 0);
  }

  void tick(const ros::SteadyTimerEvent& event) {
    if (stopped_) return;
    const ros::SteadyTime now_steady = event.current_real;
    if (!started_) {
      // a driver streams whether or not someone listens; the measurement starts when the
      // detector is subscribed (it subscribes lazily, once its output has a subscriber)
      if (!inputsConnected()) return;
      started_ = true;
      start_ = now_steady;
      NODELET_INFO("FramePlayer: the detector is subscribed; %.1f s warm-up, then measuring",
                   warmup_);
    }
    const double elapsed = (now_steady - start_).toSec();
    const bool warmup = elapsed < warmup_;
    if (!warmup && !measuring_) {
      measuring_ = true;
      measure_start_ = now_steady;
    }
    if (measuring_ &&
        ((duration_ > 0 && (now_steady - measure_start_).toSec() >= duration_) ||
         (count_ > 0 && measured_published_ >= count_))) {
      stopPublishing();
      return;
    }
    if (lockstep_) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!stats_.allBack() && (now_steady - last_publish_).toSec() < lockstep_timeout_) return;
    }
    // a late tick: the timer fired later than a period after its expected time
    const double late = (event.current_real - event.current_expected).toSec();
    if (late > 1.0 / rate_) ++late_ticks_;
    max_late_ms_ = std::max(max_late_ms_, late * 1e3);

    const Preloaded& p = frames_[next_frame_];
    next_frame_ = (next_frame_ + 1) % frames_.size();
    std_msgs::Header header;
    header.frame_id = frame_id_;
    header.seq = seq_++;  // roscpp numbers seq only in serialised messages: intra-process too
    header.stamp = ros::Time::now();
    auto colour = fill(p.colour, colour_encoding_, header);
    auto depth = fill(p.depth, depth_encoding_, header);
    auto info = boost::make_shared<sensor_msgs::CameraInfo>(info_);
    info->header = header;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stats_.published(static_cast<int64_t>(header.stamp.toNSec()), warmup);
    }
    if (!warmup) ++measured_published_;
    last_publish_ = now_steady;
    pub_colour_.publish(sensor_msgs::ImageConstPtr(colour));
    pub_depth_.publish(sensor_msgs::ImageConstPtr(depth));
    pub_info_.publish(sensor_msgs::CameraInfoConstPtr(info));
  }

  void outputCallback(const rgbd_lane_detector::LanePlaneConstPtr& msg) {
    const ros::Time now = ros::Time::now();
    const double latency_ms = (now - msg->header.stamp).toSec() * 1e3;
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.output(static_cast<int64_t>(msg->header.stamp.toNSec()), latency_ms);
  }

  void stopPublishing() {
    stopped_ = true;
    timer_.stop();
    measured_seconds_ = (ros::SteadyTime::now() - measure_start_).toSec();
    drain_start_ = ros::SteadyTime::now();
    drain_timer_ = getNodeHandle().createSteadyTimer(
        ros::WallDuration(0.02), [this](const ros::SteadyTimerEvent&) {
          bool back;
          {
            std::lock_guard<std::mutex> lock(mutex_);
            back = stats_.allBack();
          }
          if (back || (ros::SteadyTime::now() - drain_start_).toSec() >= drain_timeout_) {
            drain_timer_.stop();
            finish(back ? "done" : "done (drain timeout)");
          }
        });
  }

  void finish(const char* why) {
    if (finished_.exchange(true)) return;
    FrameSummary s;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      s = stats_.summary();
    }
    if (!stopped_ && measuring_) measured_seconds_ = (ros::SteadyTime::now() - measure_start_).toSec();
    const double rate_measured =
        measured_seconds_ > 0 ? static_cast<double>(s.published) / measured_seconds_ : 0.0;
    const std::vector<std::pair<std::string, std::string>> kv = {
        {"size", std::to_string(width_) + "x" + std::to_string(height_)},
        {"rate", num(rate_)},
        {"published", std::to_string(s.published)},
        {"outputs", std::to_string(s.outputs)},
        {"lost", std::to_string(s.lost)},
        {"duplicates", std::to_string(s.duplicates)},
        {"unknown", std::to_string(s.unknown)},
        {"warmup_published", std::to_string(s.warmup_published)},
        {"warmup_lost", std::to_string(s.warmup_published - s.warmup_outputs)},
        {"latency_mean_ms", num(s.mean_ms)},
        {"latency_p50_ms", num(s.p50_ms)},
        {"latency_p99_ms", num(s.p99_ms)},
        {"latency_max_ms", num(s.max_ms)},
        {"measured_s", num(measured_seconds_)},
        {"published_rate", num(rate_measured)},
        {"late_ticks", std::to_string(late_ticks_)},
        {"max_tick_late_ms", num(max_late_ms_)},
        {"lockstep", lockstep_ ? "true" : "false"},
        {"end", why},
    };
    std::ostringstream line;
    diagnostic_msgs::DiagnosticStatus st;
    st.name = getName();
    st.level = s.lost == 0 ? diagnostic_msgs::DiagnosticStatus::OK
                           : diagnostic_msgs::DiagnosticStatus::WARN;
    st.message = std::to_string(s.lost) + " of " + std::to_string(s.published) + " frames lost";
    for (const auto& [k, v] : kv) {
      line << " " << k << "=" << v;
      diagnostic_msgs::KeyValue e;
      e.key = k;
      e.value = v;
      st.values.push_back(e);
    }
    NODELET_INFO("FramePlayer summary:%s", line.str().c_str());
    if (pub_summary_) pub_summary_.publish(st);
  }

  static std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.3f", v);
    return buf;
  }

  // parameters
  std::string dataset_, dataset_type_, frame_filter_, colour_encoding_, depth_encoding_, frame_id_,
      tf_parent_;
  int max_frames_ = 30, width_ = 1920, height_ = 1080, count_ = 0, queue_size_ = 5,
      output_queue_size_ = 100;
  double rate_ = 30.0, duration_ = 0.0, warmup_ = 2.0, drain_timeout_ = 2.0,
         lockstep_timeout_ = 10.0, camera_height_ = 1.5;
  bool lockstep_ = false, publish_tf_ = false, wait_for_output_ = true;

  std::vector<Preloaded> frames_;
  std::string source_;
  Intrinsics K_;
  sensor_msgs::CameraInfo info_;
  ros::Publisher pub_colour_, pub_depth_, pub_info_, pub_summary_;
  ros::Subscriber sub_output_;
  ros::SteadyTimer timer_, drain_timer_;
  std::unique_ptr<tf2_ros::StaticTransformBroadcaster> tf_broadcaster_;

  // timer thread (the nodelet's single-threaded queue)
  size_t next_frame_ = 0;
  uint32_t seq_ = 0;
  bool started_ = false, measuring_ = false;
  std::atomic<bool> stopped_{false};
  ros::SteadyTime start_, measure_start_, last_publish_, drain_start_;
  int64_t measured_published_ = 0, late_ticks_ = 0;
  double max_late_ms_ = 0.0, measured_seconds_ = 0.0;

  std::mutex mutex_;  // stats_ (timer thread and output callbacks)
  FrameStats stats_;
  std::atomic<bool> finished_{false};
};

}  // namespace tools
}  // namespace rgbd_lane_detector

PLUGINLIB_EXPORT_CLASS(rgbd_lane_detector::tools::FramePlayerNodelet, nodelet::Nodelet)
