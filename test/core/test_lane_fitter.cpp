// The lane fit: each side's nearest boundary among its candidates, on its own, tracked, with
// its kind and a confidence; the paper's three-point plane in the paper mode.
#include <cmath>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/lane_fitter.h"

namespace rgbd_lane_detector {
namespace {

const Intrinsics kK{266.37, 266.37, 320.0, 190.0};
constexpr double kHeight = 1.5;

PlaneEstimate road() {
  PlaneEstimate p;
  p.valid = true;
  p.normal = Eigen::Vector3d(0, -1, 0);
  p.distance = kHeight;
  p.range = 60.0;
  p.fit_method = static_cast<int>(PlaneFit::kRoadSurface);
  return p;
}

// A traced paint line on the level road, 4-30 m ahead, with its depth; @p x_at: its camera x
// (right) at range z.
template <typename LateralAt>
BoundaryCandidate tracedLine(LateralAt x_at) {
  BoundaryCandidate c;
  c.trace.peak_score = 1.2f;
  c.trace.angle_valid = true;
  for (double z = 4.0; z <= 30.0; z *= 1.1) {
    const double x = x_at(z);
    c.trace.pixels.emplace_back(static_cast<float>(kK.fx * x / z + kK.cx),
                                static_cast<float>(kK.fy * kHeight / z + kK.cy));
    c.trace.points.emplace_back(static_cast<float>(x), static_cast<float>(kHeight),
                                static_cast<float>(z));
    c.trace.scores.push_back(1.0f);
  }
  c.trace.num_valid_points = static_cast<int>(c.trace.points.size());
  c.trace.seed = c.trace.pixels.front();
  c.trace.seed_point = c.trace.points.front();
  c.evidence.boundary = true;
  c.evidence.kind = BoundaryKind::kPaint;
  c.evidence.margin = 0.8f;
  return c;
}

// A traced line at lateral x (camera x, right) on the level road, 4-30 m ahead, with its depth.
BoundaryCandidate line(double x, BoundaryKind kind, bool boundary = true, float margin = 0.8f) {
  BoundaryCandidate c = tracedLine([x](double) { return x; });
  c.evidence.boundary = boundary;
  c.evidence.kind = kind;
  c.evidence.margin = margin;
  return c;
}

// Mean lateral position of a side's reported points.
double meanX(const MarkerTrace& m) {
  double s = 0;
  int n = 0;
  for (const auto& p : m.points)
    if (p.allFinite()) {
      s += p.x();
      ++n;
    }
  return n ? s / n : NAN;
}

struct Frame {
  std::array<std::vector<BoundaryCandidate>, 2> candidates;
  PlaneEstimate plane = road();
  Result result;

  void fit(LaneFitter& fitter) {
    LaneFitInput in;
    in.K = kK;
    in.road = &plane;
    in.road_range = plane.range;
    in.candidates = &candidates;
    in.counts = {static_cast<int>(candidates[0].size()), static_cast<int>(candidates[1].size())};
    fitter.fit(in, result);
  }
};

LaneFitter improved() {
  LaneFitter f;
  f.setParams(Params::improved());
  return f;
}

const BoundaryKind kPaint = BoundaryKind::kPaint;
const BoundaryKind kEdge = BoundaryKind::kRoadEdge;

TEST(LaneFitter, NearestBoundaryOfEachSide) {
  LaneFitter fitter = improved();
  Frame f;
  // left: the paint next to the car, a rail and the next lane's line beyond it
  f.candidates[0] = {line(-3.6, kPaint), line(-2.4, kEdge), line(-1.8, kPaint)};
  f.candidates[1] = {line(1.9, kEdge)};  // a kerb
  f.fit(fitter);
  ASSERT_TRUE(f.result.plane.valid);
  ASSERT_TRUE(f.result.left.found);
  EXPECT_NEAR(meanX(f.result.left), -1.8, 0.02);
  EXPECT_EQ(f.result.left.kind, kPaint);
  ASSERT_TRUE(f.result.right.found);
  EXPECT_NEAR(meanX(f.result.right), 1.9, 0.02);
  EXPECT_EQ(f.result.right.kind, kEdge);
  // reported points lie on the plane and project onto the image
  for (size_t i = 0; i < f.result.left.points.size(); ++i) {
    EXPECT_NEAR(f.result.left.points[i].y(), kHeight, 1e-4);
    const auto& p = f.result.left.points[i];
    EXPECT_NEAR(f.result.left.pixels[i].x, kK.fx * p.x() / p.z() + kK.cx, 1e-3);
  }
}

TEST(LaneFitter, EachSideOnItsOwn) {
  Frame f;
  f.candidates[0] = {line(-1.8, kPaint)};
  LaneFitter fitter = improved();
  f.fit(fitter);
  EXPECT_TRUE(f.result.left.found);
  EXPECT_GT(f.result.left.confidence, 0.0f);
  EXPECT_FALSE(f.result.right.found);
  EXPECT_EQ(f.result.right.confidence, 0.0f);
  EXPECT_TRUE(f.result.plane.valid);

  Params complete = Params::improved();
  complete.report_only_complete = true;
  LaneFitter strict;
  strict.setParams(complete);
  Frame g;
  g.candidates[0] = {line(-1.8, kPaint)};
  g.fit(strict);
  EXPECT_FALSE(g.result.left.found);
  EXPECT_FALSE(g.result.right.found);
  EXPECT_TRUE(g.result.plane.valid);  // the road is still there
}

TEST(LaneFitter, LinesThatCannotBeThisSidesBoundary) {
  LaneFitter fitter = improved();
  Frame f;
  // under the camera (an arrow, a crack), beyond any lane, on the other side of the car, not a
  // boundary at all, across the road
  f.candidates[0] = {line(-0.05, kPaint), line(-6.0, kPaint), line(1.5, kPaint),
                     line(-1.8, kPaint, false)};
  BoundaryCandidate across = line(-1.8, kPaint);
  for (size_t i = 0; i < across.trace.points.size(); ++i) {  // heading 45 deg
    auto& p = across.trace.points[i];
    p.x() = static_cast<float>(-1.8 - (p.z() - 4.0));
    across.trace.pixels[i].x = static_cast<float>(kK.fx * p.x() / p.z() + kK.cx);
  }
  f.candidates[0].push_back(across);
  f.fit(fitter);
  EXPECT_FALSE(f.result.left.found);
  for (const auto& c : f.candidates[0]) EXPECT_FALSE(c.usable);
}

TEST(LaneFitter, TrackedBoundaryBeforeANewNearerLine) {
  LaneFitter fitter = improved();
  for (int i = 0; i < 3; ++i) {
    Frame f;
    f.candidates[0] = {line(-1.8, kPaint)};
    f.candidates[1] = {line(1.8, kPaint)};
    f.fit(fitter);
  }
  // one frame with an arrow-like paint line between the car and the tracked boundary
  Frame f;
  f.candidates[0] = {line(-0.9, kPaint), line(-1.8, kPaint)};
  f.candidates[1] = {line(1.8, kPaint)};
  f.fit(fitter);
  ASSERT_TRUE(f.result.left.found);
  EXPECT_NEAR(meanX(f.result.left), -1.8, 0.05);
}

// A traced paint line at lateral y0 (RoadFrame y, left) at the camera and heading slope (dy/dz),
// 4-30 m ahead on the level road (camera x = -y).
BoundaryCandidate slanted(double y0, double slope) {
  return tracedLine([y0, slope](double z) { return -(y0 + slope * z); });
}

// Mean lateral distance (m) of a side's reported points from the line y = y0 + slope z.
double offLine(const MarkerTrace& m, double y0, double slope) {
  double s = 0;
  int n = 0;
  for (const auto& p : m.points)
    if (p.allFinite()) {
      s += std::fabs(-p.x() - (y0 + slope * p.z()));
      ++n;
    }
  return n ? s / n : NAN;
}

TEST(LaneFitter, ACrossedLineChangesSidesWhenTheVehiclePassesIt) {
  // A lane change to the left: the vehicle heads 0.1 rad left of the lane and moves 0.2 m left
  // per frame. The left line is the ego lane's left boundary while it is left of the vehicle
  // (its lateral position at the camera, y0 > 0: the lane model's and the ground truth's rule
  // too), although 1.5 m ahead, where the vehicle heads, it is already to the right; once the
  // vehicle has passed it, it is the right boundary. A line within boundary_offset_min of the
  // camera is no usable candidate: the tracker carries it over those frames.
  LaneFitter fitter = improved();
  const double slope = -0.1;  // the lane, seen from the vehicle, runs to the right
  for (int k = 0; k <= 7; ++k) {
    const double crossed = 1.07 - 0.2 * k;  // y0 of the line the vehicle crosses
    Frame f;
    for (double y0 : {crossed + 3.6, crossed, crossed - 3.6}) {
      // each side's candidates: the lines seen on that side of the image at 4 m
      f.candidates[y0 + slope * 4.0 > 0.0 ? 0 : 1].push_back(slanted(y0, slope));
    }
    f.fit(fitter);
    if (crossed > 0.0) {
      ASSERT_TRUE(f.result.left.found) << k;
      EXPECT_LT(offLine(f.result.left, crossed, slope), 0.1) << k;
      if (f.result.right.found) {
        EXPECT_LT(offLine(f.result.right, crossed - 3.6, slope), 0.1) << k;
      }
    } else if (k == 7) {
      ASSERT_TRUE(f.result.right.found);
      EXPECT_LT(offLine(f.result.right, crossed, slope), 0.1);
    }
  }
}

TEST(LaneFitter, ConfidenceGrowsWithEvidenceAndFadesWithout) {
  Params p = Params::improved();
  LaneFitter fitter;
  fitter.setParams(p);
  float last = 0.0f;
  for (int i = 0; i < 6; ++i) {
    Frame f;
    f.candidates[0] = {line(-1.8, kPaint)};
    f.fit(fitter);
    ASSERT_TRUE(f.result.left.found);
    EXPECT_GT(f.result.left.confidence, last) << i;
    EXPECT_LE(f.result.left.confidence, 1.0f);
    last = f.result.left.confidence;
  }
  for (int i = 0; i < p.track_max_age; ++i) {  // the paint disappears: bridged, less sure
    Frame f;
    f.fit(fitter);
    ASSERT_TRUE(f.result.left.found) << i;
    EXPECT_LT(f.result.left.confidence, last) << i;
    last = f.result.left.confidence;
  }
  Frame f;
  f.fit(fitter);
  EXPECT_FALSE(f.result.left.found);  // forgotten after track_max_age frames
}

TEST(LaneFitter, RoadEdgesAloneAreNoLane) {
  // a street without markings: kerbs (or parked cars' line) on both sides, no paint
  LaneFitter fitter = improved();
  for (int i = 0; i < 4; ++i) {
    Frame f;
    f.candidates[0] = {line(-2.6, kEdge)};
    f.candidates[1] = {line(2.4, kEdge)};
    f.fit(fitter);
    EXPECT_FALSE(f.result.left.found) << i;
    EXPECT_FALSE(f.result.right.found) << i;
    EXPECT_TRUE(f.result.plane.valid);  // the road surface is still published
  }
  // paint on one side: the kerb on the other bounds that lane
  LaneFitter marked = improved();
  Frame f;
  f.candidates[0] = {line(-1.8, kPaint)};
  f.candidates[1] = {line(2.4, kEdge)};
  f.fit(marked);
  ASSERT_TRUE(f.result.left.found && f.result.right.found);
  EXPECT_EQ(f.result.right.kind, kEdge);
}

TEST(LaneFitter, KindFollowsTheEvidence) {
  LaneFitter fitter = improved();
  BoundaryKind kind = kEdge;
  for (int i = 0; i < 8; ++i) {
    Frame f;
    // classified as a road edge twice, then paint from then on (a worn line), beside paint
    f.candidates[0] = {line(-1.8, kPaint)};
    f.candidates[1] = {line(1.8, i < 2 ? kEdge : kPaint)};
    f.fit(fitter);
    ASSERT_TRUE(f.result.right.found);
    kind = f.result.right.kind;
    if (i < 2) {
      EXPECT_EQ(kind, kEdge) << i;
    }
  }
  EXPECT_EQ(kind, kPaint);
}

TEST(LaneFitter, SidesCloserThanALaneDropTheWeakerOne) {
  LaneFitter fitter = improved();
  Frame f;
  f.candidates[0] = {line(-0.3, kPaint, true, 0.9f)};
  f.candidates[1] = {line(0.3, kPaint, true, 0.1f)};  // 0.6 m apart
  f.fit(fitter);
  EXPECT_TRUE(f.result.left.found);
  EXPECT_FALSE(f.result.right.found);
}

TEST(LaneFitter, NoRoadNoBoundaries) {
  LaneFitter fitter = improved();
  Frame f;
  f.plane.valid = false;
  f.candidates[0] = {line(-1.8, kPaint)};
  f.fit(fitter);
  EXPECT_FALSE(f.result.plane.valid);
  EXPECT_FALSE(f.result.left.found);
}

TEST(LaneFitter, PaperModeThreePointPlaneFromTheBestSeeds) {
  LaneFitter fitter;
  fitter.setParams(Params::paper());
  Frame f;
  f.candidates[0] = {line(-1.8, kPaint)};
  f.candidates[1] = {line(1.8, kPaint)};
  f.plane.valid = false;  // the paper mode does not use the road surface
  f.fit(fitter);
  ASSERT_TRUE(f.result.plane.valid);
  EXPECT_EQ(f.result.plane.fit_method, static_cast<int>(PlaneFit::kThreePoint));
  EXPECT_NEAR(f.result.plane.distance, kHeight, 1e-4);
  EXPECT_NEAR(f.result.plane.normal.y(), -1.0, 1e-6);
  EXPECT_TRUE(f.result.left.found);
  EXPECT_TRUE(f.result.right.found);
  // one side only: nothing (both sides or nothing)
  LaneFitter one;
  one.setParams(Params::paper());
  Frame g;
  g.candidates[0] = {line(-1.8, kPaint)};
  g.fit(one);
  EXPECT_FALSE(g.result.plane.valid);
}

}  // namespace
}  // namespace rgbd_lane_detector
