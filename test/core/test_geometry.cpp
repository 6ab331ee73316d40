// The geometry vocabulary (types.h Intrinsics, geometry.h) against hand-computed values of a
// camera 1.5 m above a flat road.
#include <gtest/gtest.h>

#include <cmath>

#include "rgbd_lane_detector/geometry.h"

namespace rld = rgbd_lane_detector;

namespace {

rld::Intrinsics camera() {
  rld::Intrinsics K;
  K.fx = 500.0;
  K.fy = 480.0;
  K.cx = 320.0;
  K.cy = 190.0;
  return K;
}

// y down in the optical frame: the road is y = h below a level camera, n toward the camera.
rld::PlaneEstimate levelRoad(double h) {
  rld::PlaneEstimate p;
  p.valid = true;
  p.normal = Eigen::Vector3d(0.0, -1.0, 0.0);
  p.distance = h;
  return p;
}

// The same road seen by a camera pitched down by a (rad): up has a backward component then.
rld::PlaneEstimate pitchedRoad(double h, double a) {
  rld::PlaneEstimate p = levelRoad(h);
  p.normal = Eigen::Vector3d(0.0, -std::cos(a), -std::sin(a));
  return p;
}

}  // namespace

TEST(Intrinsics, RayThroughAPixelHasUnitDepthAndProjectsBack) {
  const rld::Intrinsics K = camera();
  const Eigen::Vector3d r = K.ray(420.0, 286.0);
  EXPECT_DOUBLE_EQ(r.x(), 100.0 / 500.0);
  EXPECT_DOUBLE_EQ(r.y(), 96.0 / 480.0);
  EXPECT_DOUBLE_EQ(r.z(), 1.0);
  const cv::Point2d px = K.project(Eigen::Vector3d(7.0 * r));
  EXPECT_NEAR(px.x, 420.0, 1e-9);
  EXPECT_NEAR(px.y, 286.0, 1e-9);
  // the principal point is the optical axis; float points project the same
  const cv::Point2d c = K.project(Eigen::Vector3f(0.0f, 0.0f, 3.0f));
  EXPECT_DOUBLE_EQ(c.x, 320.0);
  EXPECT_DOUBLE_EQ(c.y, 190.0);
}

TEST(Intrinsics, EqualityComparesEveryField) {
  rld::Intrinsics a = camera(), b = camera();
  EXPECT_TRUE(a == b);
  b.cy += 1e-12;
  EXPECT_TRUE(a != b);
}

TEST(PixelLayout, ChannelsAndColourBytes) {
  EXPECT_EQ(rld::pixelLayout(rld::PixelFormat::kBgr8).channels, 3);
  EXPECT_EQ(rld::pixelLayout(rld::PixelFormat::kBgr8).r, 2);
  EXPECT_EQ(rld::pixelLayout(rld::PixelFormat::kRgb8).r, 0);
  EXPECT_EQ(rld::pixelLayout(rld::PixelFormat::kRgba8).channels, 4);
  EXPECT_EQ(rld::pixelLayout(rld::PixelFormat::kBgra8).b, 0);
  EXPECT_EQ(rld::pixelLayout(rld::PixelFormat::kMono8).channels, 1);
}

TEST(Plane, DistanceIsSignedTowardTheCamera) {
  const rld::PlaneEstimate road = levelRoad(1.5);
  EXPECT_DOUBLE_EQ(rld::planeDistance(road, Eigen::Vector3d(0.0, 0.0, 0.0)), 1.5);
  EXPECT_DOUBLE_EQ(rld::planeDistance(road, Eigen::Vector3d(2.0, 1.5, 9.0)), 0.0);
  EXPECT_DOUBLE_EQ(rld::planeDistance(road, Eigen::Vector3f(0.0f, 1.75f, 4.0f)), -0.25);
}

TEST(Plane, RayMeetsTheRoadBelowTheHorizonOnly) {
  const rld::Intrinsics K = camera();
  const rld::PlaneEstimate road = levelRoad(1.5);
  double z = -1.0;
  // 48 rows below the principal point: ray.y = 0.1, the road 15 m ahead
  ASSERT_TRUE(rld::rayPlaneDepth(road, K.ray(320.0, 238.0), z));
  EXPECT_DOUBLE_EQ(z, 15.0);
  EXPECT_DOUBLE_EQ(rld::roadPixelsPerMetre(K, road, K.ray(320.0, 238.0)), 500.0 / 15.0);
  // at and above the horizon the ray never meets the road; depth is untouched
  EXPECT_FALSE(rld::rayPlaneDepth(road, K.ray(320.0, 190.0), z));
  EXPECT_FALSE(rld::rayPlaneDepth(road, K.ray(320.0, 100.0), z));
  EXPECT_DOUBLE_EQ(z, 15.0);
  EXPECT_EQ(rld::roadPixelsPerMetre(K, road, K.ray(320.0, 100.0)), 0.0);
  // 0.3 m across the road 15 m ahead: 500 * 0.3 / 15 = 10 px, either way across; none above
  // the horizon
  EXPECT_NEAR(rld::roadPixelsAcross(K, road, K.ray(320.0, 238.0), 0.3), 10.0, 1e-12);
  EXPECT_NEAR(rld::roadPixelsAcross(K, road, K.ray(100.0, 238.0), -0.3), -10.0, 1e-12);
  EXPECT_EQ(rld::roadPixelsAcross(K, road, K.ray(320.0, 100.0), 0.3), 0.0);
  // pitched down by 10 deg the horizon row moves up by fy tan(10 deg)
  const double a = 10.0 * M_PI / 180.0;
  const rld::PlaneEstimate pitched = pitchedRoad(1.5, a);
  const double horizon = 190.0 - 480.0 * std::tan(a);
  EXPECT_TRUE(rld::rayPlaneDepth(pitched, K.ray(320.0, horizon + 1.0), z));
  EXPECT_FALSE(rld::rayPlaneDepth(pitched, K.ray(320.0, horizon - 1.0), z));
}

TEST(RoadFrame, Rep103AxesOfALevelCamera) {
  const rld::RoadFrame f = rld::RoadFrame::fromPlane(levelRoad(1.5));
  ASSERT_TRUE(f.valid());
  EXPECT_TRUE(f.forward().isApprox(Eigen::Vector3d(0.0, 0.0, 1.0)));  // optical z
  EXPECT_TRUE(f.left().isApprox(Eigen::Vector3d(-1.0, 0.0, 0.0)));    // optical -x
  EXPECT_TRUE(f.up().isApprox(Eigen::Vector3d(0.0, -1.0, 0.0)));      // optical -y
  EXPECT_TRUE(f.origin().isApprox(Eigen::Vector3d(0.0, 1.5, 0.0)));
  // a road point 10 m ahead and 1 m to the right of the camera
  const Eigen::Vector2d q = f.toRoad(Eigen::Vector3d(1.0, 1.5, 10.0));
  EXPECT_NEAR(q.x(), 10.0, 1e-12);
  EXPECT_NEAR(q.y(), -1.0, 1e-12);
  EXPECT_TRUE(f.toCamera(q.x(), q.y()).isApprox(Eigen::Vector3d(1.0, 1.5, 10.0)));
  // the camera is 1.5 m above the origin; a point 0.2 m above the road has height 0.2
  const Eigen::Isometry3d T = f.roadFromCamera();
  EXPECT_TRUE((T * Eigen::Vector3d::Zero()).isApprox(Eigen::Vector3d(0.0, 0.0, 1.5)));
  EXPECT_TRUE((T * Eigen::Vector3d(-2.0, 1.3, 8.0)).isApprox(Eigen::Vector3d(8.0, 2.0, 0.2)));
}

TEST(RoadFrame, PitchedCameraStillLooksAlongTheRoad) {
  const double a = 8.0 * M_PI / 180.0;
  const rld::RoadFrame f = rld::RoadFrame::fromPlane(pitchedRoad(1.4, a));
  ASSERT_TRUE(f.valid());
  // forward and left lie in the road; the three axes are orthonormal and right-handed
  EXPECT_NEAR(f.forward().dot(f.up()), 0.0, 1e-12);
  EXPECT_NEAR(f.left().dot(f.up()), 0.0, 1e-12);
  EXPECT_NEAR(f.forward().dot(f.left()), 0.0, 1e-12);
  EXPECT_TRUE(f.forward().cross(f.left()).isApprox(f.up()));
  // the optical axis pitched down by a: forward is (0, -sin a, cos a), left the camera's -x
  EXPECT_TRUE(f.forward().isApprox(Eigen::Vector3d(0.0, -std::sin(a), std::cos(a))));
  EXPECT_TRUE(f.left().isApprox(Eigen::Vector3d(-1.0, 0.0, 0.0)));
  // a road point 20 m ahead, 3 m left: on the plane, at depth 20 cos a + 1.4 sin a
  const rld::PlaneEstimate road = pitchedRoad(1.4, a);
  const Eigen::Vector3d p = f.toCamera(20.0, 3.0);
  EXPECT_NEAR(rld::planeDistance(road, p), 0.0, 1e-12);
  EXPECT_NEAR(p.z(), 20.0 * std::cos(a) + 1.4 * std::sin(a), 1e-12);
  EXPECT_NEAR(p.x(), -3.0, 1e-12);
  // its pixel's ray meets the plane at that depth, and the road coordinates come back
  const rld::Intrinsics K = camera();
  const cv::Point2d px = K.project(p);
  double z = 0.0;
  ASSERT_TRUE(rld::rayPlaneDepth(road, K.ray(px.x, px.y), z));
  EXPECT_NEAR(z, p.z(), 1e-9);
  EXPECT_TRUE(f.toRoad(z * K.ray(px.x, px.y)).isApprox(Eigen::Vector2d(20.0, 3.0), 1e-9));
}

TEST(RoadFrame, InvalidWithoutAPlaneOrLookingStraightDown) {
  EXPECT_FALSE(rld::RoadFrame::fromPlane(rld::PlaneEstimate()).valid());
  rld::PlaneEstimate down = levelRoad(1.5);
  down.normal = Eigen::Vector3d(0.0, 0.0, -1.0);  // optical axis perpendicular to the road
  EXPECT_FALSE(rld::RoadFrame::fromPlane(down).valid());
  EXPECT_TRUE(rld::RoadFrame().roadFromCamera().isApprox(Eigen::Isometry3d::Identity()));
}

TEST(LineSums, FitsTheLineThroughItsPointsExactly) {
  // y = 2 + 0.5 x at x = -1, 0, 3, 6: sums of small binary fractions, exact in double
  rld::LineSums sums;
  for (double x : {-1.0, 0.0, 3.0, 6.0}) sums.add(x, 2.0 + 0.5 * x);
  double a = 0.0, b = 0.0;
  ASSERT_TRUE(sums.fit(1e-9, a, b));
  EXPECT_DOUBLE_EQ(b, 0.5);
  EXPECT_DOUBLE_EQ(a, 2.0);
  EXPECT_DOUBLE_EQ(sums.n, 4.0);
}

TEST(LineSums, LeastSquaresThroughScatteredPoints) {
  // (0,0), (1,1), (2,1), (3,3): slope (4*12 - 6*5) / (4*14 - 6^2) = 0.9, a = (5 - 0.9*6) / 4
  rld::LineSums sums;
  const double pts[4][2] = {{0, 0}, {1, 1}, {2, 1}, {3, 3}};
  for (const auto& p : pts) sums.add(p[0], p[1]);
  double a = 0.0, b = 0.0;
  ASSERT_TRUE(sums.fit(1e-9, a, b));
  EXPECT_NEAR(b, 0.9, 1e-12);
  EXPECT_NEAR(a, -0.1, 1e-12);
}

TEST(LineSums, NoSpreadInXGivesTheMeanAndFalse) {
  // every point on one x (a vertical line): no slope; a is the mean y
  rld::LineSums sums;
  for (double y : {1.0, 2.0, 6.0}) sums.add(4.0, y);
  double a = -1.0, b = -1.0;
  EXPECT_FALSE(sums.fit(1e-9, a, b));
  EXPECT_EQ(b, 0.0);
  EXPECT_DOUBLE_EQ(a, 3.0);
}

TEST(LineSums, FloatPointsMultiplyAsFloats) {
  // the products of float coordinates are float products (as the pixel fits always took them)
  rld::LineSums sums;
  const float x = 1.1f;
  sums.add(x, x);
  EXPECT_EQ(sums.sxx, static_cast<double>(x * x));
  EXPECT_EQ(sums.sx, static_cast<double>(x));
}
