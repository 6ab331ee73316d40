// Left-right symmetry of the whole detector: a road seen in a mirror (colour and depth flipped
// left-right, cx -> width - 1 - cx) gives the mirror of the detections: the same maps flipped
// (R of the "/" template is the flipped R of the "\" one), the left and right sides swapped at
// mirrored pixels, the same kinds, the plane's normal with its x negated.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/lane_detector.h"
#include "synthetic_scene.h"

namespace rgbd_lane_detector {
namespace {

using test::RoadScene;

struct Views {
  cv::Mat bgr, depth, mbgr, mdepth;
  Frame f, m;
};

void makeViews(const RoadScene& scene, Views& v) {
  scene.render(v.bgr, v.depth);
  cv::flip(v.bgr, v.mbgr, 1);
  cv::flip(v.depth, v.mdepth, 1);
  for (Frame* fr : {&v.f, &v.m}) {
    fr->format = PixelFormat::kBgr8;
    fr->depth_scale = 0.001;
  }
  v.f.colour = v.bgr;
  v.f.depth = v.depth;
  v.f.intrinsics = scene.K;
  v.m.colour = v.mbgr;
  v.m.depth = v.mdepth;
  v.m.intrinsics = scene.K;
  v.m.intrinsics.cx = scene.width - 1 - scene.K.cx;
}

// Largest |a - flip(b)| (0 for two empty maps; infinity for different sizes).
double flippedDifference(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() && b.empty()) return 0.0;
  if (a.size() != b.size() || a.type() != b.type()) return INFINITY;
  cv::Mat fb, d;
  cv::flip(b, fb, 1);
  cv::absdiff(a, fb, d);
  double mx = 0;
  cv::minMaxLoc(d.reshape(1), nullptr, &mx);
  return mx;
}

// a is the mirror of b: same found/kind, seeds and traced pixels at x -> width - 1 - x,
// 3D points with x negated.
void expectMirrored(const MarkerTrace& a, const MarkerTrace& b, int width, double px_tol,
                    double m_tol, const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_EQ(a.found, b.found);
  if (!a.found) return;
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_NEAR(a.seed.x, width - 1 - b.seed.x, px_tol);
  EXPECT_NEAR(a.seed.y, b.seed.y, px_tol);
  EXPECT_EQ(a.angle_valid, b.angle_valid);
  if (a.angle_valid && b.angle_valid) {
    EXPECT_NEAR(a.angle, M_PI - b.angle, 1e-4);
  }
  EXPECT_NEAR(a.confidence, b.confidence, 1e-4);
  EXPECT_NEAR(a.paint_coverage, b.paint_coverage, 1e-3);
  EXPECT_NEAR(a.yellowness, b.yellowness, 1e-3);
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    EXPECT_NEAR(a.pixels[i].x, width - 1 - b.pixels[i].x, px_tol) << "pixel " << i;
    EXPECT_NEAR(a.pixels[i].y, b.pixels[i].y, px_tol) << "pixel " << i;
  }
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) {
    if (!a.points[i].allFinite() || !b.points[i].allFinite()) {
      EXPECT_EQ(a.points[i].allFinite(), b.points[i].allFinite()) << "point " << i;
      continue;
    }
    EXPECT_NEAR(a.points[i].x(), -b.points[i].x(), m_tol) << "point " << i;
    EXPECT_NEAR(a.points[i].y(), b.points[i].y(), m_tol) << "point " << i;
    EXPECT_NEAR(a.points[i].z(), b.points[i].z(), m_tol) << "point " << i;
  }
}

struct Case {
  const char* name;
  double lateral_offset;
  bool left_dashed, right_dashed, left_painted, right_painted;
};

// px: the traced pixels' tolerance (improved mode: the lane tracker's reported pixels of a frame
// come out up to 0.15 px apart, the same way on both sides; not found). plane_tol: the paper's
// three-point plane takes its third point on the right line (the method as written), so a
// mirror fits it through other points.
void runCase(const Params& params, const Case& c, int frames, double px, double plane_tol) {
  SCOPED_TRACE(c.name);
  LaneDetector det(params), mdet(params);
  Result r, mr;
  for (int i = 0; i < frames; ++i) {
    SCOPED_TRACE(testing::Message() << "frame " << i);
    RoadScene scene;
    scene.lateral_offset = c.lateral_offset;
    scene.left_dashed = c.left_dashed;
    scene.right_dashed = c.right_dashed;
    scene.left_painted = c.left_painted;
    scene.right_painted = c.right_painted;
    scene.travelled = 1.3 * i;
    Views v;
    makeViews(scene, v);
    ASSERT_EQ(det.detect(v.f, r), Status::kOk);
    ASSERT_EQ(mdet.detect(v.m, mr), Status::kOk);
    // the maps: exact (pixel-wise the same operations), within float rounding
    EXPECT_EQ(r.roi, mr.roi);
    EXPECT_EQ(flippedDifference(r.half_binary, mr.half_binary), 0.0) << "half-binary image";
    EXPECT_LE(flippedDifference(r.geometric, mr.geometric), 1e-4) << "G";
    EXPECT_LE(flippedDifference(r.response_left, mr.response_right), 1e-4) << "R left vs right";
    EXPECT_LE(flippedDifference(r.response_right, mr.response_left), 1e-4) << "R right vs left";
    EXPECT_NEAR(r.template_angle_left, M_PI - mr.template_angle_right, 1e-6);
    // the detections: the same within a small fraction of a pixel / a millimetre
    const double m = 0.002;
    expectMirrored(r.left, mr.right, scene.width, px, m, "left vs mirrored right");
    expectMirrored(r.right, mr.left, scene.width, px, m, "right vs mirrored left");
    expectMirrored(r.outer[kNextLeft], mr.outer[kNextRight], scene.width, px, m, "next left");
    expectMirrored(r.outer[kNextRight], mr.outer[kNextLeft], scene.width, px, m, "next right");
    expectMirrored(r.outer[kRoadEdgeLeft], mr.outer[kRoadEdgeRight], scene.width, px, m,
                   "road edge left");
    expectMirrored(r.outer[kRoadEdgeRight], mr.outer[kRoadEdgeLeft], scene.width, px, m,
                   "road edge right");
    ASSERT_EQ(r.plane.valid, mr.plane.valid);
    if (r.plane.valid) {
      EXPECT_NEAR(r.plane.normal.x(), -mr.plane.normal.x(), plane_tol);
      EXPECT_NEAR(r.plane.normal.y(), mr.plane.normal.y(), plane_tol);
      EXPECT_NEAR(r.plane.normal.z(), mr.plane.normal.z(), plane_tol);
      EXPECT_NEAR(r.plane.distance, mr.plane.distance, 10 * plane_tol);
    }
  }
}

const Case kCases[] = {
    {"centred, solid", 0.0, false, false, true, true},
    {"off centre, right dashed", 0.35, false, true, true, true},
    {"off centre left, left dashed", -0.5, true, false, true, true},
    {"one line painted", 0.2, false, false, true, false},
};

// An odd template: the matcher writes a template's score at its centre pixel. (An even one, the
// default 32, has its centre between two pixels and its score half a pixel right of it: a
// mirrored road's lines come out a pixel off, and the discrete choices after the match with
// them.)
Params odd(Params p) {
  p.template_size = 33;
  return p;
}

TEST(MirrorSymmetry, PaperMode) {
  for (const Case& c : kCases) runCase(odd(Params::paper()), c, 3, 0.01, 1e-3);
}

TEST(MirrorSymmetry, ImprovedMode) {
  for (const Case& c : kCases) runCase(odd(Params::improved()), c, 4, 0.2, 1e-4);
}

}  // namespace
}  // namespace rgbd_lane_detector
