// LaneGrid on lane models written by hand (the vehicle frame: x forward, y left), checked cell by
// cell against the boundaries' exact curves: occupied bands of the published width along every
// published boundary and nowhere else, the ego lane free between them over the published range,
// unknown elsewhere; no gap along a slanted boundary; the next lane freed only across a dashed
// ego boundary with allow_lane_change; size, origin and bad input.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/lane_grid.h"

namespace rgbd_lane_detector {
namespace {

constexpr double kEps = 1e-6;

LaneBoundaryModel boundary(BoundaryPosition p, double c0, double c1 = 0.0, double c2 = 0.0,
                           double x_min = 3.0, double x_max = 30.0, float std_dev = 0.05f,
                           LineKind kind = LineKind::kSolid) {
  LaneBoundaryModel b;
  b.valid = true;
  b.position = p;
  b.kind = kind;
  b.c = {c0, c1, c2, 0.0};
  b.x_min = x_min;
  b.x_max = x_max;
  b.lateral_std = std_dev;
  return b;
}

LaneModelEstimate egoLane(double c1 = 0.0, double c2 = 0.0, double width = 3.5,
                          LineKind left_kind = LineKind::kSolid,
                          LineKind right_kind = LineKind::kSolid) {
  LaneModelEstimate m;
  m.valid = true;
  m.width = width;
  m.boundaries[0] = boundary(BoundaryPosition::kEgoLeft, 0.5 * width, c1, c2, 3.0, 30.0, 0.05f,
                             left_kind);
  m.boundaries[1] = boundary(BoundaryPosition::kEgoRight, -0.5 * width, c1, c2, 3.0, 30.0, 0.05f,
                             right_kind);
  for (int p = 2; p < kNumBoundaryPositions; ++p)
    m.boundaries[p].position = static_cast<BoundaryPosition>(p);
  return m;
}

/// Lateral distance of the cell centre (x, y) from boundary @p b, less how far the curve moves
/// within half a cell of x (slope and curvature; the tests' cubics have c3 = 0).
double distanceTo(const LaneBoundaryModel& b, double x, double y, double res) {
  const double slope = std::fabs(b.c[1] + 2.0 * b.c[2] * x);
  return std::fabs(y - b.lateral(x)) - slope * 0.5 * res - std::fabs(b.c[2]) * 0.25 * res * res;
}

double halfWidth(const LaneBoundaryModel& b, double res) {
  return std::max(0.5 * res, static_cast<double>(b.lateral_std));
}

/// Every cell of @p grid against the exact ego lane of @p m (both ego boundaries only):
/// occupied within each band, free strictly between them over the range, unknown elsewhere.
void expectEgoLaneCells(const LaneGrid& grid, const LaneModelEstimate& m) {
  const LaneBoundaryModel& l = m.boundaries[0];
  const LaneBoundaryModel& r = m.boundaries[1];
  const double res = grid.resolution();
  int occupied = 0, free = 0;
  for (int col = 0; col < grid.cols(); ++col) {
    const double x = grid.cellX(col);
    const bool in_range = x >= l.x_min && x <= l.x_max && x >= r.x_min && x <= r.x_max;
    for (int row = 0; row < grid.rows(); ++row) {
      const double y = grid.cellY(row);
      const int8_t v = grid.at(row, col);
      if (!in_range) {
        ASSERT_EQ(v, LaneGrid::kUnknown) << "x " << x << " y " << y;
        continue;
      }
      const double dl = distanceTo(l, x, y, res), dr = distanceTo(r, x, y, res);
      const double hl = halfWidth(l, res), hr = halfWidth(r, res);
      // the band reaches at least h from the curve at the column centre, at most h beyond the
      // curve anywhere along the column
      if (std::fabs(y - l.lateral(x)) <= hl - kEps || std::fabs(y - r.lateral(x)) <= hr - kEps) {
        ASSERT_EQ(v, LaneGrid::kOccupied) << "x " << x << " y " << y;
      } else if (dl > hl + kEps && dr > hr + kEps && y < l.lateral(x) && y > r.lateral(x)) {
        ASSERT_EQ(v, LaneGrid::kFree) << "x " << x << " y " << y;
      } else if ((y > l.lateral(x) && dl > hl + kEps) || (y < r.lateral(x) && dr > hr + kEps)) {
        ASSERT_EQ(v, LaneGrid::kUnknown) << "x " << x << " y " << y;
      }
      occupied += v == LaneGrid::kOccupied;
      free += v == LaneGrid::kFree;
    }
  }
  EXPECT_GT(occupied, 0);
  EXPECT_GT(free, 0);
}

TEST(LaneGrid, DefaultSizeAndOrigin) {
  LaneGrid grid;
  grid.build(LaneModelEstimate(), LaneGridSettings());
  EXPECT_EQ(grid.cols(), 400);  // 40 m ahead
  EXPECT_EQ(grid.rows(), 200);  // 20 m across
  EXPECT_DOUBLE_EQ(grid.resolution(), 0.1);
  EXPECT_DOUBLE_EQ(grid.originX(), 0.0);
  EXPECT_DOUBLE_EQ(grid.originY(), -10.0);
  EXPECT_EQ(grid.cells().size(), 400u * 200u);
  for (int8_t v : grid.cells()) ASSERT_EQ(v, LaneGrid::kUnknown);  // no model: nothing known
  int row = -1, col = -1;
  ASSERT_TRUE(grid.cellOf(12.34, 1.75, row, col));
  EXPECT_EQ(col, 123);
  EXPECT_EQ(row, 117);
  EXPECT_NEAR(grid.cellX(col), 12.35, 1e-9);
  EXPECT_NEAR(grid.cellY(row), 1.75, 1e-9);
  EXPECT_FALSE(grid.cellOf(-0.01, 0.0, row, col));
  EXPECT_FALSE(grid.cellOf(40.0, 0.0, row, col));
  EXPECT_FALSE(grid.cellOf(5.0, 10.0, row, col));
  EXPECT_FALSE(grid.cellOf(std::nan(""), 0.0, row, col));
}

TEST(LaneGrid, StraightLaneCellByCell) {
  LaneGrid grid;
  const LaneModelEstimate m = egoLane();
  grid.build(m, LaneGridSettings());
  expectEgoLaneCells(grid, m);
  // across the lane at 10 m: unknown, one occupied cell at -1.75, free, one at +1.75, unknown
  int row_r = 0, row_l = 0, col = 0;
  ASSERT_TRUE(grid.cellOf(10.0, -1.75 + 0.01, row_r, col));
  ASSERT_TRUE(grid.cellOf(10.0, 1.75 - 0.01, row_l, col));
  EXPECT_EQ(grid.at(row_r - 1, col), LaneGrid::kUnknown);
  EXPECT_EQ(grid.at(row_r, col), LaneGrid::kOccupied);
  for (int row = row_r + 1; row < row_l; ++row) EXPECT_EQ(grid.at(row, col), LaneGrid::kFree);
  EXPECT_EQ(grid.at(row_l, col), LaneGrid::kOccupied);
  EXPECT_EQ(grid.at(row_l + 1, col), LaneGrid::kUnknown);
  // the published range: nothing known before 3 m or after 30 m
  ASSERT_TRUE(grid.cellOf(2.9, 0.0, row_r, col));
  EXPECT_EQ(grid.at(row_r, col), LaneGrid::kUnknown);
  ASSERT_TRUE(grid.cellOf(30.1, 0.0, row_r, col));
  EXPECT_EQ(grid.at(row_r, col), LaneGrid::kUnknown);
}

TEST(LaneGrid, CurvedLaneAtOtherResolutions) {
  for (double res : {0.05, 0.1, 0.25}) {
    SCOPED_TRACE(res);
    LaneGridSettings s;
    s.resolution = res;
    LaneGrid grid;
    const LaneModelEstimate m = egoLane(0.05, 0.5 / 150.0, 3.2);  // heading, radius 150 m
    grid.build(m, s);
    EXPECT_EQ(grid.cols(), static_cast<int>(std::lround(40.0 / res)));
    EXPECT_EQ(grid.rows(), static_cast<int>(std::lround(20.0 / res)));
    expectEgoLaneCells(grid, m);
  }
}

// A steep boundary (45 deg) is one 8-connected band: each column's occupied rows touch the next
// column's.
TEST(LaneGrid, SlantedBoundaryLeavesNoGap) {
  LaneModelEstimate m = egoLane();
  m.boundaries[0] = boundary(BoundaryPosition::kEgoLeft, 1.0, 1.0, 0.0, 3.0, 8.0);
  m.boundaries[1] = boundary(BoundaryPosition::kEgoRight, -1.0, -1.0, 0.0, 3.0, 8.0);
  LaneGrid grid;
  grid.build(m, LaneGridSettings());
  int prev_lo = -1, prev_hi = -1, columns = 0;
  for (int col = 0; col < grid.cols(); ++col) {
    int lo = -1, hi = -1;
    for (int row = grid.rows() / 2; row < grid.rows(); ++row) {  // the left boundary's half
      if (grid.at(row, col) != LaneGrid::kOccupied) continue;
      if (lo < 0) lo = row;
      hi = row;
    }
    if (lo < 0) continue;
    ++columns;
    if (prev_lo >= 0) {
      EXPECT_LE(lo, prev_hi + 1) << "col " << col;
      EXPECT_LE(prev_lo, hi + 1) << "col " << col;
    }
    prev_lo = lo;
    prev_hi = hi;
  }
  EXPECT_EQ(columns, 50);  // 3 to 8 m
  expectEgoLaneCells(grid, m);
}

TEST(LaneGrid, BandWidthFollowsLateralStd) {
  for (float std_dev : {0.0f, 0.05f, 0.2f, 0.45f}) {
    SCOPED_TRACE(std_dev);
    LaneModelEstimate m = egoLane();
    m.boundaries[0].lateral_std = std_dev;
    LaneGrid grid;
    grid.build(m, LaneGridSettings());
    expectEgoLaneCells(grid, m);
    int row = 0, col = 0, occupied = 0;
    ASSERT_TRUE(grid.cellOf(10.0, 0.0, row, col));
    for (int r = grid.rows() / 2; r < grid.rows(); ++r) occupied += grid.at(r, col) == LaneGrid::kOccupied;
    // 2 h / resolution cells, h = max(std, resolution / 2), give or take a cell at the edges
    const double cells = 2.0 * std::max(0.05, static_cast<double>(std_dev)) / 0.1;
    EXPECT_GE(occupied, std::floor(cells - 1e-9)) << occupied;
    EXPECT_LE(occupied, std::ceil(cells + 1e-9) + 1) << occupied;
  }
}

// Road edges and the next lanes' lines are occupied over their own ranges; the cells between
// them and the ego lane stay unknown while lane changes are not allowed.
TEST(LaneGrid, OuterBoundariesOccupiedAndBeyondTheEgoLaneUnknown) {
  LaneModelEstimate m = egoLane(0.0, 0.0, 3.5, LineKind::kDashed, LineKind::kSolid);
  m.boundaries[2] = boundary(BoundaryPosition::kNextLeft, 5.25, 0, 0, 5.0, 25.0);
  m.boundaries[5] = boundary(BoundaryPosition::kRoadEdgeRight, -2.5, 0, 0, 4.0, 20.0, 0.1f,
                             LineKind::kRoadEdge);
  LaneGrid grid;
  grid.build(m, LaneGridSettings());
  int row = 0, col = 0;
  ASSERT_TRUE(grid.cellOf(10.0, 5.25 + 0.01, row, col));
  EXPECT_EQ(grid.at(row, col), LaneGrid::kOccupied);
  ASSERT_TRUE(grid.cellOf(10.0, 3.5, row, col));  // in the next lane
  EXPECT_EQ(grid.at(row, col), LaneGrid::kUnknown);
  ASSERT_TRUE(grid.cellOf(10.0, -2.5 + 0.01, row, col));
  EXPECT_EQ(grid.at(row, col), LaneGrid::kOccupied);
  ASSERT_TRUE(grid.cellOf(21.0, -2.5 + 0.01, row, col));  // beyond the road edge's range
  EXPECT_EQ(grid.at(row, col), LaneGrid::kUnknown);
  ASSERT_TRUE(grid.cellOf(10.0, -2.1, row, col));  // between the ego line and the road edge
  EXPECT_EQ(grid.at(row, col), LaneGrid::kUnknown);
}

// allow_lane_change frees the next lane only across a dashed ego boundary and only where the
// next lane's far line is published; the dashed line's band becomes crossable (50).
TEST(LaneGrid, LaneChangeFreesTheNextLaneOnlyAcrossADashedBoundary) {
  LaneModelEstimate m = egoLane(0.0, 0.0, 3.5, LineKind::kDashed, LineKind::kSolid);
  m.boundaries[2] = boundary(BoundaryPosition::kNextLeft, 5.25, 0, 0, 5.0, 25.0);
  m.boundaries[3] = boundary(BoundaryPosition::kNextRight, -5.25, 0, 0, 5.0, 25.0);
  LaneGridSettings s;
  s.allow_lane_change = true;
  LaneGrid grid;
  grid.build(m, s);
  int row = 0, col = 0;
  ASSERT_TRUE(grid.cellOf(10.0, 3.5, row, col));  // next lane left, across the dashed line
  EXPECT_EQ(grid.at(row, col), LaneGrid::kFree);
  ASSERT_TRUE(grid.cellOf(10.0, 1.75 + 0.01, row, col));  // the dashed line itself
  EXPECT_EQ(grid.at(row, col), LaneGrid::kCrossable);
  ASSERT_TRUE(grid.cellOf(10.0, 5.25 + 0.01, row, col));  // the next lane's far line
  EXPECT_EQ(grid.at(row, col), LaneGrid::kOccupied);
  ASSERT_TRUE(grid.cellOf(10.0, 5.5, row, col));  // beyond it
  EXPECT_EQ(grid.at(row, col), LaneGrid::kUnknown);
  ASSERT_TRUE(grid.cellOf(10.0, -3.5, row, col));  // next lane right, across a solid line
  EXPECT_EQ(grid.at(row, col), LaneGrid::kUnknown);
  ASSERT_TRUE(grid.cellOf(10.0, -1.75 + 0.01, row, col));
  EXPECT_EQ(grid.at(row, col), LaneGrid::kOccupied);
  ASSERT_TRUE(grid.cellOf(27.0, 3.5, row, col));  // beyond the next lane's range
  EXPECT_EQ(grid.at(row, col), LaneGrid::kUnknown);
  ASSERT_TRUE(grid.cellOf(27.0, 1.75 + 0.01, row, col));  // the dashed line, not crossable there
  EXPECT_EQ(grid.at(row, col), LaneGrid::kOccupied);
  ASSERT_TRUE(grid.cellOf(27.0, 0.0, row, col));  // the ego lane
  EXPECT_EQ(grid.at(row, col), LaneGrid::kFree);

  // not allowed, or allowed without a published next lane: the ego lane only
  for (const bool allow : {false, true}) {
    LaneModelEstimate n = m;
    if (allow) n.boundaries[2].valid = false;
    s.allow_lane_change = allow;
    grid.build(n, s);
    ASSERT_TRUE(grid.cellOf(10.0, 3.5, row, col));
    EXPECT_EQ(grid.at(row, col), LaneGrid::kUnknown) << allow;
    ASSERT_TRUE(grid.cellOf(10.0, 1.75 + 0.01, row, col));
    EXPECT_EQ(grid.at(row, col), LaneGrid::kOccupied) << allow;
  }
  // both sides dashed: both next lanes
  m.boundaries[1].kind = LineKind::kDashed;
  s.allow_lane_change = true;
  grid.build(m, s);
  ASSERT_TRUE(grid.cellOf(10.0, -3.5, row, col));
  EXPECT_EQ(grid.at(row, col), LaneGrid::kFree);
  ASSERT_TRUE(grid.cellOf(10.0, 3.5, row, col));
  EXPECT_EQ(grid.at(row, col), LaneGrid::kFree);
}

// One ego boundary alone: it is occupied, nothing is free (the other side is not published).
TEST(LaneGrid, OneSideAloneFreesNothing) {
  LaneModelEstimate m = egoLane();
  m.boundaries[1].valid = false;
  LaneGrid grid;
  grid.build(m, LaneGridSettings());
  int occupied = 0;
  for (int8_t v : grid.cells()) {
    ASSERT_NE(v, LaneGrid::kFree);
    occupied += v == LaneGrid::kOccupied;
  }
  EXPECT_EQ(occupied, 270);  // one cell per column from 3 to 30 m
}

// Boundaries beyond the grid's sides: the lane is free up to the grid's edge.
TEST(LaneGrid, LaneWiderThanTheGrid) {
  LaneGridSettings s;
  s.width = 4.0;
  LaneGrid grid;
  grid.build(egoLane(0.0, 0.0, 6.0), s);
  EXPECT_EQ(grid.rows(), 40);
  int row = 0, col = 0;
  ASSERT_TRUE(grid.cellOf(10.0, 1.95, row, col));
  EXPECT_EQ(grid.at(row, col), LaneGrid::kFree);
  ASSERT_TRUE(grid.cellOf(10.0, -1.95, row, col));
  EXPECT_EQ(grid.at(row, col), LaneGrid::kFree);
}

TEST(LaneGrid, BadInputNeverBreaksIt) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  LaneGrid grid;
  // settings: non-finite or non-positive values are the defaults; a huge grid is coarsened
  LaneGridSettings s;
  s.resolution = nan;
  s.length = -5.0;
  s.width = inf;
  grid.build(egoLane(), s);
  EXPECT_EQ(grid.cols(), 400);
  EXPECT_EQ(grid.rows(), 200);
  s = LaneGridSettings();
  s.resolution = 0.001;
  s.length = 200.0;
  s.width = 100.0;
  grid.build(egoLane(), s);
  EXPECT_LE(static_cast<long>(grid.rows()) * grid.cols(), LaneGrid::kMaxCells + 1000);
  EXPECT_GT(grid.resolution(), 0.001);
  // non-finite coefficients, ranges, std; coefficients whose cubic overflows
  for (int k = 0; k < 5; ++k) {
    LaneModelEstimate m = egoLane();
    LaneBoundaryModel& b = m.boundaries[0];
    if (k == 0) b.c[1] = nan;
    if (k == 1) b.x_max = inf;
    if (k == 2) b.x_min = nan;
    if (k == 3) b.c[3] = 1e306;
    if (k == 4) b.lateral_std = std::numeric_limits<float>::quiet_NaN();
    grid.build(m, LaneGridSettings());
    int occupied = 0, free = 0;
    for (int8_t v : grid.cells()) {
      occupied += v == LaneGrid::kOccupied;
      free += v == LaneGrid::kFree;
    }
    if (k == 4) {  // a NaN std is no std: the band is one cell
      EXPECT_EQ(occupied, 2 * 270) << k;
      EXPECT_GT(free, 0) << k;
    } else if (k == 3) {  // the left boundary leaves the grid (then the doubles): the right one
      EXPECT_EQ(occupied, 270) << k;
    } else {  // the left boundary is absent: the right one alone, nothing free
      EXPECT_EQ(free, 0) << k;
      EXPECT_EQ(occupied, 270) << k;
    }
  }
  // crossed ego boundaries (left right of right): nothing free between them
  LaneModelEstimate crossed = egoLane();
  std::swap(crossed.boundaries[0].c, crossed.boundaries[1].c);
  grid.build(crossed, LaneGridSettings());
  for (int8_t v : grid.cells()) ASSERT_NE(v, LaneGrid::kFree);
  // an invalid model: unknown everywhere, whatever its boundaries say
  LaneModelEstimate invalid = egoLane();
  invalid.valid = false;
  grid.build(invalid, LaneGridSettings());
  for (int8_t v : grid.cells()) ASSERT_EQ(v, LaneGrid::kUnknown);
}

TEST(LaneGrid, SettingsFromParams) {
  Params p;
  const LaneGridSettings d = laneGridSettings(p);
  EXPECT_DOUBLE_EQ(d.resolution, 0.1);
  EXPECT_DOUBLE_EQ(d.length, 40.0);
  EXPECT_DOUBLE_EQ(d.width, 20.0);
  EXPECT_FALSE(d.allow_lane_change);
  p.lane_grid_resolution = 0.2;
  p.lane_grid_length = 30.0;
  p.lane_grid_width = 12.0;
  p.allow_lane_change = true;
  const LaneGridSettings s = laneGridSettings(p);
  EXPECT_DOUBLE_EQ(s.resolution, 0.2);
  EXPECT_DOUBLE_EQ(s.length, 30.0);
  EXPECT_DOUBLE_EQ(s.width, 12.0);
  EXPECT_TRUE(s.allow_lane_change);
}

}  // namespace
}  // namespace rgbd_lane_detector
