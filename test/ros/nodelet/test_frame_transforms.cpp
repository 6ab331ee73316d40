// FrameTransforms (src/ros/frame_transforms.h) on a plain tf2::BufferCore, no roscore: lookups
// never wait; a transform at the image stamp, else the latest within tf_timeout (said), else
// none (said); the vehicle frame falls back to the road frame; odometry gives the motion.
#include <string>

#include <gtest/gtest.h>

#include <tf2_eigen/tf2_eigen.h>

#include "../../../src/ros/frame_transforms.h"

namespace rgbd_lane_detector {
namespace {

constexpr const char* kOptical = "camera_optical";

geometry_msgs::TransformStamped transform(const std::string& parent, const std::string& child,
                                          double stamp, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = t;
  geometry_msgs::TransformStamped m = tf2::eigenToTransform(T);
  m.header.frame_id = parent;
  m.header.stamp = ros::Time(stamp);
  m.child_frame_id = child;
  return m;
}

std_msgs::Header imageAt(double stamp) {
  std_msgs::Header h;
  h.frame_id = kOptical;
  h.stamp = ros::Time(stamp);
  return h;
}

FrameTransforms::Frames frames(const std::string& target, double tolerance = 0.05) {
  FrameTransforms::Frames f;
  f.target = target;
  f.lane_model = "base_link";
  f.tolerance = tolerance;
  return f;
}

TEST(FrameTransforms, NoTargetFrameIsTheOpticalFrame) {
  FrameTransforms tf(frames(""), nullptr);
  Eigen::Isometry3d T;
  std::string frame_id, why;
  EXPECT_EQ(tf.outputTransform(imageAt(10), T, frame_id, why), FrameTransforms::Lookup::kAtStamp);
  EXPECT_EQ(frame_id, kOptical);
  EXPECT_TRUE(T.isApprox(Eigen::Isometry3d::Identity()));
}

TEST(FrameTransforms, AtTheStampElseTheLatestWithinTheTimeoutElseMissing) {
  tf2::BufferCore buffer;
  buffer.setTransform(transform("base_link", kOptical, 10.0, {1, 0, 0}), "test");
  buffer.setTransform(transform("base_link", kOptical, 10.2, {3, 0, 0}), "test");
  FrameTransforms tf(frames("base_link", 0.05), &buffer);
  Eigen::Isometry3d T;
  std::string frame_id, why;
  // interpolated at the stamp
  ASSERT_EQ(tf.outputTransform(imageAt(10.1), T, frame_id, why), FrameTransforms::Lookup::kAtStamp);
  EXPECT_EQ(frame_id, "base_link");
  EXPECT_NEAR(T.translation().x(), 2.0, 1e-9);
  // 30 ms after the latest: the latest, said
  ASSERT_EQ(tf.outputTransform(imageAt(10.23), T, frame_id, why), FrameTransforms::Lookup::kLatest);
  EXPECT_NEAR(T.translation().x(), 3.0, 1e-9);
  EXPECT_NE(why.find("latest"), std::string::npos) << why;
  // 100 ms after it: none, said with both frames
  ASSERT_EQ(tf.outputTransform(imageAt(10.3), T, frame_id, why), FrameTransforms::Lookup::kMissing);
  EXPECT_NE(why.find("target_frame 'base_link'"), std::string::npos) << why;
  EXPECT_NE(why.find(kOptical), std::string::npos) << why;
  // with tf_timeout 0 only the stamp itself
  FrameTransforms strict(frames("base_link", 0.0), &buffer);
  EXPECT_EQ(strict.outputTransform(imageAt(10.23), T, frame_id, why),
            FrameTransforms::Lookup::kMissing);
  // before the buffer's first transform: none (never an older image on a newer transform)
  EXPECT_EQ(tf.outputTransform(imageAt(9.0), T, frame_id, why), FrameTransforms::Lookup::kMissing);
}

TEST(FrameTransforms, StaticTransformsAreThereAtAnyStamp) {
  tf2::BufferCore buffer;
  buffer.setTransform(transform("base_link", kOptical, 0.0, {0, 0, 1.5}), "test", true);
  FrameTransforms tf(frames("base_link", 0.0), &buffer);
  Eigen::Isometry3d T;
  std::string frame_id, why;
  EXPECT_EQ(tf.outputTransform(imageAt(1234.5), T, frame_id, why),
            FrameTransforms::Lookup::kAtStamp);
  EXPECT_NEAR(T.translation().z(), 1.5, 1e-12);
  tf.reset();  // a jump back in time keeps the static transforms
  EXPECT_EQ(tf.outputTransform(imageAt(1.0), T, frame_id, why), FrameTransforms::Lookup::kAtStamp);
}

TEST(FrameTransforms, UpAxisIsTheUpFramesZInTheOpticalFrame) {
  tf2::BufferCore buffer;
  geometry_msgs::TransformStamped m = transform("camera_optical", "base_link", 0.0, {0, 1.5, 0});
  // base_link z (up) is the optical -y: a rotation of +90 deg about x takes z to -y
  const Eigen::Quaterniond q(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));
  m.transform.rotation = tf2::toMsg(q);
  buffer.setTransform(m, "test", true);
  FrameTransforms::Frames f = frames("");
  f.up = "base_link";
  FrameTransforms tf(f, &buffer);
  Eigen::Vector3d up;
  std::string why;
  ASSERT_TRUE(tf.upAxis(kOptical, up, why)) << why;
  EXPECT_TRUE(up.isApprox(Eigen::Vector3d(0, -1, 0), 1e-12)) << up.transpose();
  EXPECT_FALSE(tf.upAxis("other_optical", up, why));
  EXPECT_NE(why.find("up_frame 'base_link'"), std::string::npos) << why;
}

TEST(FrameTransforms, VehicleFrameFallsBackToTheRoadFrameAndOdometryMovesTheModel) {
  tf2::BufferCore buffer;
  FrameTransforms::Frames f = frames("");
  f.odom = "odom";
  FrameTransforms tf(f, &buffer);
  FrameTransforms::Vehicle v;
  tf.vehicleFrame(imageAt(1.0), true, v);  // nothing on tf yet
  EXPECT_FALSE(v.found);
  EXPECT_EQ(v.frame_id, std::string(kOptical) + "_road");
  EXPECT_NE(v.warning.find("road frame"), std::string::npos) << v.warning;
  tf.vehicleFrame(imageAt(1.1), false, v);  // lane model off: no lookup, no warning
  EXPECT_TRUE(v.warning.empty());

  buffer.setTransform(transform("base_link", kOptical, 0.0, {0, 0, 1.5}), "test", true);
  for (double t = 2.0; t <= 3.01; t += 0.1)  // driving forward at 10 m/s
    buffer.setTransform(transform("odom", "base_link", t, {10.0 * t, 0, 0}), "test");
  tf.vehicleFrame(imageAt(2.5), true, v);  // the first with a vehicle frame: no motion yet
  EXPECT_TRUE(v.found);
  EXPECT_EQ(v.frame_id, "base_link");
  EXPECT_NEAR(v.vehicle_from_camera.translation().z(), 1.5, 1e-12);
  EXPECT_FALSE(v.has_motion);
  tf.vehicleFrame(imageAt(2.7), true, v);
  ASSERT_TRUE(v.has_motion) << v.motion_warning;
  // base_link at 2.7 seen from base_link at 2.5: 2 m ahead
  EXPECT_NEAR(v.motion.translation().x(), 2.0, 1e-9);
  tf.vehicleFrame(imageAt(3.03), true, v);  // odometry 30 ms behind: its latest, 3.0
  ASSERT_TRUE(v.has_motion) << v.motion_warning;
  EXPECT_NEAR(v.motion.translation().x(), 3.0, 1e-9);
  tf.vehicleFrame(imageAt(3.5), true, v);  // odometry stopped: the model is not moved, said
  EXPECT_FALSE(v.has_motion);
  EXPECT_NE(v.motion_warning.find("without motion prediction"), std::string::npos);
}

}  // namespace
}  // namespace rgbd_lane_detector
