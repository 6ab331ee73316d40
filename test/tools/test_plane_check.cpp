// The evaluation's reference road plane (tools/eval/plane_check.cpp): RANSAC plus a refit, and
// the refusal of inliers that lie along one line.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rgbd_lane_detector_tools/plane_check.h"

using namespace rgbd_lane_detector;
using namespace rgbd_lane_detector::tools;

namespace {

// The road 1.6 m below the camera, pitched down by @p pitch and rolled by @p roll (rad), as
// n . p + d = 0 in the optical frame (y down, n toward the camera: up).
void roadPlane(double pitch, double roll, Eigen::Vector3d& n, double& d) {
  n = Eigen::Vector3d(std::sin(roll), -std::cos(roll) * std::cos(pitch), std::sin(pitch));
  n.normalize();
  d = 1.6;
}

// A point of the plane at lateral x and range z (the plane's y solved), with 1 cm noise.
Eigen::Vector3d onPlane(const Eigen::Vector3d& n, double d, double x, double z, double noise) {
  return Eigen::Vector3d(x, -(n.x() * x + n.z() * z + d) / n.y() + noise, z);
}

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::fabs(a.normalized().dot(b.normalized())))) * 180.0 / M_PI;
}

}  // namespace

TEST(RansacPlane, RecoversTheRoadAmongACarsPoints) {
  Eigen::Vector3d n;
  double d;
  roadPlane(0.04, 0.02, n, d);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> lateral(-3.0, 3.0), range(5.0, 30.0), unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 300; ++i) points.push_back(onPlane(n, d, lateral(rng), range(rng), noise(rng)));
  // a car's back 12 m ahead: a vertical face from the road to 1.4 m above it
  for (int i = 0; i < 150; ++i) {
    const double x = -1.0 + 2.0 * unit(rng);
    const Eigen::Vector3d foot = onPlane(n, d, x, 12.0, 0.0);
    points.emplace_back(x, foot.y() - 1.4 * unit(rng), 12.0);
  }
  Eigen::Vector3d found;
  double distance = 0.0;
  ASSERT_TRUE(ransacPlane(points, 0.05, found, distance));
  EXPECT_LT(angleDeg(found, n), 0.3);
  EXPECT_NEAR(distance, d, 0.02);
  EXPECT_LT(found.y(), 0.0);  // oriented toward the camera: up in the optical frame
}

TEST(RansacPlane, RefusesInliersAlongOneLine) {
  // a wet road that returns only from one painted line 1.7 m right of the camera: every plane
  // through that line fits it, whatever its roll
  Eigen::Vector3d n;
  double d;
  roadPlane(0.04, 0.0, n, d);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> range(5.0, 30.0), across(-0.06, 0.06);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<Eigen::Vector3d> line;
  for (int i = 0; i < 200; ++i) line.push_back(onPlane(n, d, 1.7 + across(rng), range(rng), noise(rng)));
  Eigen::Vector3d found;
  double distance = 0.0;
  EXPECT_FALSE(ransacPlane(line, 0.05, found, distance));
  // two painted lines 3.5 m apart fix it
  std::vector<Eigen::Vector3d> lane = line;
  for (int i = 0; i < 200; ++i) lane.push_back(onPlane(n, d, -1.8 + across(rng), range(rng), noise(rng)));
  ASSERT_TRUE(ransacPlane(lane, 0.05, found, distance));
  EXPECT_LT(angleDeg(found, n), 0.5);
}

TEST(RansacPlane, RefusesTooFewPoints) {
  Eigen::Vector3d n;
  double d;
  roadPlane(0.0, 0.0, n, d);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 49; ++i)  // a 7 x 7 grid
    points.push_back(onPlane(n, d, -1.8 + 0.6 * (i % 7), 5.0 + 3.0 * (i / 7), 0.0));
  Eigen::Vector3d found;
  double distance = 0.0;
  EXPECT_FALSE(ransacPlane(points, 0.05, found, distance));
  points.push_back(onPlane(n, d, 0.3, 27.0, 0.0));  // 50: enough
  EXPECT_TRUE(ransacPlane(points, 0.05, found, distance));
}
