// Concurrency of the lane detector nodelet: frames, dynamic_reconfigure changes and
// subscribers coming and going, all at once, on the nodelet loaded in this process with a
// multi-threaded callback queue (as in a nodelet manager). Under ThreadSanitizer
// (`make test-sanitize`) any data race between the frame callback, the reconfigure callback
// and the connection callbacks is a report that fails the run; in the normal build the test
// checks that the node keeps answering with finite outputs and that, once the changes stop,
// the last configuration is the one applied (the plane matches the rendered truth).
//
// Private parameters: ~duration (s of concurrent traffic, default 6).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <random>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include <cv_bridge/cv_bridge.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <image_transport/image_transport.h>
#include <nodelet/loader.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <rgbd_lane_detector/LaneDetectorConfig.h>
#include <rgbd_lane_detector/LaneMarkings.h>
#include <rgbd_lane_detector/LanePlane.h>

#include "rgbd_lane_detector/ros/conversions.h"

#include "../core/synthetic_scene.h"

namespace rgbd_lane_detector {
namespace {

using Clock = std::chrono::steady_clock;
const char* const kDetector = "/concurrency_lane_detector";
const char* const kFrame = "camera_color_optical_frame";

bool finite(const LanePlane& m) {
  return std::isfinite(m.left_score) && std::isfinite(m.right_score) &&
         std::isfinite(m.rms_error) && std::isfinite(m.normal.x) && std::isfinite(m.normal.y) &&
         std::isfinite(m.normal.z) && std::isfinite(m.distance);
}

bool finite(const sensor_msgs::PointCloud2& m) {
  if (m.width * m.height == 0) return true;
  for (sensor_msgs::PointCloud2ConstIterator<float> it(m, "x"); it != it.end(); ++it)
    if (!std::isfinite(it[0]) || !std::isfinite(it[1]) || !std::isfinite(it[2])) return false;
  return true;
}

bool finite(const LaneMarkings& m) {
  for (const auto* side : {&m.left, &m.right})
    for (const auto& p : *side)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
  return true;
}

/// Counts the messages of one output and the non-finite ones among them.
struct Counter {
  std::atomic<int> received{0};
  std::atomic<int> non_finite{0};
  template <class M>
  void add(const M& m) {
    ++received;
    if (!finite(m)) ++non_finite;
  }
};

class Concurrency : public ::testing::Test {
 protected:
  void SetUp() override {
    ros::NodeHandle pnh("~");
    pnh.param("duration", duration_, 6.0);
    // The road of the core tests (640x380) with exact plane truth.
    cv::Mat bgr, depth_mm;
    scene_.render(bgr, depth_mm);
    std_msgs::Header h;
    h.frame_id = kFrame;
    colour_ = *cv_bridge::CvImage(h, "bgr8", bgr).toImageMsg();
    depth_ = *cv_bridge::CvImage(h, "16UC1", depth_mm).toImageMsg();
    info_ = conversions::cameraInfoFromIntrinsics(scene_.K, bgr.cols, bgr.rows, h);

    pub_colour_ = nh_.advertise<sensor_msgs::Image>("rgb/image_rect_color", 5);
    pub_depth_ = nh_.advertise<sensor_msgs::Image>("depth_registered/image_rect", 5);
    pub_info_ = nh_.advertise<sensor_msgs::CameraInfo>("rgb/camera_info", 5);

    ros::param::set(std::string(kDetector) + "/mode", "improved");
    ros::param::set(std::string(kDetector) + "/queue_size", 5);
    ros::param::set(std::string(kDetector) + "/diagnostic_period", 0.2);
    const nodelet::M_string remappings;
    const nodelet::V_string argv;
    ASSERT_TRUE(
        loader_.load(kDetector, "rgbd_lane_detector/LaneDetectorNodelet", remappings, argv));
  }

  void TearDown() override {
    loader_.unload(kDetector);
    // unload() returns while a callback of the nodelet may still be running and holding it: the
    // nodelet is then destroyed on that callback's thread, which disconnects its subscriptions
    // from this fixture's publishers. Destroy the publishers only after that: each count is read
    // under the mutex the disconnection takes.
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while ((pub_colour_.getNumSubscribers() > 0 || pub_depth_.getNumSubscribers() > 0 ||
            pub_info_.getNumSubscribers() > 0) &&
           std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_EQ(pub_colour_.getNumSubscribers() + pub_depth_.getNumSubscribers() +
                  pub_info_.getNumSubscribers(),
              0u)
        << "the unloaded nodelet still subscribes the inputs";
  }

  void publishFrame() {
    const ros::Time stamp = ros::Time::now();
    auto colour = boost::make_shared<sensor_msgs::Image>(colour_);
    auto depth = boost::make_shared<sensor_msgs::Image>(depth_);
    auto info = boost::make_shared<sensor_msgs::CameraInfo>(info_);
    colour->header.stamp = depth->header.stamp = info->header.stamp = stamp;
    pub_info_.publish(info);
    pub_depth_.publish(depth);
    pub_colour_.publish(colour);
  }

  /// Full configuration through set_parameters (an empty request returns the current one).
  bool reconfigure(const LaneDetectorConfig* config, LaneDetectorConfig* applied) {
    dynamic_reconfigure::Reconfigure srv;
    if (config) config->__toMessage__(srv.request.config);
    if (!client_.isValid())  // one persistent connection, as rqt_reconfigure keeps
      client_ = nh_.serviceClient<dynamic_reconfigure::Reconfigure>(
          std::string(kDetector) + "/set_parameters", true);
    if (!client_.call(srv)) return false;
    if (applied) applied->__fromMessage__(srv.response.config);
    return true;
  }

  ros::NodeHandle nh_;
  nodelet::Loader loader_{false};
  test::RoadScene scene_;
  sensor_msgs::Image colour_, depth_;
  sensor_msgs::CameraInfo info_;
  ros::Publisher pub_colour_, pub_depth_, pub_info_;
  ros::ServiceClient client_;  // used by one thread at a time
  double duration_ = 6.0;
};

TEST_F(Concurrency, FramesReconfigureAndSubscribersAtOnce) {
  // The plane output stays subscribed throughout: it counts the frames answered.
  Counter plane, points, markings;
  std::mutex last_mutex;
  std::condition_variable last_cv;
  LanePlane::ConstPtr last_plane;
  ros::Subscriber sub_plane =
      nh_.subscribe<LanePlane>("lane_plane", 10, [&](const LanePlane::ConstPtr& m) {
        plane.add(*m);
        {
          std::lock_guard<std::mutex> lock(last_mutex);
          last_plane = m;
        }
        last_cv.notify_all();
      });

  const std::string service = std::string(kDetector) + "/set_parameters";
  ASSERT_TRUE(ros::service::waitForService(service, ros::Duration(60.0)));
  LaneDetectorConfig initial =
      LaneDetectorConfig::__getDefault__();  // (members start uninitialised)
  ASSERT_TRUE(reconfigure(nullptr, &initial));

  std::atomic<bool> stop{false};
  std::atomic<int> frames_sent{0}, reconfigurations{0}, subscription_changes{0};

  // 1. Frames at about 30 Hz.
  std::thread frames([&] {
    while (!stop) {
      publishFrame();
      ++frames_sent;
      std::this_thread::sleep_for(std::chrono::milliseconds(33));
    }
  });

  // 2. Reconfiguration as fast as the service answers: sizes that reallocate buffers and
  // change the templates, thresholds, switches between the paper's and the improved stages.
  std::thread reconfig([&] {
    std::mt19937 rng(7);
    auto pick = [&](std::initializer_list<double> v) { return *(v.begin() + rng() % v.size()); };
    LaneDetectorConfig c = initial;
    while (!stop) {
      c = initial;
      c.template_size = static_cast<int>(pick({16, 24, 32, 48}));
      c.template_line_width = static_cast<int>(pick({4, 8, 10}));
      c.template_angle_deg = pick({30.0, 45.0, 60.0});
      c.normal_window = static_cast<int>(pick({3, 5, 7}));
      c.use_depth = rng() % 4 != 0;
      c.processing_scale = pick({0.5, 0.75, 1.0});
      c.roi_top = pick({0.3, 0.45, 0.55});
      c.tau_c = static_cast<int>(pick({60, 100, 140}));
      c.adaptive_tau_c = rng() % 2 == 0;
      c.track_lanes = rng() % 2 == 0;
      c.fill_depth_holes = static_cast<int>(pick({0, 2}));
      c.plane_fit = static_cast<int>(pick({0, 1}));
      if (reconfigure(&c, nullptr)) ++reconfigurations;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });

  // 3. Other outputs subscribed and unsubscribed (the lazy input subscriptions follow them
  // when the plane subscriber is the only one left, the connection callbacks run meanwhile).
  std::thread churn([&] {
    image_transport::ImageTransport it(nh_);
    const boost::function<void(const sensor_msgs::ImageConstPtr&)> ignore =
        [](const sensor_msgs::ImageConstPtr&) {};
    int i = 0;
    while (!stop) {
      ros::Subscriber s_points, s_markings;
      image_transport::Subscriber s_left, s_debug;
      if (i % 2 == 0)
        s_points = nh_.subscribe<sensor_msgs::PointCloud2>(
            "lane_points", 5, [&](const sensor_msgs::PointCloud2::ConstPtr& m) { points.add(*m); });
      if (i % 3 == 0)
        s_markings = nh_.subscribe<LaneMarkings>(
            "lane_markings", 5, [&](const LaneMarkings::ConstPtr& m) { markings.add(*m); });
      if (i % 4 == 1) s_left = it.subscribe("response/left", 1, ignore);
      if (i % 5 == 2) s_debug = it.subscribe("debug_image", 1, ignore);
      ++subscription_changes;
      ++i;
      std::this_thread::sleep_for(std::chrono::milliseconds(120));
    }
  });

  std::this_thread::sleep_for(std::chrono::duration<double>(duration_));
  stop = true;
  frames.join();
  reconfig.join();
  churn.join();

  std::printf(
      "concurrency: %d frames sent, %d reconfigurations, %d subscription changes, %d planes, "
      "%d point clouds, %d markings\n",
      frames_sent.load(), reconfigurations.load(), subscription_changes.load(),
      plane.received.load(), points.received.load(), markings.received.load());
  EXPECT_GT(reconfigurations.load(), 2);
  EXPECT_GT(plane.received.load(), 0) << "no frame answered while parameters changed";
  EXPECT_EQ(plane.non_finite.load(), 0);
  EXPECT_EQ(points.non_finite.load(), 0);
  EXPECT_EQ(markings.non_finite.load(), 0);

  // Back to the initial configuration: the next answers are the detector's, on that
  // configuration, for the rendered road (plane within 1 degree and 5 cm of the truth).
  LaneDetectorConfig applied = LaneDetectorConfig::__getDefault__();
  ASSERT_TRUE(reconfigure(&initial, &applied));
  EXPECT_EQ(applied.template_size, initial.template_size);
  const ros::Time changed = ros::Time::now();
  const Eigen::Vector3d n_true = scene_.planeNormal();
  bool accurate = false;
  const Clock::time_point end = Clock::now() + std::chrono::seconds(60);
  int settled = 0;
  double angle = -1.0, distance = -1.0;
  while (!accurate && Clock::now() < end && ros::ok()) {
    publishFrame();
    std::unique_lock<std::mutex> lock(last_mutex);
    last_cv.wait_for(lock, std::chrono::milliseconds(200));
    if (!last_plane || last_plane->header.stamp <= changed || !last_plane->valid) continue;
    // The tracker needs a few frames on the restored configuration to settle.
    if (++settled < 5) continue;
    const Eigen::Vector3d n(last_plane->normal.x, last_plane->normal.y, last_plane->normal.z);
    angle = std::acos(std::min(1.0, std::fabs(n.normalized().dot(n_true)))) * 180.0 / M_PI;
    distance = last_plane->distance;
    accurate = angle < 1.0 && std::fabs(distance - scene_.planeDistance()) < 0.05;
  }
  EXPECT_TRUE(accurate) << "no accurate plane after the configuration was restored: " << settled
                        << " valid planes, last " << angle << " deg, distance " << distance
                        << " m (truth " << scene_.planeDistance() << " m)";
}

}  // namespace
}  // namespace rgbd_lane_detector

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_concurrency");
  ros::AsyncSpinner spinner(2);  // this test's own subscriptions and service calls
  spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  return result;
}
