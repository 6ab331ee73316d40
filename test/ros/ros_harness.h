// Harness of the nodelet's rostests (test_lane_detector_ros, test_lifecycle): publishes ray-cast
// road frames with exact plane truth, collects outputs, /rosout and /diagnostics, and waits on
// conditions with generous timeouts (republishing frames meanwhile), never on fixed sleeps.
//
// Private parameters of the test node: ~target_frame ("" = outputs in the optical frame; else the
// harness broadcasts base_link -> optical with the road at z = 0), ~detector (the detector's
// name, for dynamic_reconfigure).
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <cv_bridge/cv_bridge.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <nodelet/NodeletList.h>
#include <nodelet/NodeletLoad.h>
#include <nodelet/NodeletUnload.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <visualization_msgs/MarkerArray.h>
#include <opencv2/imgproc.hpp>

#include <rgbd_lane_detector/LaneDetectorConfig.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <rgbd_lane_detector/LaneMarkings.h>
#include <rgbd_lane_detector/LaneModel.h>
#include <rgbd_lane_detector/LanePlane.h>

#include "../core/synthetic_scene.h"
#include "rgbd_lane_detector/ros/conversions.h"

namespace rgbd_lane_detector {
namespace ros_test {

constexpr double kTimeout = 60.0;     // s per condition: generous for a loaded 2-core machine
constexpr double kTickPeriod = 0.2;   // s between frames published while waiting
constexpr double kPaceTimeout = 1.5;  // s to wait for the answer to a frame before the next
const char* const kOpticalFrame = "camera_color_optical_frame";

inline std::mutex g_mutex;  // guards every collector
inline std::condition_variable g_cv;

template <class M>
ros::Time stampOf(const M& m) {
  return m.header.stamp;
}
inline ros::Time stampOf(const visualization_msgs::MarkerArray& m) {
  return m.markers.empty() ? ros::Time() : m.markers.front().header.stamp;
}

/// Keeps every message of one topic (thread-safe); notifies waiters.
template <class M>
class Collector {
 public:
  using Ptr = boost::shared_ptr<const M>;
  Collector() = default;
  Collector(const Collector&) = delete;
  Collector& operator=(const Collector&) = delete;
  /// Unsubscribes first: shutdown() returns once no callback runs any more (roscpp removes the
  /// subscription's callbacks under their calling lock), so none can touch msgs_ after it.
  ~Collector() { sub_.shutdown(); }
  void subscribe(ros::NodeHandle& nh, const std::string& topic) {
    sub_ = nh.subscribe<M>(topic, 50, &Collector::callback, this);
  }
  void shutdown() { sub_.shutdown(); }
  /// Publishers this subscriber is connected to.
  uint32_t numPublishers() const { return sub_.getNumPublishers(); }
  void clear() {
    std::lock_guard<std::mutex> lock(g_mutex);
    msgs_.clear();
  }
  /// First message satisfying pred (null if none).
  Ptr find(const std::function<bool(const M&)>& pred) const {
    std::vector<Ptr> msgs;
    {
      std::lock_guard<std::mutex> lock(g_mutex);
      msgs = msgs_;  // pred may query other collectors
    }
    for (const auto& m : msgs)
      if (pred(*m)) return m;
    return Ptr();
  }
  Ptr withStamp(const ros::Time& t) const {
    return find([&](const M& m) { return stampOf(m) == t; });
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
  std::vector<Ptr> msgs_;  // before sub_: members are destroyed in reverse order
  ros::Subscriber sub_;
};

/// Wait until done() holds, calling tick() every kTickPeriod (e.g. to publish a frame).
/// (done may return anything testable as a bool, e.g. a found message.)
template <class Done>
bool waitFor(const Done& done, const std::function<void()>& tick = nullptr,
             double timeout = kTimeout, double tick_period = kTickPeriod) {
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](double s) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  };
  const Clock::time_point end = Clock::now() + seconds(timeout);
  Clock::time_point next_tick = Clock::now();
  while (ros::ok() && Clock::now() < end) {
    if (static_cast<bool>(done())) return true;
    if (tick && Clock::now() >= next_tick) {
      tick();
      next_tick = Clock::now() + seconds(tick_period);
    }
    std::unique_lock<std::mutex> lock(g_mutex);
    g_cv.wait_for(lock, std::chrono::milliseconds(20));
  }
  return static_cast<bool>(done());
}

inline double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::fabs(a.normalized().dot(b.normalized())))) * 180.0 / M_PI;
}

/// One set of input messages (modified per case, stamped on publish).
struct InputSet {
  sensor_msgs::Image colour, depth;
  sensor_msgs::CameraInfo info;
};

/// Test-wide state: publishers, rendered scene, truth, log and diagnostics collectors.
class Harness {
 public:
  Harness() : pnh_("~") {
    pnh_.param<std::string>("target_frame", target_frame, "");
    pnh_.param<std::string>("detector", detector, "lane_detector");
    detector = nh.resolveName(detector);
    pnh_.param<std::string>("manager", manager, "");
    if (!manager.empty()) manager = nh.resolveName(manager);
    advertiseInputs();
    rosout.subscribe(nh, "/rosout");
    diagnostics.subscribe(nh, "/diagnostics");
    scene.render(bgr, depth_mm, &depth_m);
    good = makeInputs(bgr, "bgr8", depth_mm, "16UC1", scene.K);
  }

  InputSet makeInputs(const cv::Mat& colour, const std::string& colour_enc, const cv::Mat& depth,
                      const std::string& depth_enc, const Intrinsics& K) const {
    InputSet s;
    std_msgs::Header h;
    h.frame_id = kOpticalFrame;
    s.colour = *cv_bridge::CvImage(h, colour_enc, colour).toImageMsg();
    s.depth = *cv_bridge::CvImage(h, depth_enc, depth).toImageMsg();
    s.info = conversions::cameraInfoFromIntrinsics(K, colour.cols, colour.rows, h);
    return s;
  }

  /// The good input set of another scene (bgr8, 16UC1 millimetres).
  InputSet inputsOf(const test::RoadScene& other) const {
    cv::Mat colour, depth;
    other.render(colour, depth);
    return makeInputs(colour, "bgr8", depth, "16UC1", other.K);
  }

  /// A stamp after every one published so far.
  ros::Time nextStamp() {
    ros::Time t = ros::Time::now();
    if (t <= last_stamp) t = last_stamp + ros::Duration(0, 1000);
    last_stamp = t;
    return t;
  }

  /// Publish one set with @p stamp (fresh messages: publishing never aliases earlier ones).
  ros::Time publish(const InputSet& s, const ros::Time& stamp) {
    auto colour = boost::make_shared<sensor_msgs::Image>(s.colour);
    auto depth = boost::make_shared<sensor_msgs::Image>(s.depth);
    auto info = boost::make_shared<sensor_msgs::CameraInfo>(s.info);
    colour->header.stamp = depth->header.stamp = info->header.stamp = stamp;
    pub_info.publish(info);
    pub_depth.publish(depth);
    pub_colour.publish(colour);
    ++colour_published;
    last_published = stamp;
    last_publish_time = std::chrono::steady_clock::now();
    return stamp;
  }
  /// Publish a new frame (default: the good one) unless the previous one is still unanswered on
  /// lane_plane, for at most kPaceTimeout: a slow detector (valgrind, loaded machine) is never
  /// flooded, so the frames a test waits for are not dropped from full queues.
  void publishPaced(const Collector<LanePlane>& plane, const InputSet* in = nullptr) {
    const bool answered = last_published.isZero() || plane.withStamp(last_published);
    if (!answered && std::chrono::steady_clock::now() - last_publish_time <
                         std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                             std::chrono::duration<double>(kPaceTimeout)))
      return;
    publish(in ? *in : good);
  }
  ros::Time publish(const InputSet& s) { return publish(s, nextStamp()); }

  /// Road plane truth in the output frame.
  void planeTruth(Eigen::Vector3d& n, double& d) const {
    if (target_frame.empty()) {
      n = scene.planeNormal();
      d = scene.planeDistance();
    } else {  // base_link on the road, z up
      n = Eigen::Vector3d::UnitZ();
      d = 0.0;
    }
  }
  /// Signed lateral position (m) of a point (+ right of the camera) in the output frame.
  double lateral(const geometry_msgs::Point& p) const { return target_frame.empty() ? p.x : -p.y; }
  /// Distance along the road of a point in the output frame.
  double forward(const geometry_msgs::Point& p) const { return target_frame.empty() ? p.z : p.x; }
  /// Frame of lane_model: base_link when the test broadcasts it, else the road-aligned frame the
  /// nodelet falls back to (and broadcasts) under the camera.
  std::string modelFrame() const {
    return target_frame.empty() ? std::string(kOpticalFrame) + "_road" : target_frame;
  }
  std::string outputFrame() const { return target_frame.empty() ? kOpticalFrame : target_frame; }

  /// base_link -> optical frame of the rendered camera (height camera_height, pitched down).
  void broadcastTransform() {
    if (tf_sent) return;
    const double p = scene.pitch;
    Eigen::Matrix3d R_optical_base;  // columns: base x (forward), y (left), z (up) in optical
    R_optical_base.col(0) = Eigen::Vector3d(0, -std::sin(p), std::cos(p));
    R_optical_base.col(1) = Eigen::Vector3d(-1, 0, 0);
    R_optical_base.col(2) = scene.planeNormal();  // up: the road normal, toward the camera
    Eigen::Isometry3d T_base_optical = Eigen::Isometry3d::Identity();
    T_base_optical.linear() = R_optical_base.transpose();
    T_base_optical.translation() = Eigen::Vector3d(0, 0, scene.camera_height);
    geometry_msgs::TransformStamped t = tf2::eigenToTransform(T_base_optical);
    t.header.stamp = ros::Time::now();
    t.header.frame_id = target_frame;
    t.child_frame_id = kOpticalFrame;
    broadcaster.sendTransform(t);
    tf_sent = true;
  }
  void prepare() {
    if (!target_frame.empty()) broadcastTransform();
  }

  /// The camera driver's publishers (a new publisher numbers header.seq from 0 again).
  void advertiseInputs() {
    pub_colour = nh.advertise<sensor_msgs::Image>("rgb/image_rect_color", 20);
    pub_depth = nh.advertise<sensor_msgs::Image>("depth_registered/image_rect", 20);
    pub_info = nh.advertise<sensor_msgs::CameraInfo>("rgb/camera_info", 20);
  }
  /// The camera driver stops: its publishers leave the master.
  void shutdownInputs() {
    pub_colour.shutdown();
    pub_depth.shutdown();
    pub_info.shutdown();
  }

  /// True once the /rosout collector is connected to every node publishing /rosout (the master's
  /// list): lines logged before a node's connection is made are lost, /rosout is not latched.
  bool rosoutConnected() {
    XmlRpc::XmlRpcValue args, result, payload;
    args[0] = ros::this_node::getName();
    if (!ros::master::execute("getSystemState", args, result, payload, false)) return false;
    int publishers = 0;
    for (int i = 0; i < payload[0].size(); ++i)
      if (static_cast<std::string>(payload[0][i][0]) == "/rosout") publishers = payload[0][i][1].size();
    return publishers > 0 && rosout.numPublishers() >= static_cast<uint32_t>(publishers);
  }

  /// Call the manager's load_nodelet (no bond: this process owns the nodelet's life), for the
  /// detector with the private parameters already on the parameter server.
  bool loadDetector(const std::string& name) const {
    nodelet::NodeletLoad srv;
    srv.request.name = name;
    srv.request.type = "rgbd_lane_detector/LaneDetectorNodelet";
    return ros::service::waitForService(manager + "/load_nodelet", ros::Duration(kTimeout)) &&
           ros::service::call(manager + "/load_nodelet", srv) && srv.response.success;
  }
  /// Call the manager's unload_nodelet.
  bool unloadDetector(const std::string& name) const {
    nodelet::NodeletUnload srv;
    srv.request.name = name;
    return ros::service::call(manager + "/unload_nodelet", srv) && srv.response.success;
  }
  /// The nodelets the manager runs (empty, and false, when its list service does not answer).
  bool loadedNodelets(std::vector<std::string>& names) const {
    nodelet::NodeletList srv;
    if (!ros::service::call(manager + "/list", srv)) return false;
    names = srv.response.nodelets;
    return true;
  }

  /// Number of /rosout lines of @p level containing @p a (and @p b).
  size_t logCount(uint8_t level, const std::string& a, const std::string& b = "") const {
    size_t n = 0;
    rosout.find([&](const rosgraph_msgs::Log& l) {
      n += l.level == level && l.msg.find(a) != std::string::npos &&
           l.msg.find(b) != std::string::npos;
      return false;
    });
    return n;
  }

  bool logContains(uint8_t level, const std::string& a, const std::string& b = "") const {
    return static_cast<bool>(rosout.find([&](const rosgraph_msgs::Log& l) {
      return l.level == level && l.msg.find(a) != std::string::npos &&
             l.msg.find(b) != std::string::npos;
    }));
  }

  ros::NodeHandle nh;
  std::string target_frame, detector;
  std::string manager;  ///< the nodelet manager running the detector ("" = standalone node)
  ros::Publisher pub_colour, pub_depth, pub_info;
  test::RoadScene scene;
  cv::Mat bgr, depth_mm, depth_m;
  InputSet good;
  Collector<rosgraph_msgs::Log> rosout;
  Collector<diagnostic_msgs::DiagnosticArray> diagnostics;
  tf2_ros::StaticTransformBroadcaster broadcaster;
  bool tf_sent = false;
  ros::Time last_stamp;           ///< latest stamp handed out by nextStamp()
  ros::Time last_published;       ///< stamp of the last frame published
  uint64_t colour_published = 0;  ///< colour images published (every publish*)
  std::chrono::steady_clock::time_point last_publish_time;

 private:
  ros::NodeHandle pnh_;
};

inline Harness* g = nullptr;

/// Subscribers to every output of the detector.
struct Outputs {
  Collector<LanePlane> plane;
  Collector<LaneMarkings> markings;
  Collector<sensor_msgs::PointCloud2> points;
  Collector<visualization_msgs::MarkerArray> markers;
  Collector<LaneModel> model;
  Collector<nav_msgs::Path> centre;
  Collector<nav_msgs::OccupancyGrid> grid;
  Collector<sensor_msgs::Image> left, right, geometric, debug;
  void subscribeAll(ros::NodeHandle& nh) {
    plane.subscribe(nh, "lane_plane");
    model.subscribe(nh, "lane_model");
    centre.subscribe(nh, "lane_centre_line");
    markings.subscribe(nh, "lane_markings");
    points.subscribe(nh, "lane_points");
    markers.subscribe(nh, "lane_visualization");
    left.subscribe(nh, "response/left");
    right.subscribe(nh, "response/right");
    geometric.subscribe(nh, "response/geometric");
    debug.subscribe(nh, "debug_image");
  }
};

inline bool inputsSubscribed(bool yes) {
  const auto n = [](const ros::Publisher& p) { return p.getNumSubscribers() > 0; };
  return yes ? (n(g->pub_colour) && n(g->pub_depth) && n(g->pub_info))
             : (!n(g->pub_colour) && !n(g->pub_depth) && !n(g->pub_info));
}

inline void expectPlaneNearTruth(const LanePlane& plane) {
  Eigen::Vector3d n_true;
  double d_true;
  g->planeTruth(n_true, d_true);
  const Eigen::Vector3d n(plane.normal.x, plane.normal.y, plane.normal.z);
  EXPECT_TRUE(plane.valid);
  EXPECT_NEAR(n.norm(), 1.0, 1e-6);
  EXPECT_LT(angleDeg(n, n_true), 1.0);
  EXPECT_GT(n.dot(n_true), 0.0) << "normal must point toward the camera side";
  EXPECT_NEAR(plane.distance, d_true, 0.05);
}

// Reconfigure one parameter through the set_parameters service; returns the applied config.
template <class P>
bool reconfigure(const std::string& name, decltype(P::value) value,
                 dynamic_reconfigure::Config* applied,
                 std::vector<P> dynamic_reconfigure::Config::*field) {
  const std::string service = g->detector + "/set_parameters";
  if (!ros::service::waitForService(service, ros::Duration(kTimeout))) return false;
  dynamic_reconfigure::Reconfigure srv;
  P p;
  p.name = name;
  p.value = value;
  (srv.request.config.*field).push_back(p);
  if (!ros::service::call(service, srv)) return false;
  if (applied) *applied = srv.response.config;
  return true;
}
inline bool setBool(const std::string& name, bool v, dynamic_reconfigure::Config* out = nullptr) {
  return reconfigure<dynamic_reconfigure::BoolParameter>(name, v, out,
                                                         &dynamic_reconfigure::Config::bools);
}
inline bool setDouble(const std::string& name, double v,
                      dynamic_reconfigure::Config* out = nullptr) {
  return reconfigure<dynamic_reconfigure::DoubleParameter>(name, v, out,
                                                           &dynamic_reconfigure::Config::doubles);
}
inline bool setInt(const std::string& name, int v, dynamic_reconfigure::Config* out = nullptr) {
  return reconfigure<dynamic_reconfigure::IntParameter>(name, v, out,
                                                        &dynamic_reconfigure::Config::ints);
}

/// Key/values of the detector's "processing" status in @p a (empty when absent).
inline std::map<std::string, std::string> processingValues(
    const diagnostic_msgs::DiagnosticArray& a) {
  std::map<std::string, std::string> v;
  for (const auto& s : a.status)
    if (s.name.find("processing") != std::string::npos)
      for (const auto& kv : s.values) v[kv.key] = kv.value;
  return v;
}
/// A counter of a processing status (-1 when absent); prefix: the first key starting with it.
inline long long counter(const std::map<std::string, std::string>& v, const std::string& key,
                         bool prefix = false) {
  for (const auto& kv : v)
    if (prefix ? kv.first.compare(0, key.size(), key) == 0 : kv.first == key)
      return std::stoll(kv.second);
  return -1;
}
/// The nodelet's accounting rule: received == processed + dropped + skipped + not synchronised +
/// waiting, and dropped == the sum of the per-reason counts.
inline ::testing::AssertionResult accountingHolds(const std::map<std::string, std::string>& v) {
  const long long received = counter(v, "Frames received"),
                  processed = counter(v, "Frames processed"),
                  dropped = counter(v, "Frames dropped"),
                  skipped = counter(v, "Frames skipped (no subscriber)"),
                  not_sync = counter(v, "Frames not synchronised"),
                  waiting = counter(v, "Frames waiting");
  if (std::min({received, processed, dropped, skipped, not_sync, waiting}) < 0)
    return ::testing::AssertionFailure() << "a counter is missing from the processing status";
  long long by_reason = 0;
  for (const auto& kv : v)
    if (kv.first.compare(0, 9, "Dropped: ") == 0) by_reason += std::stoll(kv.second);
  if (received != processed + dropped + skipped + not_sync + waiting || by_reason != dropped ||
      counter(v, "Frames unaccounted") != 0)
    return ::testing::AssertionFailure()
           << "received " << received << " != processed " << processed << " + dropped " << dropped
           << " (by reason " << by_reason << ") + skipped " << skipped << " + not synchronised "
           << not_sync << " + waiting " << waiting;
  return ::testing::AssertionSuccess();
}

/// Every processing status received so far keeps the accounting rule.
inline void expectAccountingInEveryReport() {
  size_t reports = 0;
  g->diagnostics.find([&](const diagnostic_msgs::DiagnosticArray& a) {
    const auto v = processingValues(a);
    if (v.empty()) return false;
    ++reports;
    EXPECT_TRUE(accountingHolds(v));
    return false;
  });
  EXPECT_GT(reports, 0u);
}

/// Unload the detector through its manager; it leaves the manager's list and its reconfigure
/// service goes.
inline ::testing::AssertionResult unloadDetectorFromManager() {
  if (!g->unloadDetector(g->detector))
    return ::testing::AssertionFailure() << "unload_nodelet " << g->detector << " failed";
  std::vector<std::string> names;
  if (!waitFor([&] {
        return g->loadedNodelets(names) &&
               std::find(names.begin(), names.end(), g->detector) == names.end();
      }))
    return ::testing::AssertionFailure() << "the manager still lists " << g->detector;
  if (!waitFor([] { return !ros::service::exists(g->detector + "/set_parameters", false); }))
    return ::testing::AssertionFailure()
           << "the reconfigure service of " << g->detector << " outlived it";
  return ::testing::AssertionSuccess();
}

/// main() of a rostest on this harness: gtest, ROS (node @p node, two spinner threads), the
/// harness g, the tests.
inline int runTests(int argc, char** argv, const char* node) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, node);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  g = new Harness;
  const int result = RUN_ALL_TESTS();
  delete g;
  g = nullptr;
  ros::shutdown();
  return result;
}

}  // namespace ros_test
}  // namespace rgbd_lane_detector
