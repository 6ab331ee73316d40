// METHOD.md section 6 scoring on hand-made detections: every TP / FP / miss branch.
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

// Straight road under a level camera: plane y = 1.5 (optical frame, y down), lines x = -+1.8.
FrameTruth straightTruth() {
  FrameTruth t;
  t.index = 0;
  t.normal = Eigen::Vector3d(0, -1, 0);
  t.distance = kHeight;
  t.has_lane = true;
  for (double z = 3.0; z <= 60.0; z += 0.5) {
    t.left.emplace_back(-kHalfLane, kHeight, z);
    t.right.emplace_back(kHalfLane, kHeight, z);
  }
  return t;
}

std::vector<Eigen::Vector3d> sidePoints(double x, int n, double error = 0.0) {
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < n; ++i) pts.emplace_back(x + error, kHeight, 5.0 + 3.0 * i);
  return pts;
}

Detection perfect() {
  Detection d;
  d.plane_valid = true;
  d.normal = Eigen::Vector3d(0, -1, 0);
  d.distance = kHeight;
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
  EXPECT_NEAR(s.angle_error_deg, 0.0, 1e-9);
  EXPECT_NEAR(s.offset_error, 0.0, 1e-12);
  EXPECT_EQ(s.left.points, 6);
  EXPECT_EQ(s.left.inliers, 6);
  EXPECT_NEAR(s.left.mean_lateral, 0.1, 1e-9);
}

TEST(Scoring, PlaneAngleLimit) {
  Detection d = perfect();
  d.normal = tilted(2.9);
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kTruePositive);
  d.normal = tilted(3.1);
  const FrameScore s = scoreFrame(d, straightTruth());
  EXPECT_EQ(s.outcome, Outcome::kFalsePositive);
  EXPECT_NEAR(s.angle_error_deg, 3.1, 1e-9);
}

TEST(Scoring, NormalMustPointTowardTheCamera) {
  Detection d = perfect();
  d.normal = -d.normal;  // same plane, wrong orientation
  d.distance = -d.distance;
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kFalsePositive);
}

TEST(Scoring, PlaneOffsetLimit) {
  Detection d = perfect();
  d.distance = kHeight + 0.14;
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kTruePositive);
  d.distance = kHeight - 0.16;
  const FrameScore s = scoreFrame(d, straightTruth());
  EXPECT_EQ(s.outcome, Outcome::kFalsePositive);
  EXPECT_NEAR(s.offset_error, 0.16, 1e-12);
}

TEST(Scoring, AtLeastFivePointsPerSide) {
  Detection d = perfect();
  d.right = sidePoints(kHalfLane, 4);
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kFalsePositive);
  d.right = sidePoints(kHalfLane, 5);
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kTruePositive);
  // points without depth do not count
  const double nan = std::numeric_limits<double>::quiet_NaN();
  d.right.back() = Eigen::Vector3d(nan, nan, nan);
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kFalsePositive);
}

TEST(Scoring, EightyPercentWithinThirtyCentimetres) {
  Detection d = perfect();
  d.left = sidePoints(-kHalfLane, 5);
  d.left[0].x() += 0.5;  // 4 of 5 = 80%: still TP
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kTruePositive);
  d.left[1].x() -= 0.31;  // 3 of 5
  const FrameScore s = scoreFrame(d, straightTruth());
  EXPECT_EQ(s.outcome, Outcome::kFalsePositive);
  EXPECT_EQ(s.left.inliers, 3);
  EXPECT_FALSE(s.left.ok);
  EXPECT_TRUE(s.right.ok);
}

TEST(Scoring, SidesAreNotInterchangeable) {
  Detection d = perfect();
  std::swap(d.left, d.right);
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kFalsePositive);
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
  for (auto* line : {&t.left, &t.right, &d.left, &d.right})
    for (auto& p : *line) p = R * p;
  EXPECT_EQ(scoreFrame(d, t).outcome, Outcome::kTruePositive);
  d.left[0] += 0.5 * (R * Eigen::Vector3d::UnitX());  // lateral outlier 1 of 6
  d.left[1] += 0.5 * (R * Eigen::Vector3d::UnitX());  // 2 of 6 -> 67% < 80%
  EXPECT_EQ(scoreFrame(d, t).outcome, Outcome::kFalsePositive);
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

TEST(Scoring, MarkersWithoutPlaneAreFalsePositive) {
  Detection d = perfect();
  d.plane_valid = false;
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kFalsePositive);
  d.right_reported = false;
  d.right.clear();
  EXPECT_EQ(scoreFrame(d, straightTruth()).outcome, Outcome::kFalsePositive);
}

TEST(Scoring, AnyReportWithoutMarkingsIsFalsePositive) {
  FrameTruth t = straightTruth();
  t.has_lane = false;
  t.left.clear();
  t.right.clear();
  EXPECT_EQ(scoreFrame(perfect(), t).outcome, Outcome::kFalsePositive);
  Detection plane_only;
  plane_only.plane_valid = true;
  plane_only.normal = Eigen::Vector3d(0, -1, 0);
  plane_only.distance = kHeight;
  EXPECT_EQ(scoreFrame(plane_only, t).outcome, Outcome::kFalsePositive);
  EXPECT_EQ(scoreFrame(Detection(), t).outcome, Outcome::kMiss);
}

TEST(Scoring, DetectionFromResultUsesReportedSides) {
  Result r;
  r.status = Status::kOk;
  r.left.found = true;
  r.left.points = {Eigen::Vector3f(-1.8f, 1.5f, 6.f)};
  r.right.found = false;
  r.right.points = {Eigen::Vector3f(1.8f, 1.5f, 6.f)};
  Detection d = detectionFromResult(r);
  EXPECT_TRUE(d.left_reported);
  EXPECT_FALSE(d.right_reported);
  EXPECT_EQ(d.left.size(), 1u);
  EXPECT_TRUE(d.right.empty());
  r.status = Status::kSizeMismatch;
  d = detectionFromResult(r);
  EXPECT_FALSE(d.left_reported);
}

TEST(Scoring, SummaryAddsUp) {
  ScoreSummary sum;
  const FrameTruth t = straightTruth();
  Detection fp = perfect();
  fp.distance += 0.5;
  sum.add(scoreFrame(perfect(), t), 10.0);
  sum.add(scoreFrame(fp, t), 20.0);
  sum.add(scoreFrame(Detection(), t), 30.0);
  sum.add(scoreFrame(perfect(), t), 40.0);
  EXPECT_EQ(sum.frames, 4);
  EXPECT_DOUBLE_EQ(sum.tpPercent(), 50.0);
  EXPECT_DOUBLE_EQ(sum.fpPercent(), 25.0);
  EXPECT_DOUBLE_EQ(sum.missPercent(), 25.0);
  EXPECT_EQ(sum.plane_frames, 3);
  EXPECT_NEAR(sum.meanOffsetError(), 0.5 / 3, 1e-12);
  EXPECT_DOUBLE_EQ(sum.meanMs(), 25.0);
}

TEST(GroundTruth, JsonRoundTrip) {
  SequenceTruth seq;
  seq.frames.push_back(straightTruth());
  FrameTruth empty = straightTruth();
  empty.index = 1;
  empty.has_lane = false;
  empty.left.clear();
  empty.right.clear();
  seq.frames.push_back(empty);
  const std::string path = ::testing::TempDir() + "/rgbd_tools_gt.json";
  std::string error;
  ASSERT_TRUE(writeGroundTruth(path, seq, error)) << error;
  SequenceTruth back;
  ASSERT_TRUE(readGroundTruth(path, back, error)) << error;
  ASSERT_EQ(back.frames.size(), 2u);
  const FrameTruth* f0 = back.find(0);
  ASSERT_NE(f0, nullptr);
  EXPECT_TRUE(f0->has_lane);
  ASSERT_EQ(f0->left.size(), seq.frames[0].left.size());
  EXPECT_NEAR((f0->left.back() - seq.frames[0].left.back()).norm(), 0.0, 1e-5);
  EXPECT_NEAR(f0->distance, kHeight, 1e-12);
  EXPECT_FALSE(back.find(1)->has_lane);
  EXPECT_TRUE(back.find(1)->right.empty());
  EXPECT_EQ(back.find(7), nullptr);
  std::remove(path.c_str());
  EXPECT_FALSE(readGroundTruth(path, back, error));
  EXPECT_NE(error.find(path), std::string::npos);
}

}  // namespace
}  // namespace tools
}  // namespace rgbd_lane_detector
