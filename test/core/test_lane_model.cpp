// LaneModelFilter on boundaries drawn from an exact lane (the vehicle frame: x forward, y left;
// the observations are given in it, vehicle_from_camera = identity): convergence of width,
// offset, heading and curvature, robustness to stray points, labels through a lane change, the
// odometry prediction, kinds and colours, nothing beyond a road edge, the published range, the
// reset after lost frames and the confidence calibration.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/lane_model.h"

namespace rgbd_lane_detector {
namespace {

/// A lane in the vehicle frame: centre y(x) = y0 + slope x + kappa x^2 / 2, lines +-width / 2.
struct Lane {
  double y0 = 0.0, slope = 0.0, kappa = 0.0, width = 3.6;
  double line(int side, double x) const {  // side 0 left, 1 right
    return y0 + (side == 0 ? 0.5 : -0.5) * width + slope * x + 0.5 * kappa * x * x;
  }
};

/// Points of a line at lateral offset @p shift from the lane's left (0) or right (1) line, every
/// 0.25 m from @p from to @p to.
std::vector<Eigen::Vector3f> linePoints(const Lane& lane, int side, double from = 2.0,
                                        double to = 45.0, double shift = 0.0) {
  std::vector<Eigen::Vector3f> pts;
  for (double x = from; x <= to; x += 0.25)
    pts.emplace_back(static_cast<float>(x), static_cast<float>(lane.line(side, x) + shift), 0.f);
  return pts;
}

BoundaryObservation observation(const std::vector<Eigen::Vector3f>& pts, bool left, bool ego = true,
                                BoundaryKind kind = BoundaryKind::kPaint, float coverage = 1.f,
                                float yellowness = 0.f) {
  BoundaryObservation o;
  o.left = left;
  o.ego = ego;
  o.kind = kind;
  o.points = &pts;
  o.confidence = 0.9f;
  o.paint_coverage = kind == BoundaryKind::kPaint ? coverage : -1.f;
  o.yellowness = kind == BoundaryKind::kPaint ? yellowness : -1.f;
  return o;
}

/// Feed @p frames frames of both ego lines of @p lane.
void feed(LaneModelFilter& f, const Lane& lane, int frames, LaneModelEstimate& m) {
  for (int i = 0; i < frames; ++i) {
    const std::vector<Eigen::Vector3f> l = linePoints(lane, 0), r = linePoints(lane, 1);
    const BoundaryObservation obs[2] = {observation(l, true), observation(r, false)};
    f.update(Eigen::Isometry3d::Identity(), obs, 2, m);
  }
}

const LaneBoundaryModel& at(const LaneModelEstimate& m, BoundaryPosition p) { return m.at(p); }

TEST(LaneModel, ConvergesToAStraightLane) {
  Lane lane;
  lane.y0 = -0.2;  // the vehicle 0.2 m left of the centre
  lane.slope = 0.01;
  LaneModelFilter f;
  LaneModelEstimate m;
  feed(f, lane, 15, m);
  ASSERT_TRUE(m.valid);
  EXPECT_NEAR(m.width, 3.6, 0.01);
  EXPECT_NEAR(m.offset, 0.2, 0.01);
  EXPECT_NEAR(m.heading_error, -std::atan(0.01), 1e-3);
  EXPECT_NEAR(m.curvature, 0.0, 2e-5);
  const LaneBoundaryModel& left = at(m, BoundaryPosition::kEgoLeft);
  const LaneBoundaryModel& right = at(m, BoundaryPosition::kEgoRight);
  ASSERT_TRUE(left.valid && right.valid);
  for (double x : {5.0, 20.0, 40.0}) {
    EXPECT_NEAR(left.lateral(x), lane.line(0, x), 0.02) << x;
    EXPECT_NEAR(right.lateral(x), lane.line(1, x), 0.02) << x;
  }
  EXPECT_LE(left.x_min, 2.5);
  EXPECT_GE(left.x_max, 40.0) << "published over the seen range";
  EXPECT_EQ(left.kind, LineKind::kSolid);
  EXPECT_EQ(left.colour, LineColour::kWhite);
  EXPECT_EQ(left.age, 0);
  EXPECT_GT(left.confidence, 0.95f);
  EXPECT_FALSE(at(m, BoundaryPosition::kNextLeft).valid);
  EXPECT_EQ(m.lane_changes, 0);
}

TEST(LaneModel, CurvatureOfACurve) {
  Lane lane;
  lane.kappa = -1.0 / 300.0;  // turning right, R = 300 m (the curve scenario)
  lane.slope = 0.012;
  lane.y0 = 0.15;
  LaneModelFilter f;
  LaneModelEstimate m;
  feed(f, lane, 20, m);
  ASSERT_TRUE(m.valid);
  EXPECT_NEAR(m.curvature, lane.kappa, 2e-5);
  EXPECT_NEAR(m.heading_error, -std::atan(lane.slope), 1e-3);
  EXPECT_NEAR(m.curvature_rate, 0.0, 1e-6);
  EXPECT_NEAR(at(m, BoundaryPosition::kEgoRight).lateral(40.0), lane.line(1, 40.0), 0.03);
}

TEST(LaneModel, StrayPointsNearTheCarAreIgnored) {
  Lane lane;
  LaneModelFilter f;
  LaneModelEstimate m;
  for (int i = 0; i < 10; ++i) {
    // the right trace starts on a patch 0.5 m inside the lane before it reaches its line
    std::vector<Eigen::Vector3f> r = linePoints(lane, 1, 2.0, 2.6, 0.5);
    const std::vector<Eigen::Vector3f> line = linePoints(lane, 1, 3.5, 16.0);
    r.insert(r.end(), line.begin(), line.end());
    const std::vector<Eigen::Vector3f> l = linePoints(lane, 0);
    const BoundaryObservation obs[2] = {observation(l, true), observation(r, false)};
    f.update(Eigen::Isometry3d::Identity(), obs, 2, m);
    ASSERT_TRUE(m.valid);
    EXPECT_NEAR(m.width, 3.6, 0.03) << "frame " << i;
    EXPECT_NEAR(at(m, BoundaryPosition::kEgoRight).lateral(2.3), lane.line(1, 2.3), 0.03);
  }
}

TEST(LaneModel, LaneChangeRelabelsTheLines) {
  // Three lanes; the vehicle moves one lane to the left at 0.15 m per frame. The detector reports
  // the nearest line on each side as its ego side, and the lines beyond as next lanes.
  LaneModelFilter f;
  LaneModelEstimate m;
  const double w = 3.6;
  int crossed_at = -1;
  for (int i = 0; i < 60; ++i) {
    const double shift = std::min(0.15 * std::max(0, i - 10), w);  // the vehicle's lateral motion
    Lane lane;  // the original ego lane, as seen from the vehicle
    lane.y0 = -shift;
    std::vector<std::vector<Eigen::Vector3f>> lines;
    std::vector<double> offsets;  // of the lines at x = 0 (left line of each lane, then right)
    for (double c0 : {lane.y0 + 1.5 * w, lane.y0 + 0.5 * w, lane.y0 - 0.5 * w, lane.y0 - 1.5 * w})
      offsets.push_back(c0);
    std::vector<BoundaryObservation> obs;
    lines.reserve(4);
    for (double c0 : offsets) {
      std::vector<Eigen::Vector3f> pts;
      for (double x = 2.0; x <= 45.0; x += 0.25) pts.emplace_back(x, static_cast<float>(c0), 0.f);
      lines.push_back(pts);
    }
    // nearest left / right of the vehicle (y = 0) are the ego sides
    int ego_left = -1, ego_right = -1;
    for (int k = 0; k < 4; ++k) {
      if (offsets[k] > 0 && (ego_left < 0 || offsets[k] < offsets[ego_left])) ego_left = k;
      if (offsets[k] <= 0 && (ego_right < 0 || offsets[k] > offsets[ego_right])) ego_right = k;
    }
    for (int k = 0; k < 4; ++k) {
      const bool left = offsets[k] > 0;
      const bool ego = k == ego_left || k == ego_right;
      if (!ego && std::fabs(offsets[k]) > 1.5 * w + 0.5 * w) continue;
      obs.push_back(observation(lines[k], left, ego, BoundaryKind::kPaint, 0.3f));
    }
    f.update(Eigen::Isometry3d::Identity(), obs.data(), static_cast<int>(obs.size()), m);
    ASSERT_TRUE(m.valid) << "frame " << i;
    if (crossed_at < 0 && m.lane_changes == 1) crossed_at = i;
    // every published boundary lies on a true line, the one of its label
    for (const LaneBoundaryModel& b : m.boundaries) {
      if (!b.valid) continue;
      double nearest = 1e9;
      for (double c0 : offsets) nearest = std::min(nearest, std::fabs(b.lateral(10.0) - c0));
      EXPECT_LT(nearest, 0.3) << "frame " << i << " " << boundaryPositionName(b.position);
    }
    const LaneBoundaryModel& el = at(m, BoundaryPosition::kEgoLeft);
    const LaneBoundaryModel& er = at(m, BoundaryPosition::kEgoRight);
    if (el.valid) {
      EXPECT_NEAR(el.lateral(0.0), offsets[ego_left], 0.3) << "frame " << i;
    }
    if (er.valid) {
      EXPECT_NEAR(er.lateral(0.0), offsets[ego_right], 0.3) << "frame " << i;
    }
  }
  EXPECT_EQ(m.lane_changes, 1) << "one change to the left";
  // the vehicle's centre crosses the line at shift 1.8 m: frame 10 + 12
  EXPECT_NEAR(crossed_at, 22, 2);
  EXPECT_NEAR(m.offset, 0.0, 0.05) << "centred in the new lane";
}

TEST(LaneModel, OdometryMovesTheModel) {
  Lane lane;
  lane.slope = 0.02;
  lane.y0 = 0.1;
  LaneModelFilter f;
  LaneModelEstimate m;
  feed(f, lane, 10, m);
  const double offset_before = m.offset;
  // 2 m forward, 0.1 m to the left and turned 0.01 rad to the left
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  motion.translation() = Eigen::Vector3d(2.0, 0.1, 0.0);
  motion.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  f.predict(motion);
  f.update(Eigen::Isometry3d::Identity(), nullptr, 0, m);  // no boundary seen this frame
  ASSERT_TRUE(m.valid);
  // the centre, 0.1 + 0.02 * 2 ahead, is now 0.1 m closer on the left
  EXPECT_NEAR(-m.offset, -offset_before + 0.02 * 2.0 - 0.1, 0.01);
  EXPECT_NEAR(std::tan(-m.heading_error), 0.02 - 0.01, 2e-3);
  EXPECT_EQ(at(m, BoundaryPosition::kEgoLeft).age, 1);
}

TEST(LaneModel, KindsAndColours) {
  Lane lane;
  LaneModelFilter f;
  LaneModelEstimate m;
  for (int i = 0; i < 8; ++i) {
    const std::vector<Eigen::Vector3f> l = linePoints(lane, 0), r = linePoints(lane, 1);
    const BoundaryObservation obs[2] = {
        observation(l, true, true, BoundaryKind::kPaint, 1.0f, 0.6f),  // solid yellow
        observation(r, false, true, BoundaryKind::kPaint, 0.3f, 0.0f)};  // dashed white
    f.update(Eigen::Isometry3d::Identity(), obs, 2, m);
  }
  EXPECT_EQ(at(m, BoundaryPosition::kEgoLeft).kind, LineKind::kSolid);
  EXPECT_EQ(at(m, BoundaryPosition::kEgoLeft).colour, LineColour::kYellow);
  EXPECT_EQ(at(m, BoundaryPosition::kEgoRight).kind, LineKind::kDashed);
  EXPECT_EQ(at(m, BoundaryPosition::kEgoRight).colour, LineColour::kWhite);
}

TEST(LaneModel, NothingBeyondARoadEdge) {
  Lane lane;
  LaneModelFilter f;
  LaneModelEstimate m;
  for (int i = 0; i < 8; ++i) {
    const std::vector<Eigen::Vector3f> l = linePoints(lane, 0);
    const std::vector<Eigen::Vector3f> kerb = linePoints(lane, 1);
    const std::vector<Eigen::Vector3f> beyond = linePoints(lane, 1, 2.0, 30.0, -3.0);  // a wall
    const std::vector<Eigen::Vector3f> next = linePoints(lane, 0, 2.0, 30.0, 3.5);
    const BoundaryObservation obs[4] = {
        observation(l, true), observation(kerb, false, true, BoundaryKind::kRoadEdge),
        observation(beyond, false, false, BoundaryKind::kRoadEdge),
        observation(next, true, false, BoundaryKind::kPaint, 0.3f)};
    f.update(Eigen::Isometry3d::Identity(), obs, 4, m);
  }
  EXPECT_EQ(at(m, BoundaryPosition::kEgoRight).kind, LineKind::kRoadEdge);
  EXPECT_EQ(at(m, BoundaryPosition::kEgoRight).colour, LineColour::kUnknown);
  EXPECT_FALSE(at(m, BoundaryPosition::kRoadEdgeRight).valid) << "the road ends at the kerb";
  const LaneBoundaryModel& next = at(m, BoundaryPosition::kNextLeft);
  ASSERT_TRUE(next.valid) << "the next lane's line on the other side";
  EXPECT_NEAR(next.lateral(10.0), lane.line(0, 10.0) + 3.5, 0.05);
  EXPECT_EQ(next.kind, LineKind::kDashed);
}

TEST(LaneModel, UnseenBoundariesAgeShrinkAndGo) {
  Lane lane;
  LaneModelFilter f;
  LaneModelEstimate m;
  feed(f, lane, 10, m);
  const double seen = at(m, BoundaryPosition::kEgoLeft).x_max;
  const float confidence = at(m, BoundaryPosition::kEgoLeft).confidence;
  f.update(Eigen::Isometry3d::Identity(), nullptr, 0, m);
  f.update(Eigen::Isometry3d::Identity(), nullptr, 0, m);
  ASSERT_TRUE(m.valid);
  const LaneBoundaryModel& coasting = at(m, BoundaryPosition::kEgoLeft);
  EXPECT_EQ(coasting.age, 2);
  EXPECT_LT(coasting.x_max, seen) << "the model is sure of less of it";
  EXPECT_LT(coasting.confidence, confidence);
  for (int i = 0; i < 20 && m.valid; ++i) f.update(Eigen::Isometry3d::Identity(), nullptr, 0, m);
  EXPECT_FALSE(m.valid) << "reset after lost frames";
  EXPECT_FALSE(at(m, BoundaryPosition::kEgoLeft).valid);
}

TEST(LaneModel, ConfidenceCalibrationIsMonotonicInTheUnitInterval) {
  float previous = calibratedConfidence(0.f);
  EXPECT_GE(previous, 0.f);
  for (int i = 1; i <= 100; ++i) {
    const float c = calibratedConfidence(0.01f * i);
    EXPECT_GE(c, previous) << i;
    EXPECT_LE(c, 1.f);
    previous = c;
  }
  EXPECT_LT(calibratedConfidence(0.1f), calibratedConfidence(0.99f));
}

}  // namespace
}  // namespace rgbd_lane_detector
