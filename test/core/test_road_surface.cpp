// Road surface from depth: a robust plane over the searched rows, with cars, raised sidewalks,
// missing depth near the car, noise and a crest.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/depth_points.h"
#include "rgbd_lane_detector/road_surface.h"
#include "simd.h"
#include "synthetic_scene.h"

namespace rgbd_lane_detector {

// RoadSurface's friend: the grid's samples as collectGrid() takes them, and the counts that
// choose the grid (they predict its samples without taking them).
struct RoadSurfaceProbe {
  struct Counts {
    int near;      // samples within fit_range
    int extended;  // and the far ones within twice fit_range (they join the near ones when few)
  };
  static Counts collected(RoadSurface& road, const cv::Mat& points, const cv::Range& rows,
                          const RoadSurfaceSettings& s, int stride) {
    road.collectGrid(points, rows, s, stride);
    const float fit_range = static_cast<float>(s.fit_range), extended = 2.0f * fit_range;
    auto within = [](float range) {
      return [range](const RoadSurface::Sample& a) { return a.p.z() <= range; };
    };
    const int near = static_cast<int>(
        std::count_if(road.near_.begin(), road.near_.end(), within(fit_range)));
    const int joined = static_cast<int>(
        std::count_if(road.far_.begin(), road.far_.end(), within(extended)));
    return {near, static_cast<int>(road.near_.size()) + joined};
  }
  static Counts counted(const RoadSurface& road, const cv::Mat& points, const cv::Range& rows,
                        const RoadSurfaceSettings& s, int stride, int& corridor) {
    return {road.nearGridCount(points, rows, s, stride),
            road.extendedGridCount(points, rows, s, stride, corridor)};
  }
};

namespace {

constexpr int kW = 320, kH = 190;
const Intrinsics kK{133.0, 133.0, 160.0, 95.0};
using Box = test::DepthBox;

// Camera 1.5 m above a road (pitched down 0.05 rad) at a quarter of 1280x760.
struct Scene : test::DepthScene {
  Scene() {
    image_width = kW;
    image_height = kH;
    K = kK;
  }
};

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::fabs(a.normalized().dot(b.normalized())))) * 180.0 / M_PI;
}

RoadSurfaceSettings settings() {
  RoadSurfaceSettings s;
  s.up = Eigen::Vector3d(0, -1, 0);
  return s;
}

const cv::Range kRows(static_cast<int>(0.41 * kH), kH);

TEST(RoadSurface, FlatRoadExactly) {
  Scene scene;
  const cv::Mat pts = scene.render();
  RoadSurface road;
  PlaneEstimate plane;
  ASSERT_TRUE(road.fit(pts, kRows, settings(), PlaneEstimate(), plane));
  EXPECT_LT(angleDeg(plane.normal, scene.normal()), 0.01);
  EXPECT_GT(plane.normal.dot(scene.normal()), 0.0);  // toward the camera
  EXPECT_NEAR(plane.distance, scene.height, 1e-3);
  EXPECT_FALSE(plane.support.empty());
  EXPECT_GE(road.validRange(), 40.0);  // a level road holds as far as the depth reaches
  EXPECT_LT(road.noiseGrowth(), 1e-4);  // exact depth: the band stays at its floor
}

TEST(RoadSurface, NoiseCarsAndRaisedSidewalks) {
  Scene scene;
  scene.noise = 0.01;
  // a car ahead (1.5 m tall, 2 m wide, 12-16 m) and 0.12 m sidewalks beyond 3 m each side:
  // both outliers
  scene.boxes = {{-0.5, 1.5, 12.0, 16.0, 1.5}, {3.0, 100.0, 0.0, 200.0, 0.12},
                 {-100.0, -3.0, 0.0, 200.0, 0.12}};
  RoadSurface road;
  PlaneEstimate plane;
  ASSERT_TRUE(road.fit(scene.render(), kRows, settings(), PlaneEstimate(), plane));
  // (a least-squares plane of all these points is off by degrees and decimetres)
  EXPECT_LT(angleDeg(plane.normal, scene.normal()), 0.5);
  EXPECT_NEAR(plane.distance, scene.height, 0.02);
}

TEST(RoadSurface, NoDepthNearTheCar) {
  // LiDAR and stereo often have nothing in the bottom rows: the road further ahead still gives
  // the plane
  Scene scene;
  scene.hole = [](int, int v) { return v > kH * 3 / 4; };
  RoadSurface road;
  PlaneEstimate plane;
  ASSERT_TRUE(road.fit(scene.render(), kRows, settings(), PlaneEstimate(), plane));
  EXPECT_LT(angleDeg(plane.normal, scene.normal()), 0.05);
  EXPECT_NEAR(plane.distance, scene.height, 0.005);
}

TEST(RoadSurface, FillFromRoadPlaneExtendsOnlyARoadSeenToContinue) {
  // no depth in the bottom quarter; a car 2-5 m ahead on the left, its back in the hole, hides
  // the road in some columns
  Scene scene;
  scene.boxes = {{-2.5, -0.8, 2.0, 5.0, 1.5}};
  const int hole_row = kH * 3 / 4;
  scene.hole = [hole_row](int, int v) { return v > hole_row; };
  cv::Mat pts = scene.render();
  RoadSurface road;
  PlaneEstimate plane;
  ASSERT_TRUE(road.fit(pts, kRows, settings(), PlaneEstimate(), plane));
  cv::Mat filled;
  const int count = road.extendToCamera(pts, kRows, kK, plane, 0.04, 0.0015, filled);
  EXPECT_GT(count, 0);
  EXPECT_EQ(cv::countNonZero(filled), count);
  const cv::Mat truth = Scene().render();  // the road without holes or the car
  int checked = 0;
  for (int v = hole_row + 1; v < kH; ++v) {
    for (int u = 0; u < kW; ++u) {
      const cv::Vec3f& p = pts.at<cv::Vec3f>(v, u);
      if (filled.at<uint8_t>(v, u) == 0) {
        EXPECT_TRUE(std::isnan(p[2])) << u << "," << v;  // left alone: still no depth
        continue;
      }
      const cv::Vec3f& t = truth.at<cv::Vec3f>(v, u);
      EXPECT_NEAR(p[2], t[2], 0.01 * t[2]) << u << "," << v;  // where the road is
      ++checked;
    }
  }
  EXPECT_GT(checked, kW * (kH - hole_row - 1) / 2);
  // the columns whose nearest depth is the car's back are not extended
  const int car_column = static_cast<int>(kK.cx + kK.fx * -1.6 / 2.0);
  EXPECT_EQ(filled.at<uint8_t>(kH - 1, car_column), 0);
  // without a plane: nothing
  EXPECT_EQ(road.extendToCamera(pts, kRows, kK, PlaneEstimate(), 0.04, 0.0015, filled), 0);
  EXPECT_EQ(cv::countNonZero(filled), 0);
}

// The fill's rows are a kernel of every SIMD target: the same points (bits, NaN left alone) and
// mask as the scalar target, on a width that leaves a tail of columns to the per-pixel code.
// Every third column has no depth at all (a sparse LiDAR's): most vectors fill only some of
// their columns and leave the others' points as they are.
TEST(RoadSurface, FillGivesTheSameBitsOnEveryTarget) {
  Scene scene;
  scene.boxes = {{-2.5, -0.8, 2.0, 5.0, 1.5}};
  const int hole_row = kH * 3 / 4;
  scene.hole = [hole_row](int u, int v) {
    return v > hole_row - (u % 7 == 0 ? 9 : 0) || u % 3 == 1;
  };
  const cv::Mat full = scene.render();
  RoadSurface road;
  PlaneEstimate plane;
  ASSERT_TRUE(road.fit(full, kRows, settings(), PlaneEstimate(), plane));
  const cv::Mat rendered = full(cv::Rect(0, 0, kW - 3, kH)).clone();
  cv::Mat ref_pts, ref_filled;
  int ref_count = -1;
  const std::vector<simd::Target> targets = simd::availableTargets();  // the scalar one last
  ASSERT_EQ(targets.back(), simd::kScalar);
  for (auto it = targets.rbegin(); it != targets.rend(); ++it) {  // the scalar one first
    const simd::Target target = *it;
    SCOPED_TRACE(simd::targetName(target));
    simd::forceTarget(target);
    cv::Mat pts = rendered.clone(), filled;
    const int count = road.extendToCamera(pts, kRows, kK, plane, 0.04, 0.0015, filled);
    if (ref_count < 0) {
      ref_pts = pts;
      ref_filled = filled;
      ref_count = count;
      // the road below the hole in two columns of three, less the car's
      EXPECT_GT(count, (kW - 3) * (kH - hole_row - 1) / 3);
      for (int v = 0; v < pts.rows; ++v)  // the columns without depth stay without
        for (int u = 1; u < pts.cols; u += 3) ASSERT_TRUE(std::isnan(pts.at<cv::Vec3f>(v, u)[2]));
      continue;
    }
    EXPECT_EQ(count, ref_count);
    EXPECT_EQ(std::memcmp(pts.data, ref_pts.data, pts.total() * pts.elemSize()), 0);
    EXPECT_EQ(std::memcmp(filled.data, ref_filled.data, filled.total()), 0);
  }
  simd::forceTarget(simd::kBest);
}

// Columns whose depth ends on different rows (a staircase of 12 rows per 64 columns) and a band
// of columns without any depth: on every target each column fills from the row below its own
// nearest depth, exactly (a row's vectors pass over the columns that fill nothing yet).
TEST(RoadSurface, FillStartsBelowEachColumnsNearestDepth) {
  auto last_row = [](int u) { return kH * 3 / 4 - 12 * (u / 64); };
  auto no_depth = [](int u) { return u >= 100 && u < 160; };
  Scene scene;
  scene.hole = [=](int u, int v) { return v > last_row(u) || no_depth(u); };
  const cv::Mat full = scene.render();
  RoadSurface road;
  PlaneEstimate plane;
  ASSERT_TRUE(road.fit(full, kRows, settings(), PlaneEstimate(), plane));
  for (const simd::Target target : simd::availableTargets()) {
    SCOPED_TRACE(simd::targetName(target));
    simd::forceTarget(target);
    cv::Mat pts = full.clone(), filled;
    const int count = road.extendToCamera(pts, kRows, kK, plane, 0.04, 0.0015, filled);
    int expected = 0;
    for (int v = 0; v < kH; ++v)
      for (int u = 0; u < kW; ++u) {
        const bool fills = !no_depth(u) && v > last_row(u);
        expected += fills;
        ASSERT_EQ(filled.at<uint8_t>(v, u) != 0, fills) << u << "," << v;
      }
    EXPECT_EQ(count, expected);
  }
  simd::forceTarget(simd::kBest);
}

TEST(RoadSurface, SeededByThePreviousPlaneAndDeterministic) {
  Scene scene;
  scene.noise = 0.02;
  const cv::Mat pts = scene.render();
  RoadSurface a, b;
  PlaneEstimate first, again, seeded;
  ASSERT_TRUE(a.fit(pts, kRows, settings(), PlaneEstimate(), first));
  ASSERT_TRUE(b.fit(pts, kRows, settings(), PlaneEstimate(), again));
  EXPECT_EQ(first.normal, again.normal);  // the same input gives the same plane, bit for bit
  EXPECT_EQ(first.distance, again.distance);
  // a previous plane 2 deg and 10 cm off converges onto the road
  PlaneEstimate previous;
  previous.valid = true;
  previous.normal = Eigen::AngleAxisd(2.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()) * scene.normal();
  previous.distance = scene.height + 0.1;
  ASSERT_TRUE(a.fit(pts, kRows, settings(), previous, seeded));
  EXPECT_LT(angleDeg(seeded.normal, scene.normal()), 0.2);
  EXPECT_NEAR(seeded.distance, scene.height, 0.02);
}

// A wet road that returns depth from its paint alone (two lines at x = +-1.7 m, 20 cm wide),
// between 15 cm pavements from |x| = 2 m that return everywhere: the road holds a small share
// of the depth.
// Where the ray of pixel (u, v) meets the road of @p scene: its lateral position x (m, right
// positive); false above the horizon.
bool roadLateral(const Scene& scene, int u, int v, double& x) {
  const double c = std::cos(scene.pitch), sn = std::sin(scene.pitch);
  const Eigen::Vector3d ray((u - kK.cx) / kK.fx, (v - kK.cy) / kK.fy, 1.0);
  const Eigen::Vector3d w(ray.x(), c * ray.y() + sn * ray.z(), -sn * ray.y() + c * ray.z());
  if (!(w.y() > 1e-6)) return false;
  x = w.x() * scene.height / w.y();
  return true;
}

// A road that returns depth only from two painted lines at x = +-1.7 m (half width
// @p paint_half) between |x| = 2 m and @p kerb high platforms beyond; rows below
// @p blind_from (share of the image height) without depth.
Scene wetRoadBetween(double kerb, double paint_half, double blind_from) {
  Scene scene;
  scene.boxes = {{2.0, 100.0, 0.0, 200.0, kerb}, {-100.0, -2.0, 0.0, 200.0, kerb}};
  const Scene geometry = scene;
  scene.hole = [geometry, paint_half, blind_from](int u, int v) {
    if (v > blind_from * kH) return true;
    double x = 0.0;
    if (!roadLateral(geometry, u, v, x)) return false;
    return std::fabs(x) < 2.0 && std::fabs(std::fabs(x) - 1.7) > paint_half;
  };
  return scene;
}

Scene wetRoadBetweenPavements() { return wetRoadBetween(0.15, 0.1, 1.0); }

TEST(RoadSurface, TheMountKeepsARoadSeenMostlyAsPaint) {
  // the vehicle's mount (its up axis and the camera's height above the road) is where the fit
  // starts: from there the plane stays on the road (within the pull of the far pavements, whose
  // tops lie within the band there), and does not follow a last plane that the pavements pulled
  // 2 deg and 10 cm off it onto them (15 cm above the road)
  const Scene scene = wetRoadBetweenPavements();
  const cv::Mat pts = scene.render();
  RoadSurfaceSettings s = settings();
  s.up = scene.normal();
  s.max_tilt_deg = 4.0;
  s.mount_height = scene.height;
  PlaneEstimate previous;
  previous.valid = true;
  previous.normal =
      Eigen::AngleAxisd(2.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()) * scene.normal();
  previous.distance = scene.height + 0.1;
  RoadSurface road;
  PlaneEstimate plane;
  ASSERT_TRUE(road.fit(pts, kRows, s, previous, plane));
  EXPECT_LT(angleDeg(plane.normal, scene.normal()), 0.7);
  EXPECT_NEAR(plane.distance, scene.height, 0.03);
  // the camera's footprint and 10 m ahead lie within 4 cm of the road (the pavement: 15 cm)
  const Eigen::Vector3d ahead = scene.normal().cross(Eigen::Vector3d::UnitX()).normalized();
  for (double x : {0.0, 10.0}) {
    const Eigen::Vector3d p = -scene.height * scene.normal() + x * ahead;  // on the road
    EXPECT_LT(std::fabs(plane.normal.dot(p) + plane.distance), 0.04) << x;
  }
}

TEST(RoadSurface, AMountOffTheRoadFallsBackToTheDepth) {
  // a vehicle frame whose origin is not on the road (0.5 m above it): the mount's plane holds
  // no depth, and the fit finds the road from the depth alone
  Scene scene;
  scene.noise = 0.01;
  RoadSurfaceSettings s = settings();
  s.up = scene.normal();
  s.mount_height = scene.height - 0.5;
  RoadSurface road;
  PlaneEstimate plane;
  ASSERT_TRUE(road.fit(scene.render(), kRows, s, PlaneEstimate(), plane));
  EXPECT_LT(angleDeg(plane.normal, scene.normal()), 0.2);
  EXPECT_NEAR(plane.distance, scene.height, 0.01);
}

TEST(RoadSurface, NotAPlaneThatTheRoadLiesBelow) {
  // no depth in the bottom 30% of the rows (a LiDAR's blind zone, a bonnet), a wet road that
  // returns only from its paint (lines at x = +-1.7 m), and 0.9 m high platforms from |x| = 2 m
  // (a row of parked vans, a loading bay) that return everywhere: the platforms' top is a
  // road-like plane 0.6 m below the camera holding most of the depth, but the road's paint lies
  // beneath it, and nothing lies beneath a road
  Scene scene = wetRoadBetween(0.9, 0.15, 0.7);
  RoadSurface road;
  PlaneEstimate plane;
  // the road's paint alone holds too small a share of the depth to be the road: no plane
  // rather than a wrong one (the platforms' top: 0.6 m, before)
  if (road.fit(scene.render(), kRows, settings(), PlaneEstimate(), plane)) {
    EXPECT_LT(angleDeg(plane.normal, scene.normal()), 0.5);
    EXPECT_NEAR(plane.distance, scene.height, 0.03);
  }
  // with the road returning everywhere, the road
  scene.hole = [](int, int v) { return v > kH * 7 / 10; };
  ASSERT_TRUE(road.fit(scene.render(), kRows, settings(), PlaneEstimate(), plane));
  EXPECT_LT(angleDeg(plane.normal, scene.normal()), 0.5);
  EXPECT_NEAR(plane.distance, scene.height, 0.03);
}

TEST(RoadSurface, CrestEndsTheValidRange) {
  // a crest of 400 m vertical radius: the plane holds near the car; the valid range ends about
  // where the road ahead leaves the fitted plane by 8 cm (5 m steps)
  Scene scene;
  const double R = 400.0;
  scene.crest = [R](double z) { return z > 0 ? z * z / (2.0 * R) : 0.0; };
  RoadSurface road;
  PlaneEstimate plane;
  const RoadSurfaceSettings s = settings();
  ASSERT_TRUE(road.fit(scene.render(), kRows, s, PlaneEstimate(), plane));
  EXPECT_NEAR(plane.distance, scene.height, 0.1);
  // where the true road under the camera's path leaves the fitted plane by 8 cm
  const double c = std::cos(scene.pitch), sn = std::sin(scene.pitch);
  double leaves = 0.0;
  for (double z = s.fit_range; z < 80.0; z += 0.25) {
    const double y = scene.height + z * z / (2.0 * R);  // world: down
    const Eigen::Vector3d p(0.0, c * y - sn * z, sn * y + c * z);  // optical frame
    if (std::fabs(plane.normal.dot(p) + plane.distance) > 0.08) {
      leaves = p.z();
      break;
    }
  }
  ASSERT_GT(leaves, 0.0);
  EXPECT_GE(road.validRange(), 0.9 * s.fit_range);
  EXPECT_NEAR(road.validRange(), leaves, 7.5);
  EXPECT_NEAR(plane.range, road.validRange(), 1e-12);
}

// The counts that choose the sampling grid are collectGrid()'s samples, on every stride: a flat
// road, a LiDAR's sparse scan lines with empty depth blocks (in the corridor, and where the far
// columns start in the middle of one) and no depth nearer than about 20 m (the far samples
// within 40 m join the near ones), and a road between 15 cm kerb bands at 2.0-2.4 m either side
// (inside the corridor's 2.5 m) with noisy depth; each with and without the depth block map and
// the far columns, on a width that leaves a part block.
TEST(RoadSurface, TheGridCountsAreTheGridsSamples) {
  Scene flat;
  Scene lidar;
  lidar.hole = [](int u, int v) { return v % 3 != 0 || (u / 16) % 2 == 0 || u % 7 == 0; };
  Scene gap;  // the scan lines only farther than about 20 m ahead
  gap.hole = [](int u, int v) { return v % 3 != 0 || (u / 16) % 2 == 0 || v > 98; };
  Scene kerbs;
  kerbs.noise = 0.01;
  kerbs.boxes = {{2.0, 2.4, 0.0, 200.0, 0.15}, {-2.4, -2.0, 0.0, 200.0, 0.15}};
  const std::vector<std::pair<std::string, cv::Mat>> images = {
      {"flat", flat.render()}, {"lidar", lidar.render()}, {"gap", gap.render()},
      {"kerbs", kerbs.render()}};
  RoadSurfaceSettings s = settings();
  const cv::Range corridor_cols = RoadSurface::corridorColumns(kK.fx, kK.cx, s.fit_range);
  ASSERT_NE(corridor_cols.start % kDepthBlock, 0);  // the far columns start inside a block
  int joined = 0;
  for (const auto& [name, image] : images) {
    for (int width : {kW, kW - 3}) {
      const cv::Mat points = image(cv::Rect(0, 0, width, kH)).clone();
      cv::Mat blocks;
      depthBlocks(points, cv::Range(0, kH), blocks);
      const cv::Mat* const maps[] = {nullptr, &blocks};
      for (const cv::Mat* map : maps) {
        for (const cv::Range& far : {cv::Range(), corridor_cols}) {
          s.far_columns = far;
          RoadSurface road;
          road.setDepthBlocks(map);
          int corridor = -1;  // counted on the first stride, for all of them
          for (int stride = 1; stride <= 20; ++stride) {
            SCOPED_TRACE(testing::Message() << name << ", width " << width << ", blocks "
                                            << (map != nullptr) << ", far columns "
                                            << far.start << "-" << far.end << ", stride "
                                            << stride);
            const RoadSurfaceProbe::Counts c =
                RoadSurfaceProbe::counted(road, points, kRows, s, stride, corridor);
            const RoadSurfaceProbe::Counts t =
                RoadSurfaceProbe::collected(road, points, kRows, s, stride);
            EXPECT_EQ(c.near, t.near);
            EXPECT_EQ(c.extended, t.extended);
            EXPECT_GT(t.extended, 0);
            if (name == "gap") {
              EXPECT_EQ(t.near, 0);
            }
            joined += t.extended > t.near;
          }
        }
      }
    }
  }
  EXPECT_GT(joined, 0);  // far samples joined the near ones
}

TEST(RoadSurface, NoRoadNoPlane) {
  RoadSurface road;
  PlaneEstimate plane;
  const cv::Mat none(kH, kW, CV_32FC3, cv::Scalar::all(std::nanf("")));
  EXPECT_FALSE(road.fit(none, kRows, settings(), PlaneEstimate(), plane));
  EXPECT_FALSE(plane.valid);
  // a wall 5 m ahead (an office, a truck's back): vertical, not a road
  cv::Mat wall(kH, kW, CV_32FC3);
  for (int v = 0; v < kH; ++v)
    for (int u = 0; u < kW; ++u)
      wall.at<cv::Vec3f>(v, u) = cv::Vec3f(static_cast<float>((u - kK.cx) / kK.fx * 5.0),
                                           static_cast<float>((v - kK.cy) / kK.fy * 5.0), 5.0f);
  EXPECT_FALSE(road.fit(wall, kRows, settings(), PlaneEstimate(), plane));
}

}  // namespace
}  // namespace rgbd_lane_detector
