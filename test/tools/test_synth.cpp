// Synthetic generator: determinism, exact ground truth (markers, plane, depth), sensor models,
// the settings record, and the urban scenarios' properties checked on rendered data (kerb,
// tram rails, asphalt edge, intersection, crest and sag, yellow double line, lane change).
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector_tools/scoring.h"
#include "rgbd_lane_detector_tools/synth/renderer.h"
#include "rgbd_lane_detector_tools/synth/scenario.h"
#include "rgbd_lane_detector_tools/synth/sequence_writer.h"
#include "synth_preset.h"

namespace rgbd_lane_detector {
namespace synth {
namespace {

using test::preset;

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

// --- generator version 2: urban scenarios, vehicle frame, labels ---------------------------

// A rendered frame with its truth, and its pixels back-projected into base_link.
struct Scene {
  RenderedFrame f;
  tools::FrameTruth t;
  Intrinsics K;
  // optical-frame point of pixel (u, v) from the exact depth (NaN when none)
  Eigen::Vector3d optical(int u, int v) const {
    const float z = f.depth_true.at<float>(v, u);
    if (!(z > 0.f)) return Eigen::Vector3d::Constant(std::nan(""));
    return pixelRay(K, u, v) * z;
  }
  Eigen::Vector3d base(int u, int v) const { return t.base_to_camera * optical(u, v); }
};

Scene renderScene(const SceneSettings& s, int frame) {
  Renderer r(s);
  Scene sc;
  r.render(frame, sc.f);
  sc.t = r.truth(frame);
  sc.K = r.intrinsics();
  return sc;
}

// Lateral offset (base_link y, positive left) of a boundary at forward distance x (linear
// interpolation of its base_link samples).
double boundaryY(const tools::TrueBoundary& b, double x) {
  const auto& p = b.points_base;
  for (size_t i = 0; i + 1 < p.size(); ++i) {
    if (x >= p[i].x() && x <= p[i + 1].x()) {
      const double w = (x - p[i].x()) / (p[i + 1].x() - p[i].x());
      return p[i].y() + w * (p[i + 1].y() - p[i].y());
    }
  }
  return std::nan("");
}

SceneSettings quiet(const std::string& name, int width = 320, int height = 190) {
  SceneSettings s = preset(name, width, height);
  s.vehicles = 0;
  s.lead_vehicle = false;
  s.canopy_shadows = 0.0;
  return s;
}

TEST(Generator, VehicleFrameIsOnTheRoadUnderTheCamera) {
  const SceneSettings s = preset("curve", 160, 95);
  Renderer r(s);
  for (int i : {0, 37, 150}) {
    const tools::FrameTruth t = r.truth(i);
    ASSERT_TRUE(t.has_vehicle_frame);
    const Eigen::Isometry3d& T = t.base_to_camera;
    EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-12);  // a proper rotation
    EXPECT_NEAR(T.translation().head<2>().norm(), 0.0, 1e-12);
    EXPECT_NEAR(T.translation().z(), s.camera_height, 0.021);  // with the height wobble
    // the road plane is base_link's z = 0: its normal is +z, the lines lie at z = 0
    EXPECT_NEAR((T.linear() * t.normal - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-9);
    for (const auto& b : t.boundaries)
      for (const auto& p : b.points_base) ASSERT_NEAR(p.z(), 0.0, 1e-4);
    // x forward, y left: the ego left line is left, ahead of the vehicle
    const tools::TrueBoundary* left = t.egoSide(true);
    ASSERT_NE(left, nullptr);
    EXPECT_NEAR(left->points_base.front().x(), s.gt_min_distance, 0.2);
    EXPECT_GT(left->points_base.front().y(), 1.0);
    EXPECT_LT(t.egoSide(false)->points_base.front().y(), -1.0);
    // lane model: width, offset from the lines at the vehicle, curve turning right
    EXPECT_NEAR(t.lane.width, s.lane_width, 1e-12);
    // the centre line y(x) = -offset - tan(heading) x + curvature x^2 / 2 (small angles)
    const tools::TrueBoundary* right = t.egoSide(false);
    for (size_t k : {size_t(2), size_t(12)}) {
      const double x = left->points_base[k].x();
      const double centre = 0.5 * (left->points_base[k].y() + boundaryY(*right, x));
      EXPECT_NEAR(centre, -t.lane.offset - std::tan(t.lane.heading) * x +
                              0.5 * t.lane.curvature * x * x,
                  0.01)
          << "x " << x;
    }
    // the ego lane's centre is the drifting camera's reference line: curvature 1/R, to the right
    EXPECT_NEAR(t.lane.curvature, -1.0 / 300.0, 1e-12);
  }
  // without body motion the camera sits exactly on the nominal mount
  SceneSettings still = s;
  still.pitch_wobble_deg = still.roll_wobble_deg = 0.0;
  still.roll_deg = 2.0;
  const tools::FrameTruth t = Renderer(still).truth(3);
  EXPECT_TRUE(t.base_to_camera.linear().isApprox(nominalMount(still).linear(), 1e-12));
  // the nominal mount looks forward and down by pitch_deg
  const Eigen::Vector3d view = nominalMount(still).linear() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(std::asin(-view.z()) * 180.0 / M_PI, still.pitch_deg, 1e-9);
  EXPECT_GT(view.x(), 0.99);
  // it is the /tf_static of --bag: tf2 RPY(-roll, pitch, 0) of the body, then body -> optical
  const double deg = M_PI / 180.0;
  const Eigen::Matrix3d body =
      (Eigen::AngleAxisd(still.pitch_deg * deg, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(-still.roll_deg * deg, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  const Eigen::Matrix3d optical = Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5).toRotationMatrix();
  EXPECT_TRUE(nominalMount(still).linear().isApprox(body * optical, 1e-12));
  // a positive roll raises the right side: the optical x axis (right) points up
  EXPECT_GT((nominalMount(still).linear() * Eigen::Vector3d::UnitX()).z(), 0.03);
}

TEST(Generator, KerbIsARaisedFaceAtTheBoundary) {
  SceneSettings s = quiet("kerb");
  s.shadows = false;
  const Scene sc = renderScene(s, 12);
  const tools::TrueBoundary* right = sc.t.egoSide(false);
  ASSERT_NE(right, nullptr);
  EXPECT_EQ(right->kind, BoundaryKind::kRoadEdge);
  EXPECT_EQ(right->style, tools::LineStyle::kRoadEdge);
  EXPECT_EQ(right->edge, tools::EdgeType::kKerb);
  EXPECT_EQ(sc.t.egoSide(true)->kind, BoundaryKind::kPaint);
  EXPECT_EQ(sc.t.boundary(tools::BoundaryLabel::kRoadEdgeRight), nullptr);  // it is ego_right
  int face = 0, top = 0;
  std::vector<Eigen::Vector3d> face_points;
  for (int v = 0; v < sc.f.labels.rows; ++v) {
    for (int u = 0; u < sc.f.labels.cols; ++u) {
      if (sc.f.labels.at<uint8_t>(v, u) != kLabelKerb) continue;
      const Eigen::Vector3d p = sc.base(u, v);
      ASSERT_TRUE(p.allFinite());
      const double lateral = boundaryY(*right, p.x()) - p.y();  // beyond the line: positive
      if (!std::isfinite(lateral)) continue;  // outside the sampled 3-60 m
      if (std::fabs(lateral) < 2e-3) {  // the face: from the road up to the kerb's top
        ASSERT_GE(p.z(), -2e-3) << u << "," << v;
        ASSERT_LE(p.z(), s.kerb_height + 2e-3) << u << "," << v;
        face_points.push_back(p);
        ++face;
      } else {  // the stones' top, 0.10-0.15 m above the road
        ASSERT_NEAR(p.z(), s.kerb_height, 2e-3) << u << "," << v;
        ASSERT_GT(lateral, 0.0);
        ASSERT_LE(lateral, s.kerb_width + 2e-3);
        ++top;
      }
    }
  }
  EXPECT_GT(face, 100);
  EXPECT_GT(top, 100);
  EXPECT_GE(s.kerb_height, 0.10);
  EXPECT_LE(s.kerb_height, 0.15);
  // the face is vertical, along the road: its normal (smallest spread) is horizontal and lateral
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : face_points) c += p / face_points.size();
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : face_points) cov += (p - c) * (p - c).transpose();
  const Eigen::Vector3d n = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0);
  EXPECT_LT(std::fabs(n.z()), 0.02);
  EXPECT_GT(std::fabs(n.y()), 0.99);
  // the kerb stones are brighter than the asphalt (grey levels of the top vs the ego lane)
  double kerb_grey = 0, road_grey = 0;
  int kn = 0, rn = 0;
  cv::Mat grey;
  cv::cvtColor(sc.f.bgr, grey, cv::COLOR_BGR2GRAY);
  for (int v = sc.f.labels.rows / 2; v < sc.f.labels.rows; ++v) {
    for (int u = 0; u < sc.f.labels.cols; ++u) {
      const uint8_t l = sc.f.labels.at<uint8_t>(v, u);
      if (l == kLabelKerb) kerb_grey += grey.at<uint8_t>(v, u), ++kn;
      if (l == kLabelRoad) road_grey += grey.at<uint8_t>(v, u), ++rn;
    }
  }
  ASSERT_GT(kn, 0);
  ASSERT_GT(rn, 0);
  EXPECT_GT(kerb_grey / kn, road_grey / rn + 20.0);
}

TEST(Generator, TramRailsLieFlushOnTheRoadAtTheBoundary) {
  const SceneSettings s = quiet("tram_rails", 640, 380);
  const Scene sc = renderScene(s, 4);
  const tools::TrueBoundary* left = sc.t.egoSide(true);
  ASSERT_NE(left, nullptr);
  EXPECT_EQ(left->kind, BoundaryKind::kRoadEdge);
  EXPECT_EQ(left->edge, tools::EdgeType::kRails);
  EXPECT_EQ(sc.t.boundary(tools::BoundaryLabel::kNextLeft), nullptr);  // the tracks: no lane
  EXPECT_NEAR(sc.t.lane.width, s.lane_width, 1e-12);
  // rail heads and grooves: flush with the road, at the four rails' offsets from the line
  const double pitch = s.tram_gauge + s.tram_head_width;
  const double rails[] = {0.0, pitch, s.tram_track_spacing, s.tram_track_spacing + pitch};
  const double reach = 0.5 * s.tram_head_width + s.tram_groove_width + 2e-3;
  int per_rail[4] = {0, 0, 0, 0};
  cv::Mat grey;
  cv::cvtColor(sc.f.bgr, grey, cv::COLOR_BGR2GRAY);
  int max_near = 0, min_near = 255;
  for (int v = 0; v < sc.f.labels.rows; ++v) {
    for (int u = 0; u < sc.f.labels.cols; ++u) {
      if (sc.f.labels.at<uint8_t>(v, u) != kLabelRail) continue;
      const Eigen::Vector3d p = sc.base(u, v);
      ASSERT_NEAR(p.z(), 0.0, 1e-3) << u << "," << v;
      const double off = p.y() - boundaryY(*left, p.x());  // left of the line: positive
      if (!std::isfinite(off)) continue;
      int which = -1;
      for (int k = 0; k < 4; ++k)
        if (std::fabs(off - rails[k]) <= reach) which = k;
      ASSERT_GE(which, 0) << "rail pixel " << off << " m from the line";
      ++per_rail[which];
      if (which == 0 && p.x() < 8.0) {  // near: head and groove both span pixels
        max_near = std::max<int>(max_near, grey.at<uint8_t>(v, u));
        min_near = std::min<int>(min_near, grey.at<uint8_t>(v, u));
      }
    }
  }
  for (int k = 0; k < 4; ++k) EXPECT_GT(per_rail[k], 50) << "rail " << k;
  // bright polished heads beside dark flangeways
  EXPECT_GT(max_near, 150);
  EXPECT_LT(min_near, 40);
}

TEST(Generator, AsphaltEdgeDropsToGravel) {
  const SceneSettings s = quiet("road_edge");
  const Scene sc = renderScene(s, 9);
  const tools::TrueBoundary* right = sc.t.egoSide(false);
  ASSERT_NE(right, nullptr);
  EXPECT_EQ(right->kind, BoundaryKind::kRoadEdge);
  EXPECT_EQ(right->edge, tools::EdgeType::kAsphaltEdge);
  int gravel = 0;
  for (int v = 0; v < sc.f.labels.rows; ++v) {
    for (int u = 0; u < sc.f.labels.cols; ++u) {
      const uint8_t l = sc.f.labels.at<uint8_t>(v, u);
      const Eigen::Vector3d p = sc.base(u, v);
      const double beyond = boundaryY(*right, p.x()) - p.y();
      if (!std::isfinite(beyond)) continue;
      if (l == kLabelTerrain) {
        ASSERT_NEAR(p.z(), -s.edge_drop, 1e-3);
        ASSERT_GT(beyond, 0.0);
        ASSERT_LE(beyond, s.gravel_width + 1e-3);
        ++gravel;
      } else if (l == kLabelRoad) {
        ASSERT_LE(beyond, 1e-3) << "asphalt beyond its edge";
        ASSERT_NEAR(p.z(), 0.0, 1e-3);
      }
    }
  }
  EXPECT_GT(gravel, 300);
}

TEST(Generator, IntersectionsInterruptTheLines) {
  SceneSettings s = quiet("intersection");
  s.turn_arrows = false;
  Renderer r(s);
  // the crossing road starts at intersection_start: the stop line at 5 m, zebra 6.5-10.5 m
  const int frame = static_cast<int>(std::lround((s.intersection_start - 12.0) / s.speed * s.fps));
  const Scene sc = renderScene(s, frame);
  const double cam_s = r.pose(frame).s;
  ASSERT_NEAR(cam_s, s.intersection_start - 12.0, 1e-9);
  EXPECT_TRUE(sc.t.lane_optional);
  EXPECT_TRUE(r.truth(frame - 7).lane_optional);    // 26 m before: lines end at 19 m
  EXPECT_FALSE(r.truth(frame - 8).lane_optional);   // 28 m before: lines for 21 m
  // the ego lines end at the stop line and resume after the crossing's far zebra
  for (const bool left : {true, false}) {
    const tools::TrueBoundary* b = sc.t.egoSide(left);
    ASSERT_NE(b, nullptr);
    for (const auto& p : b->points_base)
      EXPECT_TRUE(p.x() < 5.0 + 0.3 || p.x() > 12.0 + s.crossing_width + 7.0 - 0.3) << p.x();
  }
  // road coordinates of the pixels (straight road: s = world z, t = world x)
  const CameraPose pose = r.pose(frame);
  const Eigen::Matrix3d world_from_base = baseFromWorld(pose.yaw, pose.vehicle_pitch).transpose();
  const double s0 = s.intersection_start, left_edge = r.road().leftEdge();
  const double ego_left = r.road().laneCentre(0) - 0.5 * s.lane_width;
  int stripes = 0, gaps = 0, stop = 0;
  for (int v = 0; v < sc.f.labels.rows; ++v) {
    for (int u = 0; u < sc.f.labels.cols; ++u) {
      const Eigen::Vector3d p = sc.base(u, v);
      if (!p.allFinite() || std::fabs(p.z()) > 1e-3) continue;
      const Eigen::Vector3d w = pose.base + world_from_base * p;
      const double along = w.z() - s0, t = w.x();
      const bool marking = sc.f.labels.at<uint8_t>(v, u) == kLabelLaneMarking;
      if (along > -5.4 && along < -1.6 && t > left_edge + 0.05 && t < r.road().rightEdge() - 0.05) {
        // zebra: stripes along the road, 0.5 m wide with 0.5 m gaps, across the roadway
        const double phase = std::fmod(t - left_edge, 1.0);
        if (std::min({phase, std::fabs(phase - 0.5), 1.0 - phase}) < 0.02) continue;  // edges
        ASSERT_EQ(marking, phase < 0.5) << "zebra at s " << along << " t " << t;
        (marking ? stripes : gaps)++;
      }
      if (along > -6.95 && along < -6.55 && t > ego_left + 0.1 && t < r.road().rightEdge() - 0.1) {
        ASSERT_TRUE(marking) << "stop line missing at t " << t;
        ++stop;
      }
    }
  }
  EXPECT_GT(gaps, 200);
  EXPECT_GT(stripes, 200);
  EXPECT_GT(stop, 50);
}

TEST(Generator, CrestAndSagAreNotOnePlane) {
  SceneSettings s = quiet("crest_sag", 640, 380);
  s.lead_vehicle = true;
  Renderer r(s);
  // on the crest's falling side: the road drops away beyond 30 m
  const double cam_s = s.vertical_start + 0.5 * s.vertical_grade * s.vertical_radius;
  const int frame = static_cast<int>(std::lround(cam_s / s.speed * s.fps));
  const Scene sc = renderScene(s, frame);
  EXPECT_GT(sc.t.plane_rms, 0.002);
  EXPECT_LT(sc.t.plane_rms, 0.03);
  double near_max = 0.0, far_max = 0.0;
  int near = 0, far = 0;
  for (int v = 0; v < sc.f.labels.rows; ++v) {
    for (int u = 0; u < sc.f.labels.cols; ++u) {
      const uint8_t l = sc.f.labels.at<uint8_t>(v, u);
      if (l != kLabelRoad && l != kLabelLaneMarking) continue;
      const Eigen::Vector3d p = sc.optical(u, v);
      const Eigen::Vector3d b = sc.t.base_to_camera * p;
      if (std::fabs(b.y() + sc.t.lane.offset) > 0.5 * s.lane_width) continue;  // ego lane
      const double residual = std::fabs(sc.t.normal.dot(p) + sc.t.distance);
      if (b.x() >= 3.0 && b.x() <= 20.0) near_max = std::max(near_max, residual), ++near;
      if (b.x() > 30.0) far_max = std::max(far_max, residual), ++far;
    }
  }
  ASSERT_GT(near, 1000);
  ASSERT_GT(far, 20);
  EXPECT_LT(near_max, 0.05);  // the true plane fits the ego lane 3-20 m ahead
  EXPECT_GT(far_max, 0.3);    // beyond 30 m the road is not on it
  // the lines lie on the true surface: marker pixels of the right solid line, back-projected
  // from their depth, are within the line's half width of its true points in 3D (a line on the
  // plane instead would be decimetres off beyond 30 m)
  const tools::TrueBoundary* right = sc.t.egoSide(false);
  ASSERT_NE(right, nullptr);
  const auto distance3d = [&right](const Eigen::Vector3d& q) {
    double best = 1e9;
    for (size_t i = 0; i + 1 < right->points.size(); ++i) {
      const Eigen::Vector3d a = right->points[i], ab = right->points[i + 1] - a;
      const double h = std::min(1.0, std::max(0.0, (q - a).dot(ab) / ab.squaredNorm()));
      best = std::min(best, (q - a - h * ab).norm());
    }
    return best;
  };
  int on_line = 0, far_on_line = 0;
  for (int v = 0; v < sc.f.labels.rows; ++v) {
    for (int u = 0; u < sc.f.labels.cols; ++u) {
      if (sc.f.labels.at<uint8_t>(v, u) != kLabelLaneMarking) continue;
      const Eigen::Vector3d q = sc.optical(u, v);
      const double ahead = (sc.t.base_to_camera * q).x();
      if (ahead < s.gt_min_distance + 0.3 || ahead > 55.0 ||
          tools::lateralDistance(q, right->points, sc.t.normal, sc.t.distance) > 0.5)
        continue;  // another line, or beyond the samples
      ASSERT_LT(distance3d(q), 0.5 * s.marker_width + 0.01) << u << "," << v;
      ++on_line;
      far_on_line += q.z() > 30.0;
    }
  }
  EXPECT_GT(on_line, 200);
  EXPECT_GT(far_on_line, 5);
  // cars stand on the surface: at the sag's bottom, the car ahead is on the rising road
  const int sag = static_cast<int>(std::lround(
      (s.vertical_start + 2.0 * s.vertical_grade * s.vertical_radius + s.vertical_tangent) /
      s.speed * s.fps));
  const Scene up = renderScene(s, sag);
  ASSERT_NEAR(r.road().profile().grade(r.pose(sag).s), 0.0, 1e-9);
  Eigen::Vector3d bottom = Eigen::Vector3d::Constant(std::nan(""));
  for (int v = up.f.labels.rows - 1; v >= 0 && !bottom.allFinite(); --v)
    for (int u = 0; u < up.f.labels.cols && !bottom.allFinite(); ++u)
      if (up.f.labels.at<uint8_t>(v, u) == kLabelCar) bottom = up.base(u, v);
  ASSERT_TRUE(bottom.allFinite());
  const double sag_s = r.pose(sag).s;
  const double ground = r.road().profile().height(sag_s + bottom.x()) -
                        r.road().profile().height(sag_s);
  EXPECT_GT(ground, 0.2);                          // the road ahead rises
  // and the car's lowest pixel is on it, within a pixel's height there
  EXPECT_NEAR(bottom.z(), ground, 1.5 * bottom.x() / up.K.fy);
}

TEST(Generator, YellowDoubleCentreLine) {
  const SceneSettings s = quiet("yellow_centre");
  const Scene sc = renderScene(s, 6);
  const tools::TrueBoundary* left = sc.t.egoSide(true);
  const tools::TrueBoundary* right = sc.t.egoSide(false);
  ASSERT_NE(left, nullptr);
  ASSERT_NE(right, nullptr);
  EXPECT_EQ(left->colour, tools::LineColour::kYellow);
  EXPECT_EQ(left->style, tools::LineStyle::kDoubleSolid);
  EXPECT_EQ(right->colour, tools::LineColour::kWhite);
  cv::Mat hsv;
  cv::cvtColor(sc.f.bgr, hsv, cv::COLOR_BGR2HSV_FULL);  // hue 0-255 for 0-360 deg
  int yellow = 0, white = 0, in_gap = 0;
  for (int v = 0; v < sc.f.labels.rows; ++v) {
    for (int u = 0; u < sc.f.labels.cols; ++u) {
      if (sc.f.labels.at<uint8_t>(v, u) != kLabelLaneMarking) continue;
      const Eigen::Vector3d p = sc.base(u, v);
      if (p.x() > 15.0) continue;  // near pixels: paint only, no mixing with asphalt
      const cv::Vec3b c = hsv.at<cv::Vec3b>(v, u);
      const double hue = c[0] * 360.0 / 256.0, sat = c[1] / 255.0;
      const double dl = p.y() - boundaryY(*left, p.x());
      const double dr = p.y() - boundaryY(*right, p.x());
      if (std::fabs(dl) < 0.5) {
        // the two yellow lines, the gap between them unpainted
        EXPECT_GT(std::fabs(dl), 0.5 * s.double_line_gap - 2e-3);
        EXPECT_LT(std::fabs(dl), 0.5 * s.double_line_gap + s.marker_width + 2e-3);
        in_gap += std::fabs(dl) < 0.5 * s.double_line_gap - 2e-3;
        if (c[2] > 150) {  // unworn paint
          EXPECT_GT(hue, 35.0);
          EXPECT_LT(hue, 60.0);
          EXPECT_GT(sat, 0.5);
          ++yellow;
        }
      } else if (std::fabs(dr) < 0.3 && c[2] > 150) {
        EXPECT_LT(sat, 0.15);
        ++white;
      }
    }
  }
  EXPECT_EQ(in_gap, 0);
  EXPECT_GT(yellow, 100);
  EXPECT_GT(white, 100);
}

TEST(Generator, LaneChangeSwapsTheLabels) {
  SceneSettings s = quiet("lane_change", 64, 38);
  Renderer r(s);
  // the vehicle moves one lane left over lane_change_length (3.5 s at 20 m/s) and back
  EXPECT_NEAR(s.lane_change_length / s.speed, 3.5, 1e-12);
  int crossing = -1;
  for (int i = 1; i < s.frames && crossing < 0; ++i)
    if (r.truth(i).lane.offset < r.truth(i - 1).lane.offset - 1.0) crossing = i;
  ASSERT_GT(crossing, 0);
  const tools::FrameTruth before = r.truth(crossing - 1), after = r.truth(crossing);
  // the line the vehicle crosses: ego_left before, ego_right after (same place, moved by one
  // frame of lateral motion)
  const double crossed_before = boundaryY(*before.egoSide(true), 10.0);
  const double crossed_after = boundaryY(*after.egoSide(false), 10.0);
  EXPECT_NEAR(crossed_before, crossed_after, 0.4);
  EXPECT_LT(std::fabs(before.lane.offset), 0.5 * s.lane_width + 1e-9);
  EXPECT_LT(std::fabs(after.lane.offset), 0.5 * s.lane_width + 1e-9);
  EXPECT_GT(before.lane.offset, 1.5);  // far left in the old lane
  EXPECT_LT(after.lane.offset, -1.5);  // far right in the new one
  EXPECT_GT(before.lane.heading, 0.05);  // pointing left
  // the new lane is the leftmost: no next_left any more, the road edge is next to it
  EXPECT_NE(before.boundary(tools::BoundaryLabel::kNextLeft), nullptr);
  EXPECT_EQ(after.boundary(tools::BoundaryLabel::kNextLeft), nullptr);
  EXPECT_NE(after.boundary(tools::BoundaryLabel::kNextRight), nullptr);
  EXPECT_EQ(after.egoSide(true)->style, tools::LineStyle::kSolid);  // the road's edge line
  EXPECT_EQ(before.egoSide(true)->style, tools::LineStyle::kDashed);
  // and back later
  const tools::FrameTruth last = r.truth(s.frames - 1);
  EXPECT_EQ(last.egoSide(true)->style, tools::LineStyle::kDashed);
  EXPECT_NE(last.boundary(tools::BoundaryLabel::kNextLeft), nullptr);
}

}  // namespace
}  // namespace synth
}  // namespace rgbd_lane_detector
