// Lane-model scores of lane_model_scoring.h on hand-made models and truths in base_link: matches
// (ONCE-3DLanes style, with the label), lateral errors within the reported range, geometry,
// kind and colour, the worst published distance, F1 and the reliability table.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "rgbd_lane_detector_tools/lane_model_scoring.h"

namespace rgbd_lane_detector {
namespace tools {
namespace {

constexpr double kCurvature = 1.0 / 300.0;  // 1/m, turning left

// A true boundary y(x) = y0 + kappa x^2 / 2 in base_link, every 0.5 m from 3 to 60 m.
TrueBoundary trueLine(BoundaryLabel label, double y0, LineStyle style = LineStyle::kDashed,
                      LineColour colour = LineColour::kWhite, double kappa = kCurvature) {
  TrueBoundary b;
  b.label = label;
  b.style = style;
  b.kind = style == LineStyle::kRoadEdge ? BoundaryKind::kRoadEdge : BoundaryKind::kPaint;
  b.colour = b.kind == BoundaryKind::kRoadEdge ? LineColour::kNone : colour;
  for (double x = 3.0; x <= 60.0; x += 0.5) {
    b.points_base.emplace_back(x, y0 + 0.5 * kappa * x * x, 0.0);
    b.points.push_back(b.points_base.back());  // (the optical frame is not used here)
  }
  return b;
}

// A lane 3.6 m wide, the vehicle 0.2 m left of its centre, curving left; a dashed white left
// line, a solid yellow right line and a road edge beyond it.
FrameTruth truth() {
  FrameTruth t;
  t.has_vehicle_frame = true;
  t.lane.valid = true;
  t.lane.width = 3.6;
  t.lane.offset = 0.2;
  t.lane.heading = 0.0;
  t.lane.curvature = kCurvature;
  t.boundaries = {trueLine(BoundaryLabel::kEgoLeft, 1.6),
                  trueLine(BoundaryLabel::kEgoRight, -2.0, LineStyle::kSolid, LineColour::kYellow),
                  trueLine(BoundaryLabel::kRoadEdgeRight, -3.0, LineStyle::kRoadEdge)};
  t.syncEgoLines();
  return t;
}

LaneBoundaryModel boundary(BoundaryPosition p, double c0, LineKind kind, ::rgbd_lane_detector::LineColour colour,
                           double x_min = 4.0, double x_max = 45.0) {
  LaneBoundaryModel b;
  b.valid = true;
  b.position = p;
  b.kind = kind;
  b.colour = colour;
  b.c = {c0, 0.0, 0.5 * kCurvature, 0.0};
  b.x_min = x_min;
  b.x_max = x_max;
  b.confidence = 0.9f;
  return b;
}

// The model the truth describes.
LaneModelEstimate exact() {
  using C = ::rgbd_lane_detector::LineColour;
  LaneModelEstimate m;
  m.valid = true;
  m.width = 3.6;
  m.offset = 0.2;
  m.heading_error = 0.0;
  m.curvature = kCurvature;
  m.boundaries[0] = boundary(BoundaryPosition::kEgoLeft, 1.6, LineKind::kDashed, C::kWhite);
  m.boundaries[1] = boundary(BoundaryPosition::kEgoRight, -2.0, LineKind::kSolid, C::kYellow);
  m.boundaries[5] = boundary(BoundaryPosition::kRoadEdgeRight, -3.0, LineKind::kRoadEdge, C::kUnknown);
  return m;
}

TEST(LaneModelScoring, ExactModelMatchesEverywhere) {
  const LaneModelScore s = scoreLaneModel(exact(), truth());
  EXPECT_TRUE(s.model_valid);
  EXPECT_TRUE(s.truth_valid);
  EXPECT_NEAR(s.width_error, 0.0, 1e-12);
  EXPECT_NEAR(s.curvature_error, 0.0, 1e-12);
  for (int p : {0, 1, 5}) {
    const PositionScore& ps = s.positions[p];
    EXPECT_TRUE(ps.reported && ps.truth && ps.matched) << p;
    EXPECT_NEAR(ps.overlap, 41.0, 1e-9) << "the reported range 4-45 m inside the truth's";
    EXPECT_LT(ps.mean_distance, 0.01) << "linear interpolation of a 0.5 m polyline";
    EXPECT_EQ(ps.kind, ps.true_kind);
    EXPECT_EQ(ps.colour, ps.true_colour);
    for (int k = 0; k < kNumLateralDistances; ++k) EXPECT_LT(ps.lateral_error[k], 0.01) << k;
  }
  EXPECT_EQ(s.positions[1].true_colour, ::rgbd_lane_detector::LineColour::kYellow);
  EXPECT_EQ(s.positions[5].true_kind, LineKind::kRoadEdge);
  EXPECT_FALSE(s.positions[2].reported || s.positions[2].truth);

  LaneModelSummary sum;
  sum.add(s, 0);
  EXPECT_DOUBLE_EQ(sum.f1(allPositions()), 1.0);
  EXPECT_DOUBLE_EQ(sum.kindAccuracy(allPositions()), 100.0);
  EXPECT_DOUBLE_EQ(sum.colourAccuracy(allPositions()), 100.0);
  EXPECT_EQ(sum.colourSamples(allPositions()), 2) << "the road edge has no colour";
  EXPECT_EQ(sum.frames_beyond_limit, 0);
}

TEST(LaneModelScoring, OffsetBoundaryIsNoMatch) {
  LaneModelEstimate m = exact();
  m.boundaries[0].c[0] += 0.35;  // beyond the 0.30 m of a match
  m.width += 0.35;
  const LaneModelScore s = scoreLaneModel(m, truth());
  const PositionScore& ps = s.positions[0];
  EXPECT_FALSE(ps.matched);
  EXPECT_NEAR(ps.mean_distance, 0.35, 0.01);
  EXPECT_NEAR(ps.worst_distance, 0.35, 0.01);
  EXPECT_NEAR(ps.lateral_error[1], 0.35, 0.01);
  EXPECT_NEAR(s.width_error, 0.35, 1e-9);
  LaneModelSummary sum;
  sum.add(s, 7);
  EXPECT_EQ(sum.fp[0], 1);
  EXPECT_EQ(sum.fn[0], 1) << "the true left line is unmatched";
  EXPECT_EQ(sum.kindSamples(egoPositions()), 1) << "kinds are counted where matched";
  EXPECT_NEAR(sum.precision(allPositions()), 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(sum.worst, 0.35, 0.01);
  EXPECT_EQ(sum.worst_frame, 7);
  EXPECT_EQ(sum.frames_beyond_limit, 0) << "0.35 m is within the 0.5 m limit";
  m.boundaries[0].c[0] += 0.3;
  sum.add(scoreLaneModel(m, truth()), 8);
  EXPECT_EQ(sum.frames_beyond_limit, 1);
  EXPECT_EQ(sum.worst_frame, 8);
}

TEST(LaneModelScoring, LabelWithoutTruthIsInfinitelyFar) {
  LaneModelEstimate m = exact();
  m.boundaries[2] = boundary(BoundaryPosition::kNextLeft, 5.2, LineKind::kDashed,
                             ::rgbd_lane_detector::LineColour::kWhite);
  const LaneModelScore s = scoreLaneModel(m, truth());
  EXPECT_FALSE(s.positions[2].matched);
  EXPECT_TRUE(std::isinf(s.positions[2].worst_distance));
  LaneModelSummary sum;
  sum.add(s, 3);
  EXPECT_EQ(sum.worst_position, 2);
  EXPECT_EQ(sum.frames_beyond_limit, 1);
}

TEST(LaneModelScoring, ShortOverlapIsNoMatchAndErrorsStayInTheRange) {
  LaneModelEstimate m = exact();
  m.boundaries[0].x_min = 2.0;  // 3-6 m overlaps the truth: less than 5 m
  m.boundaries[0].x_max = 6.0;
  const LaneModelScore s = scoreLaneModel(m, truth());
  const PositionScore& ps = s.positions[0];
  EXPECT_NEAR(ps.overlap, 3.0, 1e-9);
  EXPECT_LT(ps.mean_distance, 0.01);
  EXPECT_FALSE(ps.matched);
  EXPECT_TRUE(std::isfinite(ps.lateral_error[0])) << "5 m is in the range";
  EXPECT_TRUE(std::isnan(ps.lateral_error[1])) << "10 m is beyond x_max";
}

TEST(LaneModelScoring, TruthGapsAreNotBridgedAndKindDecidesCorrect) {
  FrameTruth t = truth();
  // the left line is interrupted from 10 to 30 m (an intersection)
  std::vector<Eigen::Vector3d>& pts = t.boundaries[0].points_base;
  pts.erase(std::remove_if(pts.begin(), pts.end(),
                           [](const Eigen::Vector3d& p) { return p.x() > 10.0 && p.x() < 30.0; }),
            pts.end());
  LaneModelEstimate m = exact();
  m.boundaries[0].kind = LineKind::kSolid;  // the truth is dashed
  m.boundaries[0].x_min = 12.0;             // published only within the gap
  m.boundaries[0].x_max = 28.0;
  LaneModelScore s = scoreLaneModel(m, t);
  EXPECT_FALSE(s.positions[0].matched) << "no truth where it is published";
  EXPECT_NEAR(s.positions[0].overlap, 0.0, 1e-9);
  m.boundaries[0].x_min = 4.0;  // 4-10 m and 30-45 m on the line
  m.boundaries[0].x_max = 45.0;
  s = scoreLaneModel(m, t);
  EXPECT_TRUE(s.positions[0].matched);
  EXPECT_NEAR(s.positions[0].overlap, 21.0, 1.5);
  EXPECT_FALSE(s.positions[0].correct) << "solid published on a dashed line";
  EXPECT_TRUE(s.positions[1].correct);
  LaneModelSummary sum;
  sum.add(s, 0);
  EXPECT_DOUBLE_EQ(sum.f1(egoPositions()), 1.0) << "F1 counts matches, whatever the kind";
  int correct = 0;
  for (const auto& c : sum.calibration) correct += c.second;
  EXPECT_EQ(correct, 2) << "the calibration samples count correct boundaries";
}

TEST(LaneModelScoring, NothingWithoutVehicleFrame) {
  FrameTruth t = truth();
  t.has_vehicle_frame = false;
  const LaneModelScore s = scoreLaneModel(exact(), t);
  EXPECT_FALSE(s.truth_valid);
  EXPECT_TRUE(std::isnan(s.width_error));
  for (const auto& ps : s.positions) EXPECT_FALSE(ps.reported || ps.truth);
}

TEST(LaneModelScoring, ReliabilityTable) {
  std::vector<std::pair<float, bool>> samples;
  for (int i = 0; i < 10; ++i) samples.emplace_back(0.95f, i < 9);  // 90% right at 0.95
  for (int i = 0; i < 4; ++i) samples.emplace_back(0.25f, i < 1);   // 25% right at 0.25
  samples.emplace_back(1.0f, true);                                 // the last bin
  std::vector<double> edges;
  for (int i = 0; i <= 10; ++i) edges.push_back(0.1 * i);
  const std::vector<ReliabilityBin> t = reliabilityTable(samples, edges);
  ASSERT_EQ(t.size(), 10u);
  EXPECT_EQ(t[9].count, 11);
  EXPECT_NEAR(t[9].fractionCorrect(), 10.0 / 11.0, 1e-12);
  EXPECT_EQ(t[2].count, 4);
  EXPECT_NEAR(t[2].fractionCorrect(), 0.25, 1e-12);
  EXPECT_TRUE(std::isnan(t[5].fractionCorrect()));
  // |0.9545 - 0.9091| * 11 / 15 + |0.25 - 0.25| * 4 / 15
  EXPECT_NEAR(expectedCalibrationError(t), std::fabs((10 * 0.95 + 1.0) / 11 - 10.0 / 11) * 11 / 15,
              1e-6);
}

}  // namespace
}  // namespace tools
}  // namespace rgbd_lane_detector
