// Synthetic generator, night motorway: the bonnet (rows, label, hood depth), the roof LiDAR's
// rings (returns only on them, none from the bonnet, range noise) and the low beams (the road lit
// evenly out to headlight_range, then falling with the square of the distance).
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "rgbd_lane_detector_tools/synth/renderer.h"
#include "rgbd_lane_detector_tools/synth/scenario.h"
#include "synth_preset.h"

namespace rgbd_lane_detector {
namespace synth {
namespace {

SceneSettings nightMotorway(const std::string& sensor) {
  SceneSettings s = test::preset("night_motorway");
  EXPECT_TRUE(applySensor(sensor, s));
  return s;
}

// World elevation (rad) of the ray through pixel (u, v).
double elevation(const CameraPose& pose, const Intrinsics& K, double u, double v) {
  const Eigen::Vector3d d =
      (pose.R_wc * Eigen::Vector3d((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0)).normalized();
  return std::asin(d.y());
}

TEST(NightMotorway, BonnetHidesTheBottomRowsAtItsOwnDepth) {
  const SceneSettings s = nightMotorway("clean");
  Renderer r(s);
  const Intrinsics K = r.intrinsics();
  RenderedFrame f;
  r.render(3, f);
  const int u = static_cast<int>(K.cx);
  const double top = (1.0 - s.bonnet) * s.height;  // the edge on the principal column
  // above the edge: the road; below it: the bonnet, labelled a car
  EXPECT_EQ(f.labels.at<uint8_t>(static_cast<int>(top) - 3, u), kLabelRoad);
  for (int v = static_cast<int>(std::ceil(top)); v < s.height; ++v) {
    ASSERT_EQ(f.labels.at<uint8_t>(v, u), kLabelCar) << "row " << v;
    // a flat hood in the optical frame whose front edge is 1.8 m ahead: z = 1.8 (top - cy) / (v - cy)
    EXPECT_NEAR(f.depth_true.at<float>(v, u), 1.8 * (top - K.cy) / (v - K.cy), 1e-4) << "row " << v;
  }
  // the edge curves down toward the image's sides: the road is seen lower there
  const int side_row = static_cast<int>(top) + 5;
  EXPECT_EQ(f.labels.at<uint8_t>(side_row, u), kLabelCar);
  EXPECT_NE(f.labels.at<uint8_t>(side_row, 2), kLabelCar);
  // dark paint at night: far darker than the lit road just above it
  EXPECT_LT(f.bgr.at<cv::Vec3b>(s.height - 2, u)[1] + 20, f.bgr.at<cv::Vec3b>(static_cast<int>(top) - 8, u)[1]);
}

TEST(NightMotorway, LidarReturnsLieOnItsRingsAndNeverOnTheBonnet) {
  const SceneSettings s = nightMotorway("lidar");
  ASSERT_EQ(s.lidar_beams, 32);
  Renderer r(s);
  const Intrinsics K = r.intrinsics();
  const CameraPose pose = r.pose(5);
  RenderedFrame f;
  r.render(5, f);
  const double step = (s.lidar_high_deg - s.lidar_low_deg) * M_PI / 180.0 / (s.lidar_beams - 1);
  const double low = s.lidar_low_deg * M_PI / 180.0;
  const double bonnet_top = (1.0 - s.bonnet) * s.height;
  std::vector<int> per_ring(s.lidar_beams, 0);
  int returns = 0, seen = 0;
  double err_sum = 0.0;
  for (int v = 0; v < f.depth.rows; ++v) {
    for (int u = 0; u < f.depth.cols; ++u) {
      const float z_true = f.depth_true.at<float>(v, u), z = f.depth.at<float>(v, u);
      seen += z_true > 0.f && z_true <= s.depth_range;
      if (!(z > 0.f)) continue;
      ++returns;
      // (the bonnet's edge is lowest-curving at the principal column)
      ASSERT_FALSE(v >= bonnet_top && f.labels.at<uint8_t>(v, u) == kLabelCar)
          << "a return from the bonnet at " << u << "," << v;
      const double k = (elevation(pose, K, u, v) - low) / step;
      const int ring = static_cast<int>(std::lround(k));
      ASSERT_GE(ring, 0);
      ASSERT_LT(ring, s.lidar_beams);
      // within half a pixel of the ring's elevation
      ASSERT_LE(std::fabs(k - ring) * step, 0.5 / K.fy + 1e-9) << u << "," << v;
      ++per_ring[ring];
      err_sum += std::fabs(z - z_true);
    }
  }
  ASSERT_GT(returns, 1000);
  // sparse: a ring every 1.3 deg is one row in about six of this image
  EXPECT_LT(static_cast<double>(returns) / seen, 0.3);
  // every ring between the bottom of the road and the horizon returns
  for (int ring = 0; ring < s.lidar_beams; ++ring) {
    const double el = low + ring * step;
    const double v_bottom = K.cy + K.fy * std::tan(s.pitch_deg * M_PI / 180.0 - el);
    if (el < -0.01 && v_bottom < (1.0 - s.bonnet) * s.height - 5) {
      EXPECT_GT(per_ring[ring], 50) << "ring " << ring;
    }
  }
  // 2 cm range noise: mean |dz| = 0.02 sqrt(2 / pi) cos(angle to the axis), a little under
  EXPECT_GT(err_sum / returns, 0.02 * std::sqrt(2.0 / M_PI) * 0.8);
  EXPECT_LT(err_sum / returns, 0.02 * std::sqrt(2.0 / M_PI) * 1.02);
}

TEST(NightMotorway, LowBeamsLightTheRoadEvenlyToTheirRange) {
  SceneSettings s = nightMotorway("clean");
  s.colour_noise = 0.0;
  s.lead_vehicle = false;
  s.vehicles = 0;
  s.patch_density = 0.0;
  s.asphalt_contrast = 0.0;
  s.crack_density = 0.0;
  s.drift_amplitude = 0.0;
  Renderer r(s);
  const Intrinsics K = r.intrinsics();
  RenderedFrame f;
  r.render(0, f);
  // mean green of unpainted road pixels near the principal column whose depth is in [lo, hi]
  const auto road = [&](double lo, double hi) {
    double sum = 0.0;
    int n = 0;
    for (int v = 0; v < f.bgr.rows; ++v)
      for (int u = static_cast<int>(K.cx) - 12; u <= static_cast<int>(K.cx) + 12; ++u) {
        const float z = f.depth_true.at<float>(v, u);
        if (f.labels.at<uint8_t>(v, u) == kLabelRoad && z >= lo && z <= hi) {
          sum += f.bgr.at<cv::Vec3b>(v, u)[1];
          ++n;
        }
      }
    EXPECT_GT(n, 10) << lo << "-" << hi << " m";
    return n ? sum / n : 0.0;
  };
  const double near = road(9.0, 11.0), mid = road(28.0, 32.0), far = road(85.0, 95.0);
  ASSERT_GT(near, 20.0);
  EXPECT_NEAR(mid / near, 1.0, 0.15);  // evenly lit within headlight_range (45 m)
  // beyond it at most (45 / 90)^2 = 1/4 of the beam (less near the cut-off at the lamps'
  // horizon, 0.45 deg below it at 90 m), but still lit above the ambient light
  EXPECT_LT(far / near, 0.26);
  EXPECT_GT(far / near, 0.05);
  // the sky and the scene above the beam's cut-off stay dark
  EXPECT_LT(f.bgr.at<cv::Vec3b>(5, static_cast<int>(K.cx))[1], 15);
}

}  // namespace
}  // namespace synth
}  // namespace rgbd_lane_detector
