// Road edges from depth: a kerb and its sidewalk found where the road ends, whatever they look
// like; cars beside the road, a vehicle's rear face, missing and sparse depth are no kerb.
#include <algorithm>
#include <cmath>
#include <functional>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/road_edge_finder.h"
#include "synthetic_scene.h"

namespace rgbd_lane_detector {
namespace {

constexpr int kW = 640, kH = 380;
const Intrinsics kK{266.37, 266.37, 320.0, 190.0};

struct Scene : test::DepthScene {
  Scene() {
    image_width = kW;
    image_height = kH;
    K = kK;
  }
  PlaneEstimate plane() const {
    PlaneEstimate p;
    p.valid = true;
    p.normal = normal();
    p.distance = height;
    return p;
  }
};

const cv::Range kRows(static_cast<int>(0.41 * kH), kH);

// Lateral position (m, right) of the road point under an input pixel.
double lateralOf(const Scene& s, const cv::Point2f& px) {
  const Eigen::Vector3d ray((px.x - kK.cx) / kK.fx, (px.y - kK.cy) / kK.fy, 1.0);
  const double t = -s.height / s.normal().dot(ray);
  return ray.x() * t;
}

struct Fixture {
  RoadEdgeFinder finder;
  RoadEdgeLine left, right;
  void find(const Scene& scene, const cv::Mat& points) {
    finder.find(points, nullptr, kRows, kK, cv::Mat(), cv::Mat(), scene.plane(), RoadEdgeSettings(),
                left, right);
  }
};

TEST(RoadEdgeFinder, KerbWithASidewalkIsTheRoadsEdge) {
  // a 0.12 m kerb 2.6 m right of the camera, a 3 m sidewalk behind it
  Scene scene;
  scene.boxes = {{2.6, 5.6, 0.0, 200.0, 0.12}};
  Fixture f;
  f.find(scene, scene.render());
  ASSERT_TRUE(f.right.found);
  EXPECT_FALSE(f.left.found);
  EXPECT_NEAR(f.right.offset, -2.6, 0.05);  // y left
  EXPECT_NEAR(f.right.heading, 0.0, 0.01);
  ASSERT_GE(f.right.pixels.size(), 8u);
  ASSERT_EQ(f.right.pixels.size(), f.right.points.size());
  for (const auto& px : f.right.pixels) EXPECT_NEAR(lateralOf(scene, px), 2.6, 0.05) << px;
  for (size_t i = 1; i < f.right.pixels.size(); ++i)
    EXPECT_LE(f.right.pixels[i].y, f.right.pixels[i - 1].y);  // near to far
}

TEST(RoadEdgeFinder, KerbRisesFromACamberedGutter) {
  // the road falls 8 cm toward its gutter over the last metre before a 0.12 m kerb at 2.5 m, and
  // shrubs 0.5 m high stand on the sidewalk 0.5 m behind the kerb
  Scene scene;
  scene.camber = [](double x) { return x > 1.5 ? 0.08 * std::min(1.0, x - 1.5) : 0.0; };
  scene.boxes = {{2.5, 6.0, 0.0, 200.0, 0.12 - 0.08}, {3.0, 6.0, 0.0, 200.0, 0.5}};
  Fixture f;
  f.find(scene, scene.render());
  ASSERT_TRUE(f.right.found);
  for (const auto& px : f.right.pixels) EXPECT_NEAR(lateralOf(scene, px), 2.5, 0.1) << px;
}

// A surface rising by @p rise over @p width from the lateral position @p x0 (m, right), flat
// beyond: a rolled kerb, a verge. (The scene's surface must slope less than about 0.6 here: it
// is found by a fixed-point iteration along each pixel ray.)
std::function<double(double)> ramp(double x0, double width, double rise) {
  return [=](double x) { return -rise * std::min(1.0, std::max(0.0, (x - x0) / width)); };
}

TEST(RoadEdgeFinder, RolledKerbEndsTheRoadAtItsToe) {
  // no step between neighbouring points: 12 cm over 0.3-0.6 m, 2.5 m right of the camera
  for (double width : {0.3, 0.45, 0.6}) {
    Scene scene;
    scene.camber = ramp(2.5, width, 0.12);
    Fixture f;
    f.find(scene, scene.render());
    ASSERT_TRUE(f.right.found) << width;
    EXPECT_FALSE(f.left.found);
    EXPECT_NEAR(f.right.offset, -2.5, 0.08) << width;
    ASSERT_GE(f.right.pixels.size(), 8u);
    // at the toe, where the road ends, not up the rise (half-way: 2.5 + width / 2)
    for (const auto& px : f.right.pixels) EXPECT_NEAR(lateralOf(scene, px), 2.5, 0.1) << px;
    for (size_t i = 1; i < f.right.pixels.size(); ++i)
      EXPECT_LE(f.right.pixels[i].y, f.right.pixels[i - 1].y);  // near to far
  }
}

TEST(RoadEdgeFinder, VergeRisingBeyondAGutterEndsTheRoadAtTheGutter) {
  // the road falls 6 cm toward a gutter 2.3 m left over its last metre, and a grass verge
  // rises 15 cm from it over 0.5 m, with LiDAR-like noise
  Scene scene;
  scene.camber = [](double x) {
    if (x > -1.3) return 0.0;
    if (x > -2.3) return 0.06 * (-1.3 - x);
    return 0.06 - 0.15 * std::min(1.0, (-2.3 - x) / 0.5);
  };
  scene.noise = 0.005;
  Fixture f;
  f.find(scene, scene.render());
  ASSERT_TRUE(f.left.found);
  EXPECT_FALSE(f.right.found);
  EXPECT_NEAR(f.left.offset, 2.3, 0.1);
}

TEST(RoadEdgeFinder, ACrownRutsAndALoneBumpAreNoEdge) {
  // a road crowned 4 cm over 1.75 m to the left, 2.5 cm ruts under the wheels (+-0.8 m), and a
  // seam's rim 6 cm high and 10 cm wide 2 m right: nothing rises to stay
  Scene scene;
  scene.camber = [](double x) {
    const double crown = x < 0.0 ? 0.04 * std::min(1.0, -x / 1.75) : 0.0;
    const double rut = 0.025 * std::max(0.0, 1.0 - std::fabs(std::fabs(x) - 0.8) / 0.25);
    const double rim = std::fabs(x - 2.05) < 0.05 ? 0.06 : 0.0;
    return rut - crown - rim;
  };
  Fixture f;
  f.find(scene, scene.render());
  EXPECT_FALSE(f.left.found);
  EXPECT_FALSE(f.right.found);
}

TEST(RoadEdgeFinder, CarsAndARearFaceAreNoKerb) {
  // parked cars along the left (1.5 m high, gaps between them), a van ahead in the next lane
  // whose rear face is a vertical wall: neither is a sidewalk
  Scene scene;
  for (double z = 4.0; z < 40.0; z += 7.0) scene.boxes.push_back({-4.8, -3.0, z, z + 4.5, 1.5});
  scene.boxes.push_back({1.9, 3.9, 12.0, 20.0, 2.5});
  Fixture f;
  f.find(scene, scene.render());
  EXPECT_FALSE(f.left.found);
  EXPECT_FALSE(f.right.found);
}

TEST(RoadEdgeFinder, SparseAndNoisyDepthStillFindTheKerb) {
  // a LiDAR's scan lines: depth on every 4th row only, 1 cm of noise
  Scene scene;
  scene.boxes = {{-5.0, -2.2, 0.0, 200.0, 0.15}};
  scene.noise = 0.01;
  scene.hole = [](int, int v) { return v % 4 != 0; };
  Fixture f;
  f.find(scene, scene.render());
  ASSERT_TRUE(f.left.found);
  EXPECT_NEAR(f.left.offset, 2.2, 0.1);
  EXPECT_FALSE(f.right.found);
}

TEST(RoadEdgeFinder, KerbBeyondUnmeasuredRoad) {
  // no depth on the last 0.8 m of road before a 0.12 m kerb 2.6 m right, nor on its face (a
  // LiDAR's gap): no point within a rise's reach of its top, the foot lies somewhere in the
  // unmeasured stretch
  Scene scene;
  scene.boxes = {{2.6, 5.6, 0.0, 200.0, 0.12}};
  scene.hole = [&scene](int u, int v) {
    if (v <= kK.cy + 2) return false;
    const double x = lateralOf(scene, cv::Point2f(static_cast<float>(u), static_cast<float>(v)));
    return x > 1.8 && x < 2.9;  // (the face's pixels meet the road up to 2.83 m)
  };
  Fixture f;
  f.find(scene, scene.render());
  ASSERT_TRUE(f.right.found);
  EXPECT_GE(-f.right.offset, 1.8);
  EXPECT_LE(-f.right.offset, 2.6);
}

TEST(RoadEdgeFinder, NothingWithoutDepthOrPlane) {
  Scene scene;
  scene.boxes = {{2.6, 5.6, 0.0, 200.0, 0.12}};
  Fixture f;
  const cv::Mat none(kH, kW, CV_32FC3, cv::Scalar::all(std::nanf("")));
  f.find(scene, none);
  EXPECT_FALSE(f.left.found || f.right.found);
  f.finder.find(scene.render(), nullptr, kRows, kK, cv::Mat(), cv::Mat(), PlaneEstimate(),
                RoadEdgeSettings(), f.left, f.right);
  EXPECT_FALSE(f.left.found || f.right.found);
  // the kerb's rows without measured depth (the road plane filled in there) give no edge
  cv::Mat filled(kH, kW, CV_8UC1, cv::Scalar(255));
  f.finder.find(scene.render(), &filled, kRows, kK, cv::Mat(), cv::Mat(), scene.plane(),
                RoadEdgeSettings(), f.left, f.right);
  EXPECT_FALSE(f.right.found);
}

}  // namespace
}  // namespace rgbd_lane_detector
