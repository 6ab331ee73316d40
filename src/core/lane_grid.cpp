#include "rgbd_lane_detector/lane_grid.h"

#include <algorithm>
#include <cmath>

namespace rgbd_lane_detector {
namespace {

constexpr int kPosEgoLeft = static_cast<int>(BoundaryPosition::kEgoLeft);
constexpr int kPosEgoRight = static_cast<int>(BoundaryPosition::kEgoRight);
constexpr int kPosNextLeft = static_cast<int>(BoundaryPosition::kNextLeft);
constexpr int kPosNextRight = static_cast<int>(BoundaryPosition::kNextRight);

/// A boundary the grid can draw: published, with finite coefficients, range and std.
bool usable(const LaneBoundaryModel& b) {
  if (!b.valid || !std::isfinite(b.x_min) || !std::isfinite(b.x_max) || !(b.x_max >= b.x_min))
    return false;
  for (double c : b.c)
    if (!std::isfinite(c)) return false;
  return true;
}

/// A positive finite setting, or its default.
double positive(double v, double fallback) { return std::isfinite(v) && v > 0.0 ? v : fallback; }

}  // namespace

LaneGridSettings laneGridSettings(const Params& p) {
  LaneGridSettings s;
  s.resolution = p.lane_grid_resolution;
  s.length = p.lane_grid_length;
  s.width = p.lane_grid_width;
  s.allow_lane_change = p.allow_lane_change;
  return s;
}

bool LaneGrid::cellOf(double x, double y, int& row, int& col) const {
  const double c = std::floor(x / resolution_), r = std::floor((y - origin_y_) / resolution_);
  if (!(c >= 0.0 && c < cols_ && r >= 0.0 && r < rows_)) return false;  // also NaN
  row = static_cast<int>(r);
  col = static_cast<int>(c);
  return true;
}

void LaneGrid::rowSpan(double y_lo, double y_hi, int& lo, int& hi) const {
  // row i's centre is origin_y_ + (i + 0.5) resolution_
  const double a = std::ceil((y_lo - origin_y_) / resolution_ - 0.5);
  const double b = std::floor((y_hi - origin_y_) / resolution_ - 0.5);
  lo = static_cast<int>(std::clamp(a, -1.0, static_cast<double>(rows_)));
  hi = static_cast<int>(std::clamp(b, -1.0, static_cast<double>(rows_)));
}

void LaneGrid::fillColumn(int col, int lo, int hi, int8_t value) {
  lo = std::max(lo, 0);
  hi = std::min(hi, rows_ - 1);
  if (lo > hi) return;
  int8_t* cell = cells_.data() + static_cast<size_t>(lo) * cols_ + col;
  for (int r = lo; r <= hi; ++r, cell += cols_) *cell = value;
}

void LaneGrid::build(const LaneModelEstimate& model, const LaneGridSettings& settings) {
  const LaneGridSettings defaults;
  double res = positive(settings.resolution, defaults.resolution);
  const double length = positive(settings.length, defaults.length);
  const double width = positive(settings.width, defaults.width);
  if (length * width / (res * res) > static_cast<double>(kMaxCells))
    res = std::sqrt(length * width / static_cast<double>(kMaxCells));
  resolution_ = res;
  cols_ = std::max(1, static_cast<int>(std::lround(length / res)));
  rows_ = std::max(1, static_cast<int>(std::lround(width / res)));
  origin_y_ = -0.5 * rows_ * res;
  cells_.resize(static_cast<size_t>(rows_) * cols_);  // no allocation once sized
  std::fill(cells_.begin(), cells_.end(), kUnknown);
  if (!model.valid) return;

  bool use[kNumBoundaryPositions];
  double half[kNumBoundaryPositions];  // half-width of each band (m)
  for (int p = 0; p < kNumBoundaryPositions; ++p) {
    const LaneBoundaryModel& b = model.boundaries[p];
    use[p] = usable(b);
    const double std_dev = std::isfinite(b.lateral_std) ? static_cast<double>(b.lateral_std) : 0.0;
    half[p] = std::max(0.5 * res, std_dev);
  }
  const bool dashed_left = model.boundaries[kPosEgoLeft].kind == LineKind::kDashed;
  const bool dashed_right = model.boundaries[kPosEgoRight].kind == LineKind::kDashed;

  for (int col = 0; col < cols_; ++col) {
    const double xa = col * res, xc = (col + 0.5) * res, xb = (col + 1) * res;
    bool here[kNumBoundaryPositions];
    int lo[kNumBoundaryPositions], hi[kNumBoundaryPositions];  // each band's rows
    for (int p = 0; p < kNumBoundaryPositions; ++p) {
      const LaneBoundaryModel& b = model.boundaries[p];
      here[p] = use[p] && xc >= b.x_min && xc <= b.x_max;
      if (!here[p]) continue;
      const double ya = b.lateral(xa), yc = b.lateral(xc), yb = b.lateral(xb);
      here[p] = std::isfinite(ya) && std::isfinite(yc) && std::isfinite(yb);
      if (!here[p]) continue;  // coefficients too large for doubles
      rowSpan(std::min({ya, yc, yb}) - half[p], std::max({ya, yc, yb}) + half[p], lo[p], hi[p]);
    }
    bool crossable[kNumBoundaryPositions] = {false, false, false, false, false, false};
    if (here[kPosEgoLeft] && here[kPosEgoRight] && hi[kPosEgoRight] < lo[kPosEgoLeft]) {
      fillColumn(col, hi[kPosEgoRight] + 1, lo[kPosEgoLeft] - 1, kFree);
      if (settings.allow_lane_change) {
        if (dashed_left && here[kPosNextLeft] && hi[kPosEgoLeft] < lo[kPosNextLeft]) {
          fillColumn(col, hi[kPosEgoLeft] + 1, lo[kPosNextLeft] - 1, kFree);
          crossable[kPosEgoLeft] = true;
        }
        if (dashed_right && here[kPosNextRight] && hi[kPosNextRight] < lo[kPosEgoRight]) {
          fillColumn(col, hi[kPosNextRight] + 1, lo[kPosEgoRight] - 1, kFree);
          crossable[kPosEgoRight] = true;
        }
      }
    }
    for (int p = 0; p < kNumBoundaryPositions; ++p)
      if (here[p] && crossable[p]) fillColumn(col, lo[p], hi[p], kCrossable);
    for (int p = 0; p < kNumBoundaryPositions; ++p)
      if (here[p] && !crossable[p]) fillColumn(col, lo[p], hi[p], kOccupied);
  }
}

}  // namespace rgbd_lane_detector
