// Scoring rules of scoring.h on hand-made detections: every side outcome (correct, wrong kind,
// off the line, spurious, missed) and every frame outcome (TP, partial, FP, miss), lane-optional
// frames and the per-side statistics.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "rgbd_lane_detector_tools/ground_truth.h"
#include "rgbd_lane_detector_tools/scoring.h"

namespace rgbd_lane_detector {
namespace tools {
namespace {

constexpr double kHeight = 1.5;
constexpr double kHalfLane = 1.8;

TrueBoundary line(BoundaryLabel label, double x, BoundaryKind kind = BoundaryKind::kPaint) {
  TrueBoundary b;
  b.label = label;
  b.kind = kind;
  b.style = kind == BoundaryKind::kPaint ? LineStyle::kSolid : LineStyle::kRoadEdge;
  b.colour = kind == BoundaryKind::kPaint ? LineColour::kWhite : LineColour::kNone;
  for (double z = 3.0; z <= 60.0; z += 0.5) b.points.emplace_back(x, kHeight, z);
  return b;
}

// Straight road under a level camera: plane y = 1.5 (optical frame, y down), ego lines x = -+1.8
// of the given kinds.
FrameTruth straightTruth(BoundaryKind left = BoundaryKind::kPaint,
                         BoundaryKind right = BoundaryKind::kPaint) {
  FrameTruth t;
  t.index = 0;
  t.normal = Eigen::Vector3d(0, -1, 0);
  t.distance = kHeight;
  t.boundaries = {line(BoundaryLabel::kEgoLeft, -kHalfLane, left),
                  line(BoundaryLabel::kEgoRight, kHalfLane, right),
                  line(BoundaryLabel::kNextLeft, -3 * kHalfLane)};
  t.syncEgoLines();
  return t;
}

// Truth without the right ego boundary (an unpainted side).
FrameTruth leftOnlyTruth() {
  FrameTruth t = straightTruth();
  t.boundaries.erase(t.boundaries.begin() + 1);
  t.syncEgoLines();
  return t;
}

std::vector<Eigen::Vector3d> sidePoints(double x, int n, double error = 0.0) {
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < n; ++i) pts.emplace_back(x + error, kHeight, 5.0 + 3.0 * i);
  return pts;
}

Detection planeOnly() {
  Detection d;
  d.plane_valid = true;
  d.normal = Eigen::Vector3d(0, -1, 0);
  d.distance = kHeight;
  return d;
}

Detection perfect() {
  Detection d = planeOnly();
  d.left_reported = d.right_reported = true;
  d.left = sidePoints(-kHalfLane, 6, 0.1);
  d.right = sidePoints(kHalfLane, 6, -0.2);
  return d;
}

Eigen::Vector3d tilted(double deg) {
  return Eigen::AngleAxisd(deg * M_PI / 180.0, Eigen::Vector3d::UnitX()) *
         Eigen::Vector3d(0, -1, 0);
}

TEST(Scoring, PerfectDetectionIsTruePositive) {
  const FrameScore s = scoreFrame(perfect(), straightTruth());
  EXPECT_EQ(s.outcome, Outcome::kTruePositive);
  EXPECT_TRUE(s.reported);
  EXPECT_TRUE(s.lane_required);
  EXPECT_NEAR(s.angle_error_deg, 0.0, 1e-9);
  EXPECT_NEAR(s.offset_error, 0.0, 1e-12);
  EXPECT_EQ(s.left.points, 6);
  EXPECT_EQ(s.left.inliers, 6);
  EXPECT_NEAR(s.left.mean_lateral, 0.1, 1e-9);
  EXPECT_EQ(s.left.outcome, SideOutcome::kCorrect);
  EXPECT_EQ(s.right.outcome, SideOutcome::kCorrect);
}

TEST(Scoring, PlaneAngleLimit) {
  Detection d = perfect();
  d.normal = tilted(2.9);
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kTruePositive);
  d.normal = tilted(3.1);
  const FrameScore s = scoreFrame(d, straightTruth());
  EXPECT_EQ(s.outcome, Outcome::kWrong);  // sides reported with a wrong plane
  EXPECT_NEAR(s.angle_error_deg, 3.1, 1e-9);
  EXPECT_TRUE(s.left.correct());  // the sides themselves are right
}

TEST(Scoring, NormalMustPointTowardTheCamera) {
  Detection d = perfect();
  d.normal = -d.normal;  // same plane, wrong orientation
  d.distance = -d.distance;
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kWrong);
}

TEST(Scoring, PlaneOffsetLimit) {
  Detection d = perfect();
  d.distance = kHeight + 0.14;
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kTruePositive);
  d.distance = kHeight - 0.16;
  const FrameScore s = scoreFrame(d, straightTruth());
  EXPECT_EQ(s.outcome, Outcome::kWrong);
  EXPECT_NEAR(s.offset_error, 0.16, 1e-12);
}

TEST(Scoring, SidesWithoutPlaneAreWrong) {
  Detection d = perfect();
  d.plane_valid = false;
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kWrong);
  d.right_reported = false;  // one correct side, no plane: still wrong
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kWrong);
}

TEST(Scoring, AtLeastFivePointsPerSide) {
  Detection d = perfect();
  d.right = sidePoints(kHalfLane, 4);
  FrameScore s = scoreFrame(d, straightTruth());
  EXPECT_EQ(s.right.outcome, SideOutcome::kOffLine);
  EXPECT_EQ(s.outcome, Outcome::kWrong);
  d.right = sidePoints(kHalfLane, 5);
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kTruePositive);
  // points without depth do not count
  const double nan = std::numeric_limits<double>::quiet_NaN();
  d.right.back() = Eigen::Vector3d(nan, nan, nan);
  s = scoreFrame(d, straightTruth());
  EXPECT_EQ(s.right.points, 4);
  EXPECT_EQ(s.outcome, Outcome::kWrong);
}

TEST(Scoring, EightyPercentWithinThirtyCentimetres) {
  Detection d = perfect();
  d.left = sidePoints(-kHalfLane, 5);
  d.left[0].x() += 0.5;  // 4 of 5 = 80%: still correct
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kTruePositive);
  d.left[1].x() -= 0.31;  // 3 of 5
  const FrameScore s = scoreFrame(d, straightTruth());
  EXPECT_EQ(s.outcome, Outcome::kWrong);
  EXPECT_EQ(s.left.inliers, 3);
  EXPECT_EQ(s.left.outcome, SideOutcome::kOffLine);
  EXPECT_TRUE(s.right.correct());
}

TEST(Scoring, SidesAreNotInterchangeable) {
  Detection d = perfect();
  std::swap(d.left, d.right);
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kWrong);
}

TEST(Scoring, OneCorrectSideIsPartial) {
  Detection d = perfect();
  d.right_reported = false;
  const FrameScore s = scoreFrame(d, straightTruth());
  EXPECT_EQ(s.outcome, Outcome::kPartial);
  EXPECT_EQ(s.right.outcome, SideOutcome::kMissed);
  EXPECT_TRUE(s.left.correct());
  // a correct side with a good plane where the truth has only that side: TP
  EXPECT_EQ(scoreFrame(d, leftOnlyTruth()).outcome, Outcome::kTruePositive);
}

TEST(Scoring, KerbReportedAsPaintIsFalsePositive) {
  const FrameTruth kerb = straightTruth(BoundaryKind::kPaint, BoundaryKind::kRoadEdge);
  Detection d = perfect();  // both sides reported as paint, on the true lines
  FrameScore s = scoreFrame(d, kerb);
  EXPECT_EQ(s.right.outcome, SideOutcome::kWrongKind);
  EXPECT_TRUE(s.right.on_line);
  EXPECT_EQ(s.outcome, Outcome::kWrong);
  d.right_kind = BoundaryKind::kRoadEdge;
  s = scoreFrame(d, kerb);
  EXPECT_EQ(s.outcome, Outcome::kTruePositive);
  // and the other way round: paint reported as a road edge
  d.left_kind = BoundaryKind::kRoadEdge;
  s = scoreFrame(d, kerb);
  EXPECT_EQ(s.left.outcome, SideOutcome::kWrongKind);
  EXPECT_EQ(s.outcome, Outcome::kWrong);
}

TEST(Scoring, SideWhereTheTruthHasNoneIsFalsePositive) {
  const FrameTruth t = leftOnlyTruth();
  const FrameScore s = scoreFrame(perfect(), t);
  EXPECT_EQ(s.right.outcome, SideOutcome::kSpurious);
  EXPECT_FALSE(s.right.truth);
  EXPECT_TRUE(std::isnan(s.right.mean_lateral));
  EXPECT_EQ(s.outcome, Outcome::kWrong);
}

TEST(Scoring, PlaneAloneIsNoLaneReport) {
  FrameTruth none = straightTruth();
  none.boundaries.clear();  // no_markings: the ego lane has no boundary
  none.syncEgoLines();
  EXPECT_FALSE(none.has_lane);
  FrameScore s = scoreFrame(planeOnly(), none);
  EXPECT_EQ(s.outcome, Outcome::kMiss);
  EXPECT_FALSE(s.reported);
  EXPECT_TRUE(s.plane_ok);  // scored on its own
  EXPECT_FALSE(s.lane_required);
  EXPECT_EQ(scoreFrame(perfect(), none).outcome, Outcome::kWrong);
  // on a marked road a plane alone is a miss too
  s = scoreFrame(planeOnly(), straightTruth());
  EXPECT_EQ(s.outcome, Outcome::kMiss);
  EXPECT_TRUE(s.plane_valid);
}

TEST(Scoring, NothingReportedIsAMiss) {
  Detection d;
  const FrameScore s = scoreFrame(d, straightTruth());
  EXPECT_EQ(s.outcome, Outcome::kMiss);
  EXPECT_FALSE(s.reported);
  EXPECT_TRUE(std::isnan(s.angle_error_deg));
  // points of a side the detector does not report are not a report
  d.left = sidePoints(-kHalfLane, 6);
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kMiss);
}

TEST(Scoring, LateralDistanceIsMeasuredInTheRoadPlane) {
  const FrameTruth t = straightTruth();
  // a point 1 m above the road over the line: lateral distance 0 (height is not lateral)
  EXPECT_NEAR(lateralDistance(Eigen::Vector3d(-kHalfLane, kHeight - 1.0, 10.0), t.left, t.normal,
                              t.distance),
              0.0, 1e-12);
  // beyond the sampled range the end segments extend
  EXPECT_NEAR(lateralDistance(Eigen::Vector3d(-kHalfLane + 0.2, kHeight, 90.0), t.left, t.normal,
                              t.distance),
              0.2, 1e-9);
  EXPECT_NEAR(lateralDistance(Eigen::Vector3d(-kHalfLane - 0.25, kHeight, 1.0), t.left, t.normal,
                              t.distance),
              0.25, 1e-9);
  EXPECT_TRUE(std::isinf(lateralDistance(Eigen::Vector3d(0, 0, 1), {}, t.normal, t.distance)));
}

TEST(Scoring, RotationInvariant) {
  // the same scene seen by a pitched and rolled camera scores the same
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitZ()))
                                .toRotationMatrix();
  FrameTruth t = straightTruth();
  Detection d = perfect();
  t.normal = R * t.normal;
  d.normal = R * d.normal;
  for (auto& b : t.boundaries)
    for (auto& p : b.points) p = R * p;
  t.syncEgoLines();
  for (auto* side : {&d.left, &d.right})
    for (auto& p : *side) p = R * p;
  EXPECT_EQ(scoreFrame(d, t).outcome, Outcome::kTruePositive);
  d.left[0] += 0.5 * (R * Eigen::Vector3d::UnitX());  // lateral outlier 1 of 6
  d.left[1] += 0.5 * (R * Eigen::Vector3d::UnitX());  // 2 of 6 -> 67% < 80%
  EXPECT_EQ(scoreFrame(d, t).outcome, Outcome::kWrong);
}

TEST(Scoring, DetectionFromResultUsesReportedSides) {
  Result r;
  r.status = Status::kOk;
  r.left.found = true;
  r.left.kind = BoundaryKind::kRoadEdge;
  r.left.confidence = 0.75f;
  r.left.points = {Eigen::Vector3f(-1.8f, 1.5f, 6.f)};
  r.right.found = false;
  r.right.points = {Eigen::Vector3f(1.8f, 1.5f, 6.f)};
  Detection d = detectionFromResult(r);
  EXPECT_TRUE(d.left_reported);
  EXPECT_EQ(d.left_kind, BoundaryKind::kRoadEdge);
  EXPECT_NEAR(d.left_confidence, 0.75, 1e-7);
  EXPECT_FALSE(d.right_reported);
  EXPECT_EQ(d.left.size(), 1u);
  EXPECT_TRUE(d.right.empty());
  r.status = Status::kSizeMismatch;
  d = detectionFromResult(r);
  EXPECT_FALSE(d.left_reported);
}

TEST(Scoring, LateralErrorAtDistancesInBaseLink) {
  FrameTruth t = straightTruth();
  t.has_vehicle_frame = true;  // level camera 1.5 m above base_link
  t.base_to_camera.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  t.base_to_camera.translation() = Eigen::Vector3d(0, 0, kHeight);
  Detection d = perfect();  // left 0.1 m right of its line, right 0.2 m left, from 5 to 20 m
  d.left[2].x() += 0.3;     // at 11 m: 0.4 m off
  const FrameScore s = scoreFrame(d, t);
  EXPECT_NEAR(s.left.lateral_error[0], 0.1, 1e-9);   // 5 m
  EXPECT_NEAR(s.left.lateral_error[1], 0.1 + 0.3 * 2.0 / 3.0, 1e-9);  // 10 m: 2/3 toward 11 m
  EXPECT_NEAR(s.left.lateral_error[2], 0.1, 1e-9);   // 20 m
  EXPECT_TRUE(std::isnan(s.left.lateral_error[3]));  // the trace ends at 20 m: not 40 m
  EXPECT_NEAR(s.right.lateral_error[2], 0.2, 1e-9);
  ScoreSummary sum;
  sum.add(s, 1.0);
  EXPECT_EQ(sum.lateral_errors[0].size(), 2u);
  EXPECT_TRUE(sum.lateral_errors[3].empty());
  EXPECT_NEAR(sum.lateralPercentile(0, 50), 0.1, 1e-9);
  EXPECT_NEAR(sum.lateralPercentile(0, 95), 0.2, 1e-9);
  EXPECT_TRUE(std::isnan(sum.lateralPercentile(3, 50)));
  // without a vehicle frame (format 1 truth) nothing is measured
  t.has_vehicle_frame = false;
  EXPECT_TRUE(std::isnan(scoreFrame(d, t).left.lateral_error[0]));
}

TEST(Scoring, LaneOptionalFramesDoNotCountMisses) {
  FrameTruth optional = straightTruth();
  optional.lane_optional = true;  // an intersection ahead
  Detection wrong = perfect();
  wrong.left = sidePoints(-kHalfLane + 1.0, 6);  // a zebra stripe traced as the left line
  ScoreSummary sum;
  sum.add(scoreFrame(perfect(), straightTruth()), 1.0);  // TP
  sum.add(scoreFrame(Detection(), optional), 1.0);       // acceptable miss
  sum.add(scoreFrame(perfect(), optional), 1.0);         // correct anyway: fine
  sum.add(scoreFrame(wrong, optional), 1.0);             // wrong counts everywhere
  EXPECT_EQ(sum.frames, 4);
  EXPECT_EQ(sum.required, 1);
  EXPECT_DOUBLE_EQ(sum.tpPercent(), 100.0);
  EXPECT_DOUBLE_EQ(sum.missPercent(), 0.0);
  EXPECT_DOUBLE_EQ(sum.fpPercent(), 25.0);
  // true sides count for recall only where a lane is required
  EXPECT_EQ(sum.sides_true, 2);
  EXPECT_EQ(sum.sides_reported, 6);
  EXPECT_EQ(sum.sides_correct, 5);
}

TEST(Scoring, SummaryAddsUp) {
  ScoreSummary sum;
  const FrameTruth t = straightTruth();
  const FrameTruth kerb = straightTruth(BoundaryKind::kPaint, BoundaryKind::kRoadEdge);
  Detection wrong_plane = perfect();
  wrong_plane.distance += 0.5;
  Detection one_side = perfect();
  one_side.right_reported = false;
  FrameTruth none = t;
  none.boundaries.clear();
  none.syncEgoLines();
  sum.add(scoreFrame(perfect(), t), 10.0);      // TP
  sum.add(scoreFrame(wrong_plane, t), 20.0);    // FP
  sum.add(scoreFrame(Detection(), t), 30.0);    // miss
  sum.add(scoreFrame(one_side, t), 40.0);       // partial
  sum.add(scoreFrame(perfect(), kerb), 50.0);   // FP: the kerb reported as paint
  sum.add(scoreFrame(planeOnly(), none), 60.0);  // no lane needed, plane alone: fine
  EXPECT_EQ(sum.frames, 6);
  EXPECT_EQ(sum.required, 5);
  EXPECT_DOUBLE_EQ(sum.tpPercent(), 20.0);
  EXPECT_DOUBLE_EQ(sum.partialPercent(), 20.0);
  EXPECT_DOUBLE_EQ(sum.missPercent(), 20.0);
  EXPECT_DOUBLE_EQ(sum.fpPercent(), 100.0 * 2 / 6);
  EXPECT_EQ(sum.plane_frames, 5);
  EXPECT_EQ(sum.plane_ok, 4);
  EXPECT_DOUBLE_EQ(sum.planeOkPercent(), 80.0);
  EXPECT_NEAR(sum.meanOffsetError(), 0.5 / 5, 1e-12);
  EXPECT_DOUBLE_EQ(sum.meanMs(), 35.0);
  // sides: reported 2 + 2 + 0 + 1 + 2 = 7, correct 2 + 2 + 1 + 1 = 6 (the wrong plane's sides
  // are on their lines), the kerb's paint report is the only kind error
  EXPECT_EQ(sum.sides_reported, 7);
  EXPECT_EQ(sum.sides_correct, 6);
  EXPECT_EQ(sum.confusion[1][0], 1);  // paint on a road edge
  EXPECT_EQ(sum.confusion[0][1], 0);
  EXPECT_EQ(sum.sides_true, 10);
  EXPECT_EQ(sum.sides_true_correct, 6);
  EXPECT_DOUBLE_EQ(sum.sideRecall(), 60.0);
  EXPECT_TRUE(std::isnan(ScoreSummary().tpPercent()));  // no lane frames: no rate
}

}  // namespace
}  // namespace tools
}  // namespace rgbd_lane_detector
