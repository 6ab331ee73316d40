/**
 * @file lane_grid.h
 * @brief The lane model as an occupancy grid for planners and costmaps (the values of
 * nav_msgs/OccupancyGrid): a rolling grid in the vehicle frame, rebuilt from each frame's
 * LaneModelEstimate (the stage after the lane model; the nodelet publishes it as `lane_grid`).
 *
 * Frame: the lane model's vehicle frame (REP-103: x forward, y left). The grid covers x in
 * [0, length) ahead of the vehicle and y in [-width / 2, width / 2); cell (row, col) is the square
 * of side `resolution` whose corner nearest the origin is (col * resolution, -width / 2 + row *
 * resolution), so its centre is cellX(col), cellY(row). Cells are stored row-major (index = row *
 * cols() + col), rows along y (increasing to the left), columns along x, as OccupancyGrid.data
 * with info.origin = (originX(), originY(), 0) and the identity orientation.
 *
 * Values:
 * - kOccupied (100): on a published boundary (ego, next lane or road edge): the cells whose
 *   centre lies within max(lateral_std, resolution / 2) of the boundary's cubic anywhere along
 *   the column (both column edges and the centre, so a slanted boundary leaves no gap), over the
 *   boundary's published range [x_min, x_max] (column centres);
 * - kFree (0): between the two ego boundaries' bands, in the columns where both are published;
 * - with allow_lane_change, a dashed ego boundary with the next lane beyond it published in that
 *   column: the next lane (between the two bands) is free too and the dashed boundary's band is
 *   kCrossable (50: free in a trinary costmap, a medium cost otherwise) instead of occupied;
 * - kUnknown (-1) everywhere else (beyond the published range, beyond the ego lane, everywhere
 *   when the model is not valid).
 * Occupied bands are written last: they win over free cells and crossable bands.
 *
 * Steady state allocates nothing: the cells are resized only when the size changes. Non-finite
 * coefficients, ranges or standard deviations make a boundary absent; the cell count is capped
 * at kMaxCells (the resolution is coarsened to fit).
 */
#pragma once

#include <cstdint>
#include <vector>

#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/// Size and content rules of the lane grid (filled from Params: laneGridSettings()).
struct LaneGridSettings {
  double resolution = 0.1;         ///< m: side of a cell
  double length = 40.0;            ///< m ahead of the vehicle (x in [0, length))
  double width = 20.0;             ///< m across, centred on the vehicle
  bool allow_lane_change = false;  ///< free the next lane across a dashed ego boundary
};

/// The lane grid settings of @p p (lane_grid_resolution, lane_grid_length, lane_grid_width,
/// allow_lane_change).
LaneGridSettings laneGridSettings(const Params& p);

/// The lane model rasterised into an occupancy grid (see the file comment).
class LaneGrid {
 public:
  static constexpr int8_t kUnknown = -1;
  static constexpr int8_t kFree = 0;
  static constexpr int8_t kCrossable = 50;
  static constexpr int8_t kOccupied = 100;
  static constexpr long kMaxCells = 4000000;  ///< larger grids are built at a coarser resolution

  /**
   * @brief Rebuild the grid from @p model.
   * @param[in] model the lane model in the vehicle frame (Result::lane_model).
   * @param[in] settings size and rules (invalid or non-finite values fall back to the defaults).
   */
  void build(const LaneModelEstimate& model, const LaneGridSettings& settings);

  int rows() const { return rows_; }  ///< cells along y (OccupancyGrid info.height)
  int cols() const { return cols_; }  ///< cells along x (OccupancyGrid info.width)
  double resolution() const { return resolution_; }  ///< m (after the kMaxCells cap)
  double originX() const { return 0.0; }              ///< m: x of the grid's corner
  double originY() const { return origin_y_; }        ///< m: y of the grid's corner
  const std::vector<int8_t>& cells() const { return cells_; }
  int8_t at(int row, int col) const { return cells_[static_cast<size_t>(row) * cols_ + col]; }
  double cellX(int col) const { return (col + 0.5) * resolution_; }
  double cellY(int row) const { return origin_y_ + (row + 0.5) * resolution_; }
  /// The cell holding (x, y); false outside the grid.
  bool cellOf(double x, double y, int& row, int& col) const;

 private:
  /// Rows [lo, hi] whose centres lie in [y_lo, y_hi], clamped to [-1, rows_] (may be empty).
  void rowSpan(double y_lo, double y_hi, int& lo, int& hi) const;
  void fillColumn(int col, int lo, int hi, int8_t value);

  std::vector<int8_t> cells_;
  int rows_ = 0, cols_ = 0;
  double resolution_ = 0.1, origin_y_ = 0.0;
};

}  // namespace rgbd_lane_detector
