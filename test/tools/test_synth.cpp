// Synthetic generator: determinism, exact ground truth (markers, plane, depth), sensor models
// and the settings record.
#include <cmath>

#include <gtest/gtest.h>

#include "rgbd_lane_detector_tools/scoring.h"
#include "rgbd_lane_detector_tools/synth/renderer.h"
#include "rgbd_lane_detector_tools/synth/scenario.h"
#include "rgbd_lane_detector_tools/synth/sequence_writer.h"

namespace rgbd_lane_detector {
namespace synth {
namespace {

SceneSettings preset(const std::string& name, int width = 640, int height = 380) {
  SceneSettings s;
  s.width = width;
  s.height = height;
  EXPECT_TRUE(applyScenario(name, s));
  return s;
}

// Ray through pixel (u, v) scaled to z = 1.
Eigen::Vector3d pixelRay(const Intrinsics& K, double u, double v) {
  return Eigen::Vector3d((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
}

TEST(Generator, SameSeedSameImages) {
  SceneSettings s = preset("shadows", 320, 190);
  s.sensor = "sparse";
  applySensor("sparse", s);
  Renderer a(s), b(s);
  RenderedFrame fa, fb;
  a.render(7, fa);
  b.render(7, fb);
  EXPECT_EQ(cv::norm(fa.bgr, fb.bgr, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(fa.depth, fb.depth, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(fa.labels, fb.labels, cv::NORM_INF), 0.0);
  // rendering order does not matter: frame 7 after frame 3 is the same frame 7
  RenderedFrame fc;
  a.render(3, fc);
  a.render(7, fc);
  EXPECT_EQ(cv::norm(fa.bgr, fc.bgr, cv::NORM_INF), 0.0);
  // another seed gives another sequence
  s.seed = 2;
  Renderer c(s);
  c.render(7, fc);
  EXPECT_GT(cv::norm(fa.bgr, fc.bgr, cv::NORM_L1), 0.0);
}

// Every rendered marker pixel near an ego line back-projects onto the true plane within the
// marker's half-width of the true centre line, and the lines are actually drawn.
void checkMarkerGroundTruth(const SceneSettings& s, int frame) {
  Renderer r(s);
  RenderedFrame f;
  r.render(frame, f);
  const tools::FrameTruth t = r.truth(frame);
  ASSERT_TRUE(t.has_lane);
  const Intrinsics K = r.intrinsics();
  int near_ego = 0;
  for (int v = 0; v < f.labels.rows; ++v) {
    for (int u = 0; u < f.labels.cols; ++u) {
      if (f.labels.at<uint8_t>(v, u) != kLabelLaneMarking) continue;
      const Eigen::Vector3d ray = pixelRay(K, u, v);
      const double denom = t.normal.dot(ray);
      ASSERT_LT(denom, 0.0) << "marker pixel above the horizon at " << u << "," << v;
      const Eigen::Vector3d p = ray * (-t.distance / denom);
      if (p.z() < s.gt_min_distance || p.z() > s.gt_max_distance) continue;
      const double dl = tools::lateralDistance(p, t.left, t.normal, t.distance);
      const double dr = tools::lateralDistance(p, t.right, t.normal, t.distance);
      if (std::min(dl, dr) > 1.0) continue;  // a neighbour lane's line
      ++near_ego;
      EXPECT_LE(std::min(dl, dr), 0.5 * s.marker_width + 2e-3) << "pixel " << u << "," << v;
    }
  }
  EXPECT_GT(near_ego, 300);
  // converse: the true centre lines (solid, unoccluded, up to 25 m) project onto marker pixels
  int hits = 0, total = 0;
  for (const auto* line : {&t.left, &t.right}) {
    for (const auto& p : *line) {
      if (p.z() > 25.0) continue;
      const int u = static_cast<int>(std::lround(K.fx * p.x() / p.z() + K.cx));
      const int v = static_cast<int>(std::lround(K.fy * p.y() / p.z() + K.cy));
      if (u < 0 || v < 0 || u >= f.labels.cols || v >= f.labels.rows) continue;
      ++total;
      hits += f.labels.at<uint8_t>(v, u) == kLabelLaneMarking;
    }
  }
  ASSERT_GT(total, 20);
  EXPECT_GE(hits, 0.95 * total);
}

TEST(Generator, MarkerPixelsLieOnTheTrueCentreLines) {
  SceneSettings s = preset("solid");
  s.vehicles = 0;
  s.lead_vehicle = false;
  checkMarkerGroundTruth(s, 11);
}

TEST(Generator, CurvedMarkerPixelsLieOnTheTrueCentreLines) {
  SceneSettings s = preset("curve");
  s.ego_left = MarkerKind::kSolid;
  s.vehicles = 0;
  s.lead_vehicle = false;
  checkMarkerGroundTruth(s, 40);
}

TEST(Generator, RoadDepthIsThePlaneIntersection) {
  SceneSettings s = preset("summer");
  Renderer r(s);
  RenderedFrame f;
  r.render(5, f);
  const tools::FrameTruth t = r.truth(5);
  const Intrinsics K = r.intrinsics();
  cv::Mat cm;
  encodeDepthCentimetres(f.depth, cm);
  int road = 0;
  for (int v = 0; v < f.labels.rows; ++v) {
    for (int u = 0; u < f.labels.cols; ++u) {
      const uint8_t l = f.labels.at<uint8_t>(v, u);
      if (l != kLabelRoad && l != kLabelLaneMarking) continue;
      const Eigen::Vector3d ray = pixelRay(K, u, v);
      const double z = -t.distance / t.normal.dot(ray);
      ASSERT_NEAR(f.depth.at<float>(v, u), z, 1e-4 * z) << u << "," << v;
      ASSERT_NEAR(cm.at<cv::Vec3w>(v, u)[0] * 0.01, z, 0.0051) << u << "," << v;
      ++road;
    }
  }
  EXPECT_GT(road, 50000);
  // the sky has no depth
  EXPECT_EQ(f.labels.at<uint8_t>(0, 0), kLabelSky);
  EXPECT_EQ(f.depth.at<float>(0, 0), 0.f);
}

TEST(Generator, PlaneNormalPointsTowardTheCamera) {
  const SceneSettings s = preset("curve");
  Renderer r(s);
  for (int i : {0, 50, 100}) {
    const tools::FrameTruth t = r.truth(i);
    EXPECT_NEAR(t.normal.norm(), 1.0, 1e-12);
    EXPECT_LT(t.normal.y(), -0.9);  // up in the optical frame is -y
    EXPECT_NEAR(t.distance, s.camera_height, 0.021);
    // the camera (origin) is on the positive side; ground points satisfy the plane
    EXPECT_GT(t.distance, 0.0);
    for (const auto& p : t.left) EXPECT_NEAR(t.normal.dot(p) + t.distance, 0.0, 1e-9);
    ASSERT_FALSE(t.left.empty());
    EXPECT_NEAR(t.left.front().z(), 3.0, 0.5);
    EXPECT_LT(t.left.front().z(), t.left.back().z());  // near to far
    EXPECT_LT(t.left.front().x(), t.right.front().x());
  }
}

TEST(Generator, NoMarkingsHasNoLane) {
  const SceneSettings s = preset("no_markings", 160, 95);
  Renderer r(s);
  const tools::FrameTruth t = r.truth(3);
  EXPECT_FALSE(t.has_lane);
  EXPECT_TRUE(t.left.empty());
  RenderedFrame f;
  r.render(3, f);
  EXPECT_EQ(cv::countNonZero(f.labels == kLabelLaneMarking), 0);
}

TEST(Generator, SensorModels) {
  SceneSettings s = preset("summer", 320, 190);
  s.sensor = "kinect";
  ASSERT_TRUE(applySensor("kinect", s));
  Renderer kinect(s);
  RenderedFrame f;
  kinect.render(2, f);
  double max_depth = 0, sum_err = 0;
  int n = 0;
  for (int v = 0; v < f.depth.rows; ++v) {
    for (int u = 0; u < f.depth.cols; ++u) {
      const float d = f.depth.at<float>(v, u), z = f.depth_true.at<float>(v, u);
      if (d > 0) {
        max_depth = std::max<double>(max_depth, d);
        sum_err += std::fabs(d - z) / (z * z);
        ++n;
      }
    }
  }
  EXPECT_LE(max_depth, 20.0 + 20.0 * 20.0 * 0.0015 * 5);
  ASSERT_GT(n, 1000);
  // mean |N(0, k z^2)| / z^2 = k sqrt(2/pi)
  EXPECT_NEAR(sum_err / n, 0.0015 * std::sqrt(2.0 / M_PI), 0.0003);

  ASSERT_TRUE(applySensor("sparse", s));
  Renderer sparse(s);
  sparse.render(2, f);
  int in_range = 0, invalid = 0;
  for (int v = 0; v < f.depth.rows; ++v) {
    for (int u = 0; u < f.depth.cols; ++u) {
      const float z = f.depth_true.at<float>(v, u);
      if (z <= 0 || z > s.depth_range) continue;
      ++in_range;
      invalid += f.depth.at<float>(v, u) <= 0;
    }
  }
  ASSERT_GT(in_range, 1000);
  const double frac = static_cast<double>(invalid) / in_range;
  EXPECT_GT(frac, 0.4);
  EXPECT_LT(frac, 0.65);
}

TEST(Generator, SettingsRoundTripAndOverrides) {
  SceneSettings s = preset("overpass");
  std::string error;
  EXPECT_TRUE(setSetting(s, "dash_length", "6", error));
  EXPECT_TRUE(setSetting(s, "ego_left", "solid", error));
  EXPECT_TRUE(setSetting(s, "fog_colour", "0.5,0.6,0.7", error));
  EXPECT_FALSE(setSetting(s, "no_such_key", "1", error));
  EXPECT_NE(error.find("no_such_key"), std::string::npos);
  EXPECT_FALSE(setSetting(s, "frames", "ten", error));
  EXPECT_FALSE(setSetting(s, "ego_right", "dotted", error));
  EXPECT_DOUBLE_EQ(s.dash_length, 6.0);
  EXPECT_EQ(s.ego_left, MarkerKind::kSolid);
  EXPECT_TRUE(validateSettings(s, error)) << error;
  SceneSettings bad = s;
  bad.width = 0;
  EXPECT_FALSE(validateSettings(bad, error));

  const std::string json = settingsToJson(s);
  const std::string path = ::testing::TempDir() + "/rgbd_synth_settings.json";
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs(json.c_str(), f);
    std::fclose(f);
  }
  SceneSettings back;
  ASSERT_TRUE(readSettingsJson(path, back, error)) << error;
  EXPECT_EQ(settingsToJson(back), json);
  std::remove(path.c_str());
  EXPECT_FALSE(readSettingsJson(path, back, error));
  EXPECT_FALSE(applyScenario("no_such_scenario", back));
  EXPECT_FALSE(applySensor("no_such_sensor", back));
}

TEST(Generator, IntrinsicsScaleWithWidth) {
  Renderer full(preset("summer", 1280, 760));
  EXPECT_DOUBLE_EQ(full.intrinsics().fx, 532.740352);
  EXPECT_DOUBLE_EQ(full.intrinsics().cx, 640.0);
  EXPECT_DOUBLE_EQ(full.intrinsics().cy, 380.0);
  Renderer half(preset("summer", 640, 380));
  EXPECT_DOUBLE_EQ(half.intrinsics().fx, 266.370176);
  EXPECT_DOUBLE_EQ(half.intrinsics().cy, 190.0);
}

}  // namespace
}  // namespace synth
}  // namespace rgbd_lane_detector
