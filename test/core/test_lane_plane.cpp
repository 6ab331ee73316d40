// Lane plane: exact normal and offset from three points, degenerate input, robust fit.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/lane_plane.h"

namespace rgbd_lane_detector {
namespace {

TEST(LanePlane, ExactFromThreePointsOrientedTowardTheCamera) {
  // road 1.5 m below a level camera: y = 1.5, normal toward the camera (0, -1, 0), d = 1.5
  const Eigen::Vector3f a1(-1.8f, 1.5f, 6.f), b(1.8f, 1.5f, 6.f), a2(1.8f, 1.5f, 30.f);
  PlaneEstimate pl;
  ASSERT_TRUE(planeFromThreePoints(a1, b, a2, pl));
  EXPECT_NEAR(pl.normal.x(), 0.0, 1e-9);
  EXPECT_NEAR(pl.normal.y(), -1.0, 1e-9);
  EXPECT_NEAR(pl.normal.z(), 0.0, 1e-9);
  EXPECT_NEAR(pl.distance, 1.5, 1e-6);
  EXPECT_EQ(pl.support.size(), 3u);
  // the order of the points does not flip the orientation
  ASSERT_TRUE(planeFromThreePoints(a1, a2, b, pl));
  EXPECT_NEAR(pl.normal.y(), -1.0, 1e-9);
  EXPECT_NEAR(pl.distance, 1.5, 1e-6);
  // tilted plane: n = (0, -cos t, -sin t), d = h
  const double t = 0.1, h = 1.3;
  const Eigen::Vector3d n(0, -std::cos(t), -std::sin(t));
  auto on = [&](double x, double z) {  // point of the plane with given x and z
    const double y = (-h - n.z() * z) / n.y();
    return Eigen::Vector3f(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
  };
  ASSERT_TRUE(planeFromThreePoints(on(-2, 5), on(2, 5), on(2, 25), pl));
  EXPECT_LT((pl.normal - n).norm(), 1e-5);
  EXPECT_NEAR(pl.distance, h, 1e-5);
}

TEST(LanePlane, DegenerateInputGivesAnInvalidPlaneNotNaN) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  PlaneEstimate pl;
  // collinear
  EXPECT_FALSE(planeFromThreePoints({0, 1, 5}, {0, 1, 10}, {0, 1, 20}, pl));
  EXPECT_TRUE(pl.normal.allFinite());
  EXPECT_TRUE(std::isfinite(pl.distance));
  // coincident
  EXPECT_FALSE(planeFromThreePoints({1, 1, 5}, {1, 1, 5}, {2, 1, 9}, pl));
  // invalid depth
  EXPECT_FALSE(planeFromThreePoints({nan, nan, nan}, {1, 1, 5}, {2, 1, 9}, pl));
  EXPECT_TRUE(pl.normal.allFinite());
  // plane through the camera centre
  EXPECT_FALSE(planeFromThreePoints({0, 0, 5}, {1, 0, 5}, {0, 0, 9}, pl));
  EXPECT_FALSE(pl.valid);
}

TEST(LanePlane, LeastSquaresRejectsOutliers) {
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 20; ++i) {
    pts.emplace_back(-1.8f, 1.5f, 5.f + i);
    pts.emplace_back(1.8f, 1.5f + 0.01f * ((i % 3) - 1), 5.f + i);
  }
  pts.emplace_back(1.8f, 0.2f, 12.f);  // bright stripe on a truck, 1.3 m above the road
  pts.emplace_back(-1.7f, 0.0f, 15.f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  pts.emplace_back(nan, nan, nan);
  PlaneEstimate pl;
  ASSERT_TRUE(fitPlaneLeastSquares(pts, 0.1, 3, pl));
  EXPECT_LT(std::acos(std::min(1.0, -pl.normal.y())), 0.01);
  EXPECT_NEAR(pl.distance, 1.5, 0.01);
  EXPECT_EQ(pl.support.size(), 40u);
  EXPECT_LT(pl.rms, 0.01);
  // collinear points: invalid
  std::vector<Eigen::Vector3f> line;
  for (int i = 0; i < 10; ++i) line.emplace_back(1.8f, 1.5f, 5.f + i);
  EXPECT_FALSE(fitPlaneLeastSquares(line, 0.1, 3, pl));
  EXPECT_FALSE(fitPlaneLeastSquares({}, 0.1, 3, pl));
}

}  // namespace
}  // namespace rgbd_lane_detector
