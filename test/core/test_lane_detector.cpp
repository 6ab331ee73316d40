// Whole pipeline on rendered roads: both markers found, plane within 1 deg and 5 cm of truth.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector/lane_detector.h"
#include "simd.h"  // private: targets and the reference stages
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

// The fast stages against the method as written (cv::matchTemplate, FALS solved in double):
// over a drive with adapting templates, the response maps agree within 1e-4 and every
// detection (seeds, angles, traced pixels and points, plane) is the same.
TEST(LaneDetector, FastStagesGiveTheReferenceResults) {
  for (const Params& params : {Params::paper(), Params::improved()}) {
    LaneDetector fast(params), ref(params);
    Result a, b;
    for (int i = 0; i < 6; ++i) {
      RoadScene scene;
      scene.right_dashed = true;
      scene.lateral_offset = 0.25 * std::sin(0.7 * i);
      scene.pitch = 0.07 + 0.005 * i;
      cv::Mat bgr, depth;
      const Frame f = makeFrame(scene, bgr, depth);
      ASSERT_EQ(fast.detect(f, a), Status::kOk);
      setReferenceStages(true);
      const Status st = ref.detect(f, b);
      setReferenceStages(false);
      ASSERT_EQ(st, Status::kOk);
      SCOPED_TRACE(testing::Message() << "frame " << i);
      EXPECT_LT(cv::norm(a.response_left, b.response_left, cv::NORM_INF), 1e-4);
      EXPECT_LT(cv::norm(a.response_right, b.response_right, cv::NORM_INF), 1e-4);
      for (const auto& [p, q] :
           {std::make_pair(&a.left, &b.left), std::make_pair(&a.right, &b.right)}) {
        EXPECT_EQ(p->found, q->found);
        EXPECT_EQ(p->seed, q->seed);
        EXPECT_EQ(p->angle, q->angle);
        EXPECT_EQ(p->pixels, q->pixels);
        EXPECT_NEAR(p->peak_score, q->peak_score, 1e-4);
      }
      EXPECT_EQ(a.plane.valid, b.plane.valid);
      EXPECT_EQ(a.plane.normal, b.plane.normal);
      EXPECT_EQ(a.plane.distance, b.plane.distance);
      EXPECT_EQ(a.template_angle_left, b.template_angle_left);
      EXPECT_EQ(a.template_angle_right, b.template_angle_right);
    }
  }
}

// Two maps with the same size, type and bits.
bool sameBits(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

// The same R bits, traced pixels and plane.
void expectSameDetections(const Result& a, const Result& b) {
  EXPECT_TRUE(sameBits(a.response_left, b.response_left));
  EXPECT_TRUE(sameBits(a.response_right, b.response_right));
  EXPECT_EQ(a.left.pixels, b.left.pixels);
  EXPECT_EQ(a.right.pixels, b.right.pixels);
  EXPECT_EQ(a.left.found, b.left.found);
  EXPECT_EQ(a.right.found, b.right.found);
  EXPECT_EQ(a.plane.valid, b.plane.valid);
  EXPECT_EQ(a.plane.normal, b.plane.normal);
  EXPECT_EQ(a.plane.distance, b.plane.distance);
}

// The kernels dispatch on the CPU (x86: AVX-512, AVX2, SSE4; aarch64: NEON; and the scalar
// loops): every target this machine runs gives the same bits as the scalar one, so results do
// not depend on the machine.
TEST(LaneDetector, EveryTargetGivesTheSameBits) {
  const std::vector<simd::Target> targets = simd::availableTargets();
  ASSERT_FALSE(targets.empty());
  EXPECT_EQ(targets.back(), simd::kScalar);
#ifdef RLD_EXPECT_VECTOR_TARGETS  // x86 and aarch64 builds with Highway
  EXPECT_GE(targets.size(), 2u) << "no vector target on this machine";
#endif
  std::vector<std::vector<Result>> results(targets.size());
  for (size_t k = 0; k < targets.size(); ++k) {
    simd::forceTarget(targets[k]);
    EXPECT_EQ(simd::currentTarget(), targets[k]);
    // improved: the road gate also keeps the normals; paper twice: G only where it enters R
    // (the default), and everywhere (setFullGeometricMap)
    for (int run = 0; run < 3; ++run) {
      LaneDetector det(run == 0 ? Params::improved() : Params::paper());
      det.setFullGeometricMap(run == 2);
      for (int i = 0; i < 4; ++i) {
        RoadScene scene;
        scene.width = 333;  // odd: vector bodies and scalar tails
        scene.height = 201;
        scene.K = Intrinsics{140.0, 140.0, 166.0, 100.0};
        scene.right_dashed = true;
        scene.lateral_offset = 0.2 * i;
        cv::Mat bgr, depth;
        Frame f = makeFrame(scene, bgr, depth);
        cv::circle(depth, cv::Point(60 + 40 * i, 150), 5, cv::Scalar(0), -1);  // missing depth
        cv::Mat depth_m;  // float metres on odd frames: the other depth kernel
        if (i % 2) {
          depth.convertTo(depth_m, CV_32FC1, 0.001);
          f.depth = depth_m;
        }
        results[k].emplace_back();
        ASSERT_EQ(det.detect(f, results[k].back()), Status::kOk);
        results[k].back().half_binary = results[k].back().half_binary.clone();  // kept
        results[k].back().geometric = results[k].back().geometric.clone();
        results[k].back().response_left = results[k].back().response_left.clone();
        results[k].back().response_right = results[k].back().response_right.clone();
      }
    }
  }
  simd::forceTarget(simd::kBest);
  const size_t ref = targets.size() - 1;  // the scalar target (the last, lowest)
  for (size_t k = 0; k < ref; ++k) {
    for (size_t i = 0; i < results[k].size(); ++i) {
      SCOPED_TRACE(testing::Message() << simd::targetName(targets[k]) << " against "
                                      << simd::targetName(targets[ref]) << ", frame " << i);
      const Result& a = results[k][i];
      const Result& b = results[ref][i];
      EXPECT_TRUE(sameBits(a.half_binary, b.half_binary));
      EXPECT_TRUE(sameBits(a.geometric, b.geometric));
      expectSameDetections(a, b);
    }
  }
}

// By default G is computed only where it enters R (M >= tau_G in any match map): R, the
// detections and the carried state are those of the whole map, frame after frame, and G is the
// whole map's there and 0 elsewhere. Improved mode: the acquisition templates add their maps.
TEST(LaneDetector, GeometricMapOnlyWhereItEntersRChangesNoDetection) {
  for (const Params& params : {Params::improved(), Params::paper()}) {
    SCOPED_TRACE(params.acquisition_angle_deg > 0.0 ? "improved" : "paper");
    LaneDetector whole(params), masked(params);
    whole.setFullGeometricMap(true);
    EXPECT_FALSE(masked.fullGeometricMap());
    int g_kept = 0;
    for (int i = 0; i < 6; ++i) {
      SCOPED_TRACE(testing::Message() << "frame " << i);
      RoadScene scene;
      scene.right_dashed = true;
      // toward the right line, so that it is steep in the image; reset() on odd frames: the
      // acquisition templates' maps (sides without a tracked line) enter R too
      scene.lateral_offset = 0.3 * i;
      scene.travelled = 2.0 * i;
      scene.right_painted = i != 4;
      if (i % 2) {
        whole.reset();
        masked.reset();
      }
      cv::Mat bgr, depth;
      Frame f = makeFrame(scene, bgr, depth);
      cv::circle(depth, cv::Point(200 + 30 * i, 400), 9, cv::Scalar(0), -1);  // missing depth
      Result a, b;
      ASSERT_EQ(whole.detect(f, a), Status::kOk);
      ASSERT_EQ(masked.detect(f, b), Status::kOk);
      expectSameDetections(a, b);
      EXPECT_EQ(a.template_angle_left, b.template_angle_left);
      EXPECT_EQ(a.template_angle_right, b.template_angle_right);
      // every traced line, the acquisition templates' included: same pixels, same R scores
      for (int side = 0; side < 2; ++side) {
        int na = 0, nb = 0;
        const BoundaryCandidate* ca = whole.candidates(side, na);
        const BoundaryCandidate* cb = masked.candidates(side, nb);
        ASSERT_EQ(na, nb);
        for (int k = 0; k < na; ++k) {
          EXPECT_EQ(ca[k].trace.pixels, cb[k].trace.pixels);
          EXPECT_EQ(ca[k].trace.scores, cb[k].trace.scores);
        }
      }
      const float tau = static_cast<float>(params.tau_g);
      int wrong = 0, zero_in_full = 0;
      for (int y = a.roi.y; y < a.roi.br().y; ++y)
        for (int x = 0; x < a.geometric.cols; ++x) {
          const float g = b.geometric.at<float>(y, x), full = a.geometric.at<float>(y, x);
          const bool enters =
              a.response_left.at<float>(y, x) >= tau || a.response_right.at<float>(y, x) >= tau;
          if (enters) {
            wrong += g != full;
            g_kept += g != 0.f;
          } else {
            wrong += g != 0.f && g != full;  // an acquisition map's pixel, or 0
          }
          zero_in_full += full == 0.f;
        }
      EXPECT_EQ(wrong, 0);
      EXPECT_LT(zero_in_full, a.roi.area() / 100) << "the whole map is not whole";
    }
    EXPECT_GT(g_kept, 500) << "no G where it enters R";
  }
}

// Fraction of a side's 3D points within 0.3 m laterally of the true marker (METHOD.md's rule).
double fractionNear(const MarkerTrace& m, double marker_x) {
  int n = 0, near = 0;
  for (const auto& p : m.points) {
    if (!p.allFinite()) continue;
    ++n;
    near += std::fabs(p.x() - marker_x) <= 0.3;
  }
  return n ? static_cast<double>(near) / n : 0.0;
}

// Both lines dashed (3 m paint, 9 m gap), the car driving 2 m per frame and drifting sideways:
// on many frames no dash is near. The paper mode then loses a side; the improved mode's lane
// model keeps both, with the plane, once it has seen both sides (a few frames).
TEST(LaneDetector, DashedLinesWhileDriving) {
  RoadScene scene;
  scene.left_dashed = true;
  scene.right_dashed = true;
  LaneDetector paper(Params::paper()), improved(Params::improved());
  Result rp, ri;
  int paper_complete = 0, improved_complete = 0, improved_correct = 0;
  const int frames = 30, warm_up = 6;
  for (int i = 0; i < frames; ++i) {
    scene.travelled = 2.0 * i;
    scene.lateral_offset = 0.25 * std::sin(0.3 * i);
    cv::Mat bgr, depth;
    const Frame f = makeFrame(scene, bgr, depth);
    ASSERT_EQ(paper.detect(f, rp), Status::kOk);
    ASSERT_EQ(improved.detect(f, ri), Status::kOk);
    if (i < warm_up) continue;
    paper_complete += rp.plane.valid && rp.left.found && rp.right.found;
    if (!(ri.plane.valid && ri.left.found && ri.right.found)) continue;
    ++improved_complete;
    improved_correct += angleDeg(ri.plane.normal, scene.planeNormal()) < 1.0 &&
                        std::fabs(ri.plane.distance - scene.planeDistance()) < 0.05 &&
                        ri.left.num_valid_points >= 5 && ri.right.num_valid_points >= 5 &&
                        fractionNear(ri.left, scene.leftMarkerX()) >= 0.8 &&
                        fractionNear(ri.right, scene.rightMarkerX()) >= 0.8;
  }
  EXPECT_EQ(improved_complete, frames - warm_up);
  EXPECT_EQ(improved_correct, improved_complete);
  EXPECT_LT(paper_complete, improved_complete);
}

// The road plane comes from depth: published on a road without any marking (the paper mode
// needs both markers for it), and nothing is reported as a lane boundary there.
TEST(LaneDetector, ImprovedModeFindsTheRoadWithoutMarkings) {
  RoadScene scene;
  scene.left_painted = scene.right_painted = false;
  cv::Mat bgr, depth;
  const Frame f = makeFrame(scene, bgr, depth);
  LaneDetector improved(Params::improved()), paper(Params::paper());
  Result ri, rp;
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(improved.detect(f, ri), Status::kOk);
    ASSERT_EQ(paper.detect(f, rp), Status::kOk);
    ASSERT_TRUE(ri.plane.valid) << i;
    EXPECT_LT(angleDeg(ri.plane.normal, scene.planeNormal()), 0.2);
    EXPECT_NEAR(ri.plane.distance, scene.planeDistance(), 0.01);
    EXPECT_EQ(ri.plane.fit_method, static_cast<int>(PlaneFit::kRoadSurface));
    EXPECT_FALSE(ri.left.found);
    EXPECT_FALSE(ri.right.found);
    EXPECT_FALSE(rp.plane.valid);
  }
}

// With the camera's mount (the vehicle frame) and depth that shows no road (a short-baseline
// stereo's depth far off, too sparse a LiDAR), the mount's plane is the road surface, and the
// markers are placed on it.
TEST(LaneDetector, WithoutRoadDepthTheMountIsTheRoad) {
  RoadScene scene;
  cv::Mat bgr, depth;
  Frame f = makeFrame(scene, bgr, depth);
  PlaneEstimate truth;
  truth.valid = true;
  truth.normal = scene.planeNormal();
  truth.distance = scene.planeDistance();
  f.has_vehicle_frame = true;
  f.vehicle_from_camera = RoadFrame::fromPlane(truth).roadFromCamera();
  // depth only above the horizon (trees, buildings): nothing of the road
  for (int v = static_cast<int>(scene.K.cy); v < depth.rows; ++v) depth.row(v).setTo(0);
  LaneDetector detector(Params::improved());
  Result r;
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(detector.detect(f, r), Status::kOk);
    ASSERT_TRUE(r.plane.valid) << i;
    EXPECT_LT(angleDeg(r.plane.normal, scene.planeNormal()), 1e-6);
    EXPECT_NEAR(r.plane.distance, scene.planeDistance(), 1e-6);
  }
  ASSERT_TRUE(r.left.found);
  ASSERT_TRUE(r.right.found);
  EXPECT_LT(meanLateralError(r.left, scene.leftMarkerX()), 0.1);
  EXPECT_LT(meanLateralError(r.right, scene.rightMarkerX()), 0.1);
  // without the mount: no plane, no markers placed
  f.has_vehicle_frame = false;
  LaneDetector without(Params::improved());
  ASSERT_EQ(without.detect(f, r), Status::kOk);
  EXPECT_FALSE(r.plane.valid);
  // a vehicle frame whose origin is 0.5 m above the road (not on it): once the depth has shown
  // the road 0.5 m below the mount's plane, that plane no longer stands in for frames without
  // road depth (the last plane holds for 5 of them, as against any jump)
  cv::Mat bgr2, full_depth;
  Frame g = makeFrame(scene, bgr2, full_depth);
  g.has_vehicle_frame = true;
  g.vehicle_from_camera = f.vehicle_from_camera;
  g.vehicle_from_camera.translation().z() -= 0.5;
  f.has_vehicle_frame = true;
  f.vehicle_from_camera = g.vehicle_from_camera;
  LaneDetector elevated(Params::improved());
  ASSERT_EQ(elevated.detect(g, r), Status::kOk);
  ASSERT_TRUE(r.plane.valid);
  EXPECT_NEAR(r.plane.distance, scene.planeDistance(), 0.01);  // from the depth
  for (int i = 0; i < 8; ++i) {
    ASSERT_EQ(elevated.detect(f, r), Status::kOk);
    const double mount_height = scene.planeDistance() - 0.5;
    EXPECT_FALSE(r.plane.valid && std::fabs(r.plane.distance - mount_height) < 0.01) << i;
  }
}

// The lane model's state lies in the frame it was updated in. When tf stops giving the vehicle
// frame (a late transform) the model goes on in the road frame under the camera, and a state
// carried over from base_link (here 1.5 m ahead of the camera and 1 m left of it) would be
// published as the road frame's: it starts again. So does a model switched off and on (its ages
// advance only in updates: the old lane would come back as current).
TEST(LaneDetector, TheLaneModelStartsAgainInAnotherFrameAndAfterBeingOffNotForNewTemplates) {
  RoadScene lines, bare;
  bare.left_painted = bare.right_painted = false;
  cv::Mat bgr, depth, bare_bgr, bare_depth;
  Frame f = makeFrame(lines, bgr, depth);
  Frame empty = makeFrame(bare, bare_bgr, bare_depth);
  PlaneEstimate truth;
  truth.valid = true;
  truth.normal = lines.planeNormal();
  truth.distance = lines.planeDistance();
  Eigen::Isometry3d vehicle_from_camera = RoadFrame::fromPlane(truth).roadFromCamera();
  vehicle_from_camera.pretranslate(Eigen::Vector3d(1.5, 1.0, 0.0));  // base_link behind, right
  for (const bool vehicle_first : {true, false}) {
    LaneDetector detector(Params::improved());
    Result r;
    f.has_vehicle_frame = vehicle_first;
    f.vehicle_from_camera = vehicle_from_camera;
    for (int i = 0; i < 4; ++i) ASSERT_EQ(detector.detect(f, r), Status::kOk);
    ASSERT_TRUE(r.lane_model.valid);
    const double left_c0 = r.lane_model.at(BoundaryPosition::kEgoLeft).c[0];
    EXPECT_NEAR(left_c0, -lines.leftMarkerX() + (vehicle_first ? 1.0 : 0.0), 0.15)
        << "+y is left of the frame's origin";
    empty.has_vehicle_frame = vehicle_first;  // a frame without lines, the same frame: kept
    empty.vehicle_from_camera = vehicle_from_camera;
    ASSERT_EQ(detector.detect(empty, r), Status::kOk);
    EXPECT_TRUE(r.lane_model.valid) << "one frame without lines keeps the lane";
    ASSERT_EQ(detector.detect(f, r), Status::kOk);
    empty.has_vehicle_frame = !vehicle_first;  // the same, but in the other frame
    ASSERT_EQ(detector.detect(empty, r), Status::kOk);
    EXPECT_FALSE(r.lane_model.valid) << "a lane of the other frame was carried over";
  }
  LaneDetector detector(Params::improved());
  Result r;
  f.has_vehicle_frame = empty.has_vehicle_frame = false;
  for (int i = 0; i < 4; ++i) ASSERT_EQ(detector.detect(f, r), Status::kOk);
  ASSERT_TRUE(r.lane_model.valid);
  // new templates (reconfigured live) start only the templates' adapted angles again
  Params wider = Params::improved();
  wider.template_size += 2;
  detector.setParams(wider);
  ASSERT_EQ(detector.detect(empty, r), Status::kOk);
  EXPECT_TRUE(r.lane_model.valid) << "a new template size threw away the lane";
  EXPECT_TRUE(r.left.found && r.right.found) << "the tracked sides were thrown away";
  ASSERT_EQ(detector.detect(f, r), Status::kOk);
  Params off = Params::improved();
  off.lane_model = false;
  detector.setParams(off);
  ASSERT_EQ(detector.detect(f, r), Status::kOk);
  EXPECT_FALSE(r.lane_model.valid);
  detector.setParams(Params::improved());
  ASSERT_EQ(detector.detect(empty, r), Status::kOk);
  EXPECT_FALSE(r.lane_model.valid) << "the lane from before the model was off came back";
}

// One side without paint (a kerb-less edge, worn paint): the other side is reported on its own,
// with its confidence; with report_only_complete nothing is.
TEST(LaneDetector, OneGoodSideIsReportedOnItsOwn) {
  RoadScene scene;
  scene.right_painted = false;
  cv::Mat bgr, depth;
  const Frame f = makeFrame(scene, bgr, depth);
  Params complete = Params::improved();
  complete.report_only_complete = true;
  LaneDetector det(Params::improved()), strict(complete);
  Result r, rs;
  for (int i = 0; i < 4; ++i) {
    ASSERT_EQ(det.detect(f, r), Status::kOk);
    ASSERT_EQ(strict.detect(f, rs), Status::kOk);
  }
  ASSERT_TRUE(r.left.found);
  EXPECT_EQ(r.left.kind, BoundaryKind::kPaint);
  EXPECT_LT(meanLateralError(r.left, scene.leftMarkerX()), 0.1);
  EXPECT_GT(r.left.confidence, 0.5f);
  EXPECT_LE(r.left.confidence, 1.0f);
  EXPECT_FALSE(r.right.found);
  EXPECT_EQ(r.right.confidence, 0.0f);
  EXPECT_TRUE(r.plane.valid);
  EXPECT_FALSE(rs.left.found);
  EXPECT_FALSE(rs.right.found);
}

// No depth in the bottom rows (LiDAR and stereo gaps near the car): the markers there are
// placed on the road plane fitted to the depth further ahead, and both sides are found.
TEST(LaneDetector, NoDepthNearTheCar) {
  RoadScene scene;
  scene.left_dashed = true;
  scene.min_range = 9.0;  // no depth nearer than 9 m: the bottom half of the road rows
  LaneDetector improved(Params::improved());
  int found = 0;
  for (int i = 0; i < 8; ++i) {
    scene.travelled = 2.0 * i;
    cv::Mat bgr, depth;
    const Frame f = makeFrame(scene, bgr, depth);
    Result r;
    ASSERT_EQ(improved.detect(f, r), Status::kOk);
    if (i < 2) continue;
    ASSERT_TRUE(r.plane.valid) << i;
    EXPECT_LT(angleDeg(r.plane.normal, scene.planeNormal()), 0.2);
    if (!(r.left.found && r.right.found)) continue;
    ++found;
    EXPECT_GE(fractionNear(r.left, scene.leftMarkerX()), 0.8) << i;
    EXPECT_GE(fractionNear(r.right, scene.rightMarkerX()), 0.8) << i;
    // points nearer than the depth reaches: from the plane
    double nearest = 1e9;
    for (const auto& p : r.right.points)
      if (p.allFinite()) nearest = std::min(nearest, static_cast<double>(p.z()));
    EXPECT_LT(nearest, scene.min_range) << i;
  }
  EXPECT_EQ(found, 6);
}

}  // namespace
}  // namespace rgbd_lane_detector
