// scoreLaneGrid() on hand-made truths (straight lines in base_link, sampled like the generator's)
// and grids built from lane models placed at, or off, those lines: coverage, free cells beyond a
// boundary with their excess, and the next lane across a dashed or a solid line.
#include <cmath>
#include <sstream>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/lane_grid.h"
#include "rgbd_lane_detector_tools/lane_grid_scoring.h"

namespace rgbd_lane_detector {
namespace tools {
namespace {

TrueBoundary trueLine(BoundaryLabel label, double y, LineStyle style = LineStyle::kSolid) {
  TrueBoundary b;
  b.label = label;
  b.kind = BoundaryKind::kPaint;
  b.style = style;
  b.colour = LineColour::kWhite;
  for (double x = 3.0; x <= 60.0; x += 0.5) {
    b.points_base.emplace_back(x, y, 0.0);
    b.points.emplace_back(-y, 1.5, x);  // optical frame (unused by the grid scores)
  }
  return b;
}

/// Two lanes: the ego lane (1.75 / -1.75) and the one to its left (far line 5.25).
FrameTruth twoLanes(LineStyle ego_left_style) {
  FrameTruth t;
  t.has_vehicle_frame = true;
  t.boundaries = {trueLine(BoundaryLabel::kEgoLeft, 1.75, ego_left_style),
                  trueLine(BoundaryLabel::kEgoRight, -1.75),
                  trueLine(BoundaryLabel::kNextLeft, 5.25)};
  t.syncEgoLines();
  return t;
}

LaneBoundaryModel modelLine(BoundaryPosition p, double y, LineKind kind = LineKind::kSolid,
                            float std_dev = 0.05f) {
  LaneBoundaryModel b;
  b.valid = true;
  b.position = p;
  b.kind = kind;
  b.c = {y, 0.0, 0.0, 0.0};
  b.x_min = 4.0;
  b.x_max = 30.0;
  b.lateral_std = std_dev;
  return b;
}

/// A model of the two lanes with the ego left line at @p left.
LaneModelEstimate model(double left = 1.75, LineKind left_kind = LineKind::kSolid) {
  LaneModelEstimate m;
  m.valid = true;
  m.boundaries[0] = modelLine(BoundaryPosition::kEgoLeft, left, left_kind);
  m.boundaries[1] = modelLine(BoundaryPosition::kEgoRight, -1.75);
  m.boundaries[2] = modelLine(BoundaryPosition::kNextLeft, 5.25);
  return m;
}

LaneGridScore score(const LaneModelEstimate& m, const FrameTruth& t, bool allow) {
  LaneGridSettings s;
  s.allow_lane_change = allow;
  LaneGrid grid;
  grid.build(m, s);
  return scoreLaneGrid(grid, m, t, allow);
}

TEST(LaneGridScoring, GridOnTheTruthIsCoveredAndFreeOnlyInside) {
  const LaneGridScore s = score(model(), twoLanes(LineStyle::kSolid), false);
  ASSERT_TRUE(s.truth_valid);
  EXPECT_EQ(s.free_columns, 260);  // 4 to 30 m
  EXPECT_NEAR(s.free_length, 26.0, 1e-9);
  EXPECT_EQ(s.boundary_cells, 2 * 260);
  EXPECT_EQ(s.boundary_covered, s.boundary_cells);
  EXPECT_EQ(s.free_checked, s.free_cells);
  EXPECT_GT(s.free_cells, 260 * 30);
  EXPECT_EQ(s.free_beyond, 0);
  EXPECT_EQ(s.worst_beyond, 0.0);
  EXPECT_EQ(s.next_lane_cells, 0);
}

// The model's left line 0.4 m too far out: its band is 4 cells from the true line (not covered)
// and the free cells reach 0.35 m past it, 0.2 m beyond its std + one cell.
TEST(LaneGridScoring, ModelOffTheLineFreesCellsBeyondIt) {
  const LaneGridScore s = score(model(2.15), twoLanes(LineStyle::kSolid), false);
  EXPECT_EQ(s.boundary_cells, 2 * 260);
  EXPECT_EQ(s.boundary_covered, 260) << "the right line only";
  EXPECT_EQ(s.free_beyond, 260 * 2) << "two cells per column (centres 1.95, 2.05)";
  EXPECT_NEAR(s.worst_beyond, 2.05 - (1.75 + 0.05 + 0.1), 1e-6);
  // within std + one cell of the truth: not counted
  const LaneGridScore near = score(model(1.88), twoLanes(LineStyle::kSolid), false);
  EXPECT_EQ(near.free_beyond, 0);
  EXPECT_EQ(near.boundary_covered, near.boundary_cells) << "one cell off: still covered";
}

// Lane changes allowed: the next lane freed across a truly dashed line counts as the next lane;
// the same grid over a truly solid line is free beyond a boundary, a lane's width of it.
TEST(LaneGridScoring, NextLaneOnlyAcrossADashedLine) {
  const LaneModelEstimate m = model(1.75, LineKind::kDashed);
  const LaneGridScore dashed = score(m, twoLanes(LineStyle::kDashed), true);
  EXPECT_GT(dashed.next_lane_cells, 260 * 30);
  EXPECT_EQ(dashed.free_beyond, 0);
  EXPECT_EQ(dashed.boundary_covered, dashed.boundary_cells) << "the crossable band is marked";
  const LaneGridScore solid = score(m, twoLanes(LineStyle::kSolid), true);
  EXPECT_EQ(solid.next_lane_cells, 0);
  EXPECT_EQ(solid.free_beyond, dashed.next_lane_cells);
  EXPECT_NEAR(solid.worst_beyond, 5.15 - (1.75 + 0.05 + 0.1), 1e-6);
  // not allowed: the same truths give nothing beyond and no next lane
  const LaneGridScore ego = score(m, twoLanes(LineStyle::kDashed), false);
  EXPECT_EQ(ego.next_lane_cells, 0);
  EXPECT_EQ(ego.free_beyond, 0);
}

TEST(LaneGridScoring, NothingWithoutAVehicleFrame) {
  FrameTruth t = twoLanes(LineStyle::kSolid);
  t.has_vehicle_frame = false;
  const LaneGridScore s = score(model(), t, false);
  EXPECT_FALSE(s.truth_valid);
  EXPECT_EQ(s.free_cells, 0);
  LaneGridSummary sum;
  sum.add(s, 0);
  EXPECT_EQ(sum.frames, 0);
  EXPECT_TRUE(std::isnan(sum.coveredPercent()));
}

TEST(LaneGridScoring, SummaryAndReport) {
  LaneGridSummary a, b;
  a.add(score(model(), twoLanes(LineStyle::kSolid), false), 3);
  b.add(score(model(2.15), twoLanes(LineStyle::kSolid), false), 7);
  EXPECT_DOUBLE_EQ(a.coveredPercent(), 100.0);
  EXPECT_DOUBLE_EQ(b.coveredPercent(), 50.0);
  a.merge(b);
  EXPECT_EQ(a.frames, 2);
  EXPECT_EQ(a.worst_frame, 7);
  EXPECT_EQ(a.frames_beyond, 1);
  EXPECT_DOUBLE_EQ(a.coveredPercent(), 75.0);
  EXPECT_NEAR(a.meanFreeLength(), 26.0, 1e-9);
  LaneGridReport report;
  EXPECT_TRUE(report.empty());
  report.add("solid", "improved", 0, score(model(), twoLanes(LineStyle::kSolid), false),
             score(model(), twoLanes(LineStyle::kSolid), true));
  report.add("off", "improved", 7, score(model(2.15), twoLanes(LineStyle::kSolid), false),
             score(model(2.15), twoLanes(LineStyle::kSolid), true));
  // a frame whose grid frees the next lane across its dashed line: counted as freed, nothing beyond
  const LaneModelEstimate dashed = model(1.75, LineKind::kDashed);
  report.add("dashed", "improved", 0, score(dashed, twoLanes(LineStyle::kDashed), false),
             score(dashed, twoLanes(LineStyle::kDashed), true));
  std::ostringstream md;
  report.writeMarkdown(md);
  for (const char* row :
       {"| solid | improved | 1 | 1 | 26.0 | 520 | 100.00 | 8840 | 0 (0.0000%) | - | 0 | 0 | 0 |",
        "| off | improved | 1 | 1 | 26.0 | 520 | 50.00 | 9880 | 520 (5.2632%) | 0.150 (7) | 1 | 0 | "
        "520 |",
        "| dashed | improved | 1 | 1 | 26.0 | 520 | 100.00 | 8840 | 0 (0.0000%) | - | 0 | 1 | 0 |",
        "| **all** | improved | 3 | 3 | 26.0 | 1560 | 83.33 | 27560 | 520 "})
    EXPECT_NE(md.str().find(row), std::string::npos) << row << "\n" << md.str();
}

}  // namespace
}  // namespace tools
}  // namespace rgbd_lane_detector
