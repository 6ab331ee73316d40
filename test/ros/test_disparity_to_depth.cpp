// rostests of the stereo path.
//  DisparityToDepth.* (disparity_to_depth.test): the nodelet alone, fed stereo_msgs/DisparityImage
//    messages with analytic expectations (Z = f T / d, NaN for invalid pixels), laziness, and bad
//    input that must not stop it.
//  StereoChain.* (stereo_chain.test): launch/stereo.launch as shipped (stereo_image_proc's
//    disparity, DisparityToDepthNodelet and the lane detector in one manager), fed a rectified
//    colour pair of a textured wall at a known disparity.
// Every wait is on a condition with a timeout, never a fixed sleep.
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <functional>
#include <limits>
#include <mutex>
#include <vector>

#include <gtest/gtest.h>

#include <rgbd_lane_detector/LanePlane.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <stereo_msgs/DisparityImage.h>
#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector/ros/conversions.h"

namespace rgbd_lane_detector {
namespace {

namespace enc = sensor_msgs::image_encodings;
constexpr double kTimeout = 60.0;  // s per condition: generous for a loaded 2-core machine
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

std::mutex g_mutex;
std::condition_variable g_cv;

/// Every message of one topic (thread-safe).
template <class M>
class Collector {
 public:
  using Ptr = boost::shared_ptr<const M>;
  void subscribe(ros::NodeHandle& nh, const std::string& topic) {
    sub_ = nh.subscribe<M>(topic, 20, &Collector::callback, this);
  }
  void shutdown() { sub_.shutdown(); }
  Ptr find(const std::function<bool(const M&)>& pred) const {
    std::lock_guard<std::mutex> lock(g_mutex);
    for (const auto& m : msgs_)
      if (pred(*m)) return m;
    return Ptr();
  }
  size_t size() const {
    std::lock_guard<std::mutex> lock(g_mutex);
    return msgs_.size();
  }

 private:
  void callback(const Ptr& m) {
    {
      std::lock_guard<std::mutex> lock(g_mutex);
      msgs_.push_back(m);
    }
    g_cv.notify_all();
  }
  ros::Subscriber sub_;
  std::vector<Ptr> msgs_;
};

/// Wait until done() holds, calling tick() every @p period s meanwhile (e.g. to publish).
bool waitFor(const std::function<bool()>& done, const std::function<void()>& tick = nullptr,
             double period = 0.2) {
  using Clock = std::chrono::steady_clock;
  const auto end = Clock::now() + std::chrono::duration<double>(kTimeout);
  auto next_tick = Clock::now();
  while (ros::ok() && Clock::now() < end) {
    if (done()) return true;
    if (tick && Clock::now() >= next_tick) {
      tick();
      next_tick = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                     std::chrono::duration<double>(period));
    }
    std::unique_lock<std::mutex> lock(g_mutex);
    g_cv.wait_for(lock, std::chrono::milliseconds(20));
  }
  return done();
}

template <class M>
bool stampIs(const M& m, const ros::Time& t) {
  return m.header.stamp == t;
}

// ---------------------------------------------------------------------------
// The nodelet alone

constexpr double kF = 700.0, kT = 0.12;  // f T = 84 px m

/// A DisparityImage of given values (row-major), f 700, T 0.12, range [2, 120], 1/16 px.
stereo_msgs::DisparityImage disparityMsg(int w, int h, const std::vector<float>& values,
                                         const ros::Time& stamp) {
  stereo_msgs::DisparityImage m;
  m.header.stamp = stamp;
  m.header.frame_id = "left_optical";
  m.image.header = m.header;
  m.image.width = w;
  m.image.height = h;
  m.image.encoding = enc::TYPE_32FC1;
  m.image.is_bigendian = __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__;
  m.image.step = w * sizeof(float);
  m.image.data.resize(m.image.step * h);
  std::memcpy(m.image.data.data(), values.data(), m.image.data.size());
  m.f = kF;
  m.T = kT;
  m.min_disparity = 2.f;
  m.max_disparity = 120.f;
  m.delta_d = 1.f / 16;
  return m;
}

class DisparityToDepth : public ::testing::Test {
 protected:
  void SetUp() override {
    pub_ = nh_.advertise<stereo_msgs::DisparityImage>("disparity", 20);
    depth_.subscribe(nh_, "depth_registered/image_rect");
    log_.subscribe(root_, "/rosout");
    // lazy: the nodelet subscribes to the disparity once the depth has a subscriber
    ASSERT_TRUE(waitFor([this] { return pub_.getNumSubscribers() > 0; }));
  }
  /// Publish @p m (stamped @p t) until its depth arrives; the answer or null.
  Collector<sensor_msgs::Image>::Ptr roundTrip(const stereo_msgs::DisparityImage& m) {
    const ros::Time t = m.header.stamp;
    auto answer = [&] { return depth_.find([&](const sensor_msgs::Image& d) { return stampIs(d, t); }); };
    waitFor([&] { return static_cast<bool>(answer()); }, [&] { pub_.publish(m); }, 1.0);
    return answer();
  }
  ros::Time nextStamp() { return ros::Time(1000 + ++count_, 0); }

  ros::NodeHandle nh_{"stereo"}, root_;
  ros::Publisher pub_;
  Collector<sensor_msgs::Image> depth_;
  Collector<rosgraph_msgs::Log> log_;
  int count_ = 0;
};

TEST_F(DisparityToDepth, AnalyticDepthAndInvalidPixels) {
  // 6 x 4; valid window x 1-4, y 1-2; min_disparity 2, max 120, delta_d 1/16
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> d = {
      42.f, 42.f, 42.f, 42.f, 42.f, 42.f,   // row 0: outside the window
      42.f, 42.f, 84.f, 2.f,  21.f, 42.f,   // row 1: column 0 and 5 outside; 2 = min: valid
      42.f, -1.f, 1.9f, kNaN, 121.f, 42.f,  // row 2: unmatched (-1), below min, NaN, above max
      42.f, inf,  42.f, 42.f, 42.f, 42.f};  // row 3: outside the window
  stereo_msgs::DisparityImage m = disparityMsg(6, 4, d, nextStamp());
  m.valid_window.x_offset = 1;
  m.valid_window.y_offset = 1;
  m.valid_window.width = 4;
  m.valid_window.height = 2;
  const auto out = roundTrip(m);
  ASSERT_TRUE(out) << "no depth for the disparity image";
  EXPECT_EQ(out->header.frame_id, "left_optical");
  EXPECT_EQ(out->encoding, enc::TYPE_32FC1);
  ASSERT_EQ(out->width, 6u);
  ASSERT_EQ(out->height, 4u);
  ASSERT_EQ(out->step, 6u * sizeof(float));
  ASSERT_EQ(out->data.size(), out->step * out->height);
  cv::Mat z;
  double scale;
  cv::Mat swap;
  ASSERT_EQ(conversions::depthFromMsg(*out, z, scale, swap), nullptr);
  const float expected[4][6] = {{kNaN, kNaN, kNaN, kNaN, kNaN, kNaN},
                                {kNaN, 2.f, 1.f, 42.f, 4.f, kNaN},
                                {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN},
                                {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN}};
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) {
      const float e = expected[y][x], v = z.at<float>(y, x);
      if (std::isnan(e))
        EXPECT_TRUE(std::isnan(v)) << x << "," << y << ": " << v;
      else
        EXPECT_NEAR(v, e, 1e-6f * e) << x << "," << y;
    }
}

TEST_F(DisparityToDepth, OtherByteOrderAndWholeImageWindow) {
  // the same values sent big-endian (little-endian on a big-endian host), window unset
  const std::vector<float> d = {84.f, 42.f, 28.f, 8.4f};
  stereo_msgs::DisparityImage m = disparityMsg(2, 2, d, nextStamp());
  m.image.is_bigendian = !m.image.is_bigendian;
  for (size_t i = 0; i < m.image.data.size(); i += 4)
    std::reverse(m.image.data.begin() + i, m.image.data.begin() + i + 4);
  const auto out = roundTrip(m);
  ASSERT_TRUE(out);
  cv::Mat z, swap;
  double scale;
  ASSERT_EQ(conversions::depthFromMsg(*out, z, scale, swap), nullptr);
  EXPECT_FLOAT_EQ(z.at<float>(0, 0), 1.f);
  EXPECT_FLOAT_EQ(z.at<float>(0, 1), 2.f);
  EXPECT_FLOAT_EQ(z.at<float>(1, 0), 3.f);
  EXPECT_FLOAT_EQ(z.at<float>(1, 1), 10.f);
}

TEST_F(DisparityToDepth, BadInputIsDroppedAndTheNodeKeepsRunning) {
  std::vector<stereo_msgs::DisparityImage> bad;
  const std::vector<float> four(4, 42.f);
  auto add = [&](const std::function<void(stereo_msgs::DisparityImage&)>& spoil) {
    stereo_msgs::DisparityImage m = disparityMsg(2, 2, four, nextStamp());
    spoil(m);
    bad.push_back(m);
  };
  add([](stereo_msgs::DisparityImage& m) { m.image.encoding = enc::TYPE_16UC1; });
  add([](stereo_msgs::DisparityImage& m) {  // size 0
    m.image.width = m.image.height = 0;
    m.image.step = 0;
    m.image.data.clear();
  });
  add([](stereo_msgs::DisparityImage& m) { m.image.step = 4; });          // step < width * 4
  add([](stereo_msgs::DisparityImage& m) { m.image.data.resize(8); });   // data too short
  add([](stereo_msgs::DisparityImage& m) { m.f = 0.f; });
  add([](stereo_msgs::DisparityImage& m) { m.T = kNaN; });
  add([](stereo_msgs::DisparityImage& m) {  // window outside the image
    m.valid_window.x_offset = 10;
    m.valid_window.width = 2;
    m.valid_window.height = 2;
  });
  for (const auto& m : bad) pub_.publish(m);
  // a good image afterwards is answered (same connection, in order: the bad ones came first)
  const auto good = roundTrip(disparityMsg(2, 2, four, nextStamp()));
  ASSERT_TRUE(good) << "the nodelet stopped answering after bad input";
  for (const auto& m : bad)
    EXPECT_FALSE(depth_.find([&](const sensor_msgs::Image& d) { return stampIs(d, m.header.stamp); }))
        << "a bad disparity image was converted (stamp " << m.header.stamp << ")";
  // the problem is reported as an error naming it (throttled to one per 5 s: the wrong encoding
  // is sent again until the log connection is up and its error gets through)
  EXPECT_TRUE(waitFor(
      [this] {
        return static_cast<bool>(log_.find([](const rosgraph_msgs::Log& l) {
          return l.level == rosgraph_msgs::Log::ERROR &&
                 l.msg.find("Dropping disparity image") != std::string::npos &&
                 l.msg.find("encoding") != std::string::npos;
        }));
      },
      [&] { pub_.publish(bad.front()); }, 1.0));
}

TEST_F(DisparityToDepth, UnsubscribesWhenNobodyListens) {
  depth_.shutdown();
  EXPECT_TRUE(waitFor([this] { return pub_.getNumSubscribers() == 0; }));
  depth_.subscribe(nh_, "depth_registered/image_rect");
  EXPECT_TRUE(waitFor([this] { return pub_.getNumSubscribers() > 0; }));
}

// ---------------------------------------------------------------------------
// launch/stereo.launch

constexpr int kW = 640, kH = 360, kDisparity = 32;
constexpr double kFx = 500.0, kBaseline = 0.12;  // Z = 500 * 0.12 / 32 = 1.875 m

sensor_msgs::CameraInfo cameraInfo(double tx) {
  std_msgs::Header h;
  h.frame_id = "stereo_left_optical";
  sensor_msgs::CameraInfo info =
      conversions::cameraInfoFromIntrinsics(Intrinsics{kFx, kFx, kW / 2.0, kH / 2.0}, kW, kH, h);
  info.P[3] = tx;  // right camera: -fx B
  return info;
}

sensor_msgs::Image colourMsg(const cv::Mat& grey) {
  sensor_msgs::Image m;
  cv::Mat bgr = conversions::prepareImage(grey.rows, grey.cols, CV_8UC3, enc::BGR8,
                                          std_msgs::Header(), m);
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  return m;
}

TEST(StereoChain, TexturedWallAtKnownDepth) {
  ros::NodeHandle nh("stereo");
  // a textured wall facing the rig: the right image is the left shifted by the disparity
  cv::Mat texture(kH, kW + kDisparity, CV_8UC1);
  cv::RNG(7).fill(texture, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(texture, texture, cv::Size(3, 3), 0.8);
  sensor_msgs::Image left = colourMsg(texture(cv::Rect(0, 0, kW, kH)));
  sensor_msgs::Image right = colourMsg(texture(cv::Rect(kDisparity, 0, kW, kH)));
  // both camera_infos in the left optical frame, as stereo drivers send them (image_geometry's
  // StereoCameraModel asserts it: other frames abort stereo_image_proc, and its manager)
  const sensor_msgs::CameraInfo left_info = cameraInfo(0.0);
  const sensor_msgs::CameraInfo right_info = cameraInfo(-kFx * kBaseline);
  ros::Publisher pub_left = nh.advertise<sensor_msgs::Image>("left/image_rect_color", 5);
  ros::Publisher pub_right = nh.advertise<sensor_msgs::Image>("right/image_rect_color", 5);
  ros::Publisher pub_left_info = nh.advertise<sensor_msgs::CameraInfo>("left/camera_info", 5);
  ros::Publisher pub_right_info = nh.advertise<sensor_msgs::CameraInfo>("right/camera_info", 5);
  Collector<sensor_msgs::Image> depth;
  Collector<LanePlane> plane;
  depth.subscribe(nh, "depth_registered/image_rect");
  plane.subscribe(nh, "lane_plane");
  std::vector<ros::Time> sent;
  int n = 0;
  auto publish = [&] {
    const ros::Time t(2000 + ++n, 0);
    sensor_msgs::CameraInfo li = left_info, ri = right_info;
    left.header = right.header = li.header;
    left.header.stamp = right.header.stamp = li.header.stamp = ri.header.stamp = t;
    {
      std::lock_guard<std::mutex> lock(g_mutex);
      sent.push_back(t);
    }
    pub_left_info.publish(li);
    pub_right_info.publish(ri);
    pub_left.publish(left);
    pub_right.publish(right);
  };
  auto wasSent = [&](const ros::Time& t) {
    return std::find(sent.begin(), sent.end(), t) != sent.end();  // under g_mutex (find)
  };
  // depth and the lane detector's plane (which needs colour, depth and camera_info in sync)
  ASSERT_TRUE(waitFor(
      [&] {
        return depth.find([&](const sensor_msgs::Image& d) { return wasSent(d.header.stamp); }) &&
               plane.find([&](const LanePlane& p) { return wasSent(p.header.stamp); });
      },
      publish, 0.5))
      << "depth messages " << depth.size() << ", lane_plane messages " << plane.size();
  const auto d = depth.find([&](const sensor_msgs::Image& m) { return wasSent(m.header.stamp); });
  EXPECT_EQ(d->header.frame_id, "stereo_left_optical");  // registered to the left image
  EXPECT_EQ(d->encoding, enc::TYPE_32FC1);
  ASSERT_EQ(d->width, static_cast<uint32_t>(kW));
  ASSERT_EQ(d->height, static_cast<uint32_t>(kH));
  cv::Mat z, swap;
  double scale;
  ASSERT_EQ(conversions::depthFromMsg(*d, z, scale, swap), nullptr);
  const double expected = kFx * kBaseline / kDisparity;
  int valid = 0, close = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float v = z.at<float>(y, x);
      if (std::isnan(v)) continue;
      ++valid;
      close += std::fabs(v - expected) <= 0.01 * expected;
    }
  // stereo_image_proc leaves the left disparity_range columns and a block border unmatched
  EXPECT_GT(valid, 0.6 * kW * kH);
  EXPECT_GT(close, 0.98 * valid) << close << " of " << valid << " within 1% of " << expected;
}

}  // namespace
}  // namespace rgbd_lane_detector

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_disparity_to_depth");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return result;
}
