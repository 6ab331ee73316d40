// Temporal lane model: boundaries in the road plane (softly parallel), gap bridging, drift,
// outliers, reported ranges.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/lane_tracker.h"

namespace rgbd_lane_detector {
namespace {

// A level road 1.5 m below the camera: forward = z, lateral (RoadFrame y, left) = -x. The
// markers are placed at camera x (right); the tracker's lateral positions are y = -x.
PlaneEstimate road() {
  PlaneEstimate p;
  p.valid = true;
  p.normal = Eigen::Vector3d(0, -1, 0);
  p.distance = 1.5;
  return p;
}

std::vector<Eigen::Vector3f> marker(double (*lateral)(double), double offset, double f0,
                                    double f1, double step = 1.0) {
  std::vector<Eigen::Vector3f> pts;
  for (double f = f0; f <= f1 + 1e-9; f += step)
    pts.emplace_back(static_cast<float>(lateral(f) + offset), 1.5f, static_cast<float>(f));
  return pts;
}

double straight(double) { return 0.0; }
double curved(double f) { return f * f / (2.0 * 300.0); }  // 300 m radius to the right

const std::vector<Eigen::Vector3f> kNone;

TEST(LaneTracker, StraightLaneFromOneFrame) {
  LaneTracker t;
  const RoadFrame f = RoadFrame::fromPlane(road());
  TrackerParams tp;
  t.update(f, marker(straight, -1.8, 3, 20), marker(straight, 1.8, 3, 20), tp);
  ASSERT_TRUE(t.valid(0) && t.valid(1));
  for (double d : {3.0, 10.0, 20.0}) {
    EXPECT_NEAR(t.lateral(0, d), 1.8, 0.01);
    EXPECT_NEAR(t.lateral(1, d), -1.8, 0.01);
  }
  std::vector<Eigen::Vector3f> out;
  t.sample(0, f, tp.sample_step, out);
  ASSERT_GE(out.size(), 5u);
  for (size_t i = 0; i < out.size(); ++i) {
    EXPECT_NEAR(out[i].x(), -1.8f, 0.01f);
    EXPECT_NEAR(out[i].y(), 1.5f, 1e-5f);  // on the plane
    EXPECT_GE(out[i].z(), 3.0f - 1e-4f);
    EXPECT_LE(out[i].z(), 20.0f + 1e-4f);
    if (i > 0) {
      EXPECT_GT(out[i].z(), out[i - 1].z());  // near to far
    }
  }
}

TEST(LaneTracker, BridgesADashGapAndForgetsAfterMaxAge) {
  LaneTracker t;
  const RoadFrame f = RoadFrame::fromPlane(road());
  TrackerParams tp;
  tp.max_age = 6;
  for (int i = 0; i < 2; ++i)
    t.update(f, marker(straight, -1.8, 4, 8), marker(straight, 1.8, 3, 30), tp);
  // no paint on the left for max_age frames: the left marker is still known and still parallel
  for (int i = 0; i < tp.max_age; ++i) {
    t.update(f, kNone, marker(straight, 1.8, 3, 30), tp);
    ASSERT_TRUE(t.valid(0)) << i;
  }
  EXPECT_NEAR(t.lateral(0, 25.0), 1.8, 0.02);
  std::vector<Eigen::Vector3f> out;
  t.sample(0, f, tp.sample_step, out);
  ASSERT_FALSE(out.empty());
  // reported 4 m beyond its own short evidence, not over all of the other side's 30 m
  EXPECT_NEAR(out.back().z(), 8.0f + 4.0f, 0.3f);
  t.update(f, kNone, marker(straight, 1.8, 3, 30), tp);
  EXPECT_FALSE(t.valid(0));
  EXPECT_TRUE(t.valid(1));
}

TEST(LaneTracker, SidewaysMotionMovesBothMarkers) {
  LaneTracker t;
  const RoadFrame f = RoadFrame::fromPlane(road());
  TrackerParams tp;
  t.update(f, marker(straight, -1.8, 3, 20), marker(straight, 1.8, 3, 20), tp);
  t.update(f, marker(straight, -1.8, 3, 20), marker(straight, 1.8, 3, 20), tp);
  // the car drifts right 0.1 m per frame: the lane moves left; only the right side is seen
  double shift = 0.0;
  for (int i = 0; i < 5; ++i) {
    shift -= 0.1;
    t.update(f, kNone, marker(straight, 1.8 + shift, 3, 20), tp);
  }
  EXPECT_NEAR(t.lateral(1, 10.0), -1.8 - shift, 0.02);
  EXPECT_NEAR(t.lateral(0, 10.0), 1.8 - shift, 0.03);  // followed without evidence of its own
}

TEST(LaneTracker, RejectsStrayPointsButFollowsALaneChange) {
  LaneTracker t;
  const RoadFrame f = RoadFrame::fromPlane(road());
  TrackerParams tp;
  for (int i = 0; i < 3; ++i)
    t.update(f, marker(straight, -1.8, 3, 20), marker(straight, 1.8, 3, 20), tp);
  // a stray trace 1 m off on the left (a shadow edge) in one frame: rejected
  t.update(f, marker(straight, -0.8, 3, 20), marker(straight, 1.8, 3, 20), tp);
  EXPECT_NEAR(t.lateral(0, 10.0), 1.8, 0.02);
  // the left side is lost for a while, then seen for good 3.6 m further left (lane change)
  for (int i = 0; i < 4; ++i) t.update(f, kNone, kNone, tp);
  t.update(f, marker(straight, -5.4, 3, 20), marker(straight, -1.8, 3, 20), tp);
  EXPECT_NEAR(t.lateral(0, 10.0), 5.4, 0.05);
  EXPECT_NEAR(t.lateral(1, 10.0), 1.8, 0.05);
}

TEST(LaneTracker, FirstEvidenceIsTrimmedToItsOwnLine) {
  LaneTracker t;
  const RoadFrame f = RoadFrame::fromPlane(road());
  TrackerParams tp;
  std::vector<Eigen::Vector3f> left = marker(straight, -1.8, 3, 20);
  for (double d = 12; d <= 18; d += 1.0)  // the trace left the marker along a vehicle's edge
    left.emplace_back(static_cast<float>(-1.8 + 0.5 * (d - 10.0)), 1.5f, static_cast<float>(d));
  t.update(f, left, marker(straight, 1.8, 3, 20), tp);
  EXPECT_NEAR(t.lateral(0, 16.0), 1.8, 0.05);
}

TEST(LaneTracker, CurvedLane) {
  LaneTracker t;
  const RoadFrame f = RoadFrame::fromPlane(road());
  TrackerParams tp;
  for (int i = 0; i < 3; ++i)
    t.update(f, marker(curved, -1.8, 3, 40, 0.5), marker(curved, 1.8, 3, 40, 0.5), tp);
  for (double d : {5.0, 20.0, 35.0}) {
    EXPECT_NEAR(t.lateral(0, d), 1.8 - curved(d), 0.05) << d;
    EXPECT_NEAR(t.lateral(1, d), -1.8 - curved(d), 0.05) << d;
  }
}

double diverging(double f) { return 0.08 * f; }  // a kerb leaving the lane (4.6 deg)
double heading(double f) { return 0.05 * f; }     // both lines at 2.9 deg to the camera

TEST(LaneTracker, TwoWellSeenSidesKeepTheirOwnHeadings) {
  // paint straight ahead on the left, a kerb turning away on the right (before an intersection):
  // each side seen over 3-30 m follows its own points, not a shared shape
  LaneTracker t;
  const RoadFrame f = RoadFrame::fromPlane(road());
  TrackerParams tp;
  for (int i = 0; i < 3; ++i)
    t.update(f, marker(straight, -1.8, 3, 30, 0.5), marker(diverging, 1.8, 3, 30, 0.5), tp);
  for (double d : {5.0, 15.0, 25.0}) {
    EXPECT_NEAR(t.lateral(0, d), 1.8, 0.1) << d;
    EXPECT_NEAR(t.lateral(1, d), -1.8 - diverging(d), 0.1) << d;
  }
}

TEST(LaneTracker, AShortDashTakesItsShapeFromTheOtherSide) {
  // one dash of 2 m on the right says little of its heading: it runs parallel to the left line
  LaneTracker t;
  const RoadFrame f = RoadFrame::fromPlane(road());
  TrackerParams tp;
  std::vector<Eigen::Vector3f> dash = marker(heading, 1.8, 10, 12, 0.25);
  for (size_t k = 0; k < dash.size(); ++k)  // 3 cm of noise, the far half to one side
    dash[k].x() += k < dash.size() / 2 ? -0.03f : 0.03f;
  for (int i = 0; i < 3; ++i) t.update(f, marker(heading, -1.8, 3, 40, 0.5), dash, tp);
  EXPECT_NEAR(t.lateral(1, 11.0), -1.8 - heading(11.0), 0.05);
  EXPECT_NEAR(t.lateral(1, 30.0), -1.8 - heading(30.0), 0.15);
}

TEST(LaneTracker, ARoadEdgeIsReportedLessFarBeyondItsEvidence) {
  LaneTracker t;
  const RoadFrame f = RoadFrame::fromPlane(road());
  TrackerParams tp;
  t.update(f, marker(straight, -1.8, 3, 30), marker(straight, 1.8, 4, 10), tp);
  std::vector<Eigen::Vector3f> out;
  t.sample(1, f, tp.sample_step, out, LaneTracker::kEdgeExtrapolation);
  ASSERT_FALSE(out.empty());
  EXPECT_NEAR(out.back().z(), 10.0f + LaneTracker::kEdgeExtrapolation, 0.3f);
  EXPECT_NEAR(out.front().z(), 3.0f, 0.3f);  // toward the car: the other side's 3 m
  t.sample(1, f, tp.sample_step, out, 0.0);
  EXPECT_NEAR(out.back().z(), 10.0f, 0.3f);
  EXPECT_NEAR(out.front().z(), 4.0f, 0.3f);
  // evidence shorter than 2 m is no boundary
  LaneTracker s;
  s.update(f, kNone, marker(straight, 1.8, 4, 5.5, 0.25), tp);
  ASSERT_TRUE(s.valid(1));
  s.sample(1, f, tp.sample_step, out, 0.0);
  EXPECT_TRUE(out.empty());
}

// Points of a straight line at lateral offset + slope f (RoadFrame y, left) over [f0, f1], kept
// where a dash of @p dash metres every @p period metres starting at @p phase lies (period 0: a
// solid line).
std::vector<Eigen::Vector3f> line(double offset, double slope, double f0, double f1,
                                  double period = 0.0, double dash = 0.0, double phase = 0.0) {
  std::vector<Eigen::Vector3f> pts;
  for (double f = f0; f <= f1 + 1e-9; f += 0.5) {
    if (period > 0.0 && std::fmod(f - phase + 100.0 * period, period) > dash) continue;
    pts.emplace_back(static_cast<float>(-(offset + slope * f)), 1.5f, static_cast<float>(f));
  }
  return pts;
}

TEST(LaneTracker, FollowsTheLaneWhileTheVehicleTurns) {
  // A lane change to the left at 20 m/s and 10 frames/s: the car yaws left by 0.01 rad per frame
  // for half a second and back for half a second, so in the camera's road frame the lane turns
  // right and back (up to 2.9 deg) and moves right. The left line is dashed (3 m of paint every
  // 12 m), the right one solid. The evidence of the previous frames lies at the old heading: the
  // model must turn with the lane, not lag it (a lagging model is 0.3-0.5 m off 30 m ahead).
  LaneTracker t;
  const RoadFrame f = RoadFrame::fromPlane(road());
  TrackerParams tp;
  double offset = 0.0, slope = 0.0;
  for (int k = 0; k < 20; ++k) {
    slope += k < 3 ? 0.0 : k < 8 ? -0.01 : k < 13 ? 0.01 : 0.0;
    offset += 2.0 * slope;  // 2 m forward at the heading
    const double phase = std::fmod(-2.0 * k, 12.0);
    t.update(f, line(offset + 1.8, slope, 3, 40, 12.0, 3.0, phase), line(offset - 1.8, slope, 3, 40),
             tp);
    ASSERT_TRUE(t.valid(0) && t.valid(1)) << k;
    if (k < 5) continue;  // (the turn rate takes a frame or two to be learnt)
    for (double d : {5.0, 20.0, 30.0}) {
      EXPECT_NEAR(t.lateral(0, d), offset + 1.8 + slope * d, 0.1) << k << " " << d;
      EXPECT_NEAR(t.lateral(1, d), offset - 1.8 + slope * d, 0.1) << k << " " << d;
    }
  }
}

TEST(LaneTracker, InvalidFrameAgesWithoutCrashing) {
  LaneTracker t;
  TrackerParams tp;
  t.update(RoadFrame(), marker(straight, -1.8, 3, 20), marker(straight, 1.8, 3, 20), tp);
  EXPECT_FALSE(t.valid(0));
  EXPECT_FALSE(t.valid(1));
  std::vector<Eigen::Vector3f> out(3);
  t.sample(0, RoadFrame::fromPlane(road()), 0.5, out);
  EXPECT_TRUE(out.empty());
}

}  // namespace
}  // namespace rgbd_lane_detector
