// Whole pipeline on rendered roads: both markers found, plane within 1 deg and 5 cm of truth.
#include <cmath>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/lane_detector.h"
#include "synthetic_scene.h"

namespace rgbd_lane_detector {
namespace {

using test::RoadScene;

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::fabs(a.normalized().dot(b.normalized())))) * 180.0 / M_PI;
}

Frame makeFrame(const RoadScene& scene, cv::Mat& bgr, cv::Mat& depth) {
  scene.render(bgr, depth);
  Frame f;
  f.colour = bgr;
  f.format = PixelFormat::kBgr8;
  f.depth = depth;
  f.depth_scale = 0.001;
  f.intrinsics = scene.K;
  return f;
}

// Mean lateral distance of a side's 3D points to the true marker centre line.
double meanLateralError(const MarkerTrace& m, double marker_x) {
  double sum = 0;
  int n = 0;
  for (const auto& p : m.points) {
    if (!p.allFinite()) continue;
    sum += std::fabs(p.x() - marker_x);
    ++n;
  }
  return n ? sum / n : 1e9;
}

TEST(LaneDetector, StraightRoadPaperMode) {
  RoadScene scene;
  cv::Mat bgr, depth;
  const Frame f = makeFrame(scene, bgr, depth);
  LaneDetector det;
  Result r;
  ASSERT_EQ(det.detect(f, r), Status::kOk);
  ASSERT_TRUE(r.left.found);
  ASSERT_TRUE(r.right.found);
  EXPECT_GE(r.left.num_valid_points, 5);
  EXPECT_GE(r.right.num_valid_points, 5);
  EXPECT_LT(meanLateralError(r.left, scene.leftMarkerX()), 0.15);
  EXPECT_LT(meanLateralError(r.right, scene.rightMarkerX()), 0.15);
  ASSERT_TRUE(r.plane.valid);
  EXPECT_LT(angleDeg(r.plane.normal, scene.planeNormal()), 1.0);
  EXPECT_GT(r.plane.normal.dot(scene.planeNormal()), 0.0);  // toward the camera
  EXPECT_NEAR(r.plane.distance, scene.planeDistance(), 0.05);
  // left marker points lie left of the right ones
  EXPECT_LT(r.left.seed.x, r.right.seed.x);
}

TEST(LaneDetector, StraightRoadImprovedModeWithDashes) {
  RoadScene scene;
  scene.right_dashed = true;
  cv::Mat bgr, depth;
  const Frame f = makeFrame(scene, bgr, depth);
  LaneDetector det(Params::improved());
  Result r;
  for (int i = 0; i < 3; ++i) {  // templates adapt over frames
    ASSERT_EQ(det.detect(f, r), Status::kOk);
  }
  ASSERT_TRUE(r.left.found);
  ASSERT_TRUE(r.right.found);
  EXPECT_LT(meanLateralError(r.left, scene.leftMarkerX()), 0.15);
  EXPECT_LT(meanLateralError(r.right, scene.rightMarkerX()), 0.15);
  ASSERT_TRUE(r.plane.valid);
  EXPECT_LT(angleDeg(r.plane.normal, scene.planeNormal()), 1.0);
  EXPECT_NEAR(r.plane.distance, scene.planeDistance(), 0.05);
}

}  // namespace
}  // namespace rgbd_lane_detector
