/**
 * @file lane_grid_scoring.h
 * @brief Scores of the lane grid (LaneGrid, issue 25) against the frame's true boundaries, their
 * sums per sequence and the Markdown table of docs/RESULTS.md. ROS-free.
 *
 * Everything is compared in base_link (REP-103: x forward, y left): the grid is built from the
 * lane model in base_link, a true boundary is the polyline TrueBoundary::points_base interpolated
 * linearly in x, not extrapolated, with a gap where two samples are more than 2 m apart (as
 * lane_model_scoring.h). A grid column is scored at its centre x; a cell at its centre (x, y).
 *
 * - **Range**: the columns that hold at least one free cell (the grid claims the lane there).
 * - **Boundary coverage**: in every column of the range, the cell of each true ego boundary
 *   (ego_left, ego_right; a kerb or an unpainted edge bounding the ego lane is one of them) that
 *   lies inside the grid is checked: covered when it or a cell within LaneGridRules::neighbourhood
 *   cells (8-neighbourhood) is marked: occupied, or crossable (a dashed line the grid lets the
 *   vehicle cross; only with lane changes allowed).
 * - **Free beyond a boundary**: every free cell is checked against the true boundary that bounds
 *   it on each side: on the left the first of ego_left, next_left, road_edge_left that exists at
 *   its x and may not be crossed (with lane changes allowed, a truly dashed ego boundary may be
 *   crossed: the next line out bounds the cell instead); the right likewise. A free cell whose
 *   centre lies beyond that boundary by more than the published lateral_std of the model's
 *   boundary at the same position (0 when that position is not published) plus one cell is
 *   counted, with its excess (m beyond that tolerance).
 * - **Next lane**: with lane changes allowed, the free cells beyond a truly dashed ego boundary
 *   (by more than its tolerance; next_lane_cells), and in the report the frames whose grid with
 *   lane changes allowed frees more cells than the one without (the grid freed a next lane).
 */
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "rgbd_lane_detector/lane_grid.h"
#include "rgbd_lane_detector/types.h"
#include "rgbd_lane_detector_tools/ground_truth.h"

namespace rgbd_lane_detector {
namespace tools {

/// Thresholds of the lane-grid scores.
struct LaneGridRules {
  int neighbourhood = 1;  ///< cells: a true boundary cell this close to a marked one is covered
};

/// Score of one frame's lane grid.
struct LaneGridScore {
  bool truth_valid = false;   ///< the frame has a vehicle frame (base_link boundaries)
  int free_cells = 0;         ///< cells free
  int free_columns = 0;       ///< columns with a free cell (the range)
  double free_length = 0.0;   ///< m of x they cover
  int boundary_cells = 0;     ///< true ego boundary cells checked (in the range, in the grid)
  int boundary_covered = 0;   ///< of those, marked or next to a marked cell
  int free_checked = 0;       ///< free cells with a true bounding boundary on at least one side
  int free_beyond = 0;        ///< free cells beyond their bounding boundary (see the file comment)
  double worst_beyond = 0.0;  ///< m: the largest excess of such a cell (0: none)
  int next_lane_cells = 0;    ///< free cells across a truly dashed ego boundary (lane changes)
};

/**
 * @brief Score a frame's lane grid.
 * @param[in] grid built from @p model.
 * @param[in] model the lane model it was built from (the published lateral_std).
 * @param[in] truth the frame's truth (format 2: boundaries in base_link).
 * @param[in] allow_lane_change the grid was built with lane changes allowed.
 * @param[in] rules thresholds.
 * @return the scores; nothing is measured without a vehicle frame in @p truth.
 */
LaneGridScore scoreLaneGrid(const LaneGrid& grid, const LaneModelEstimate& model,
                            const FrameTruth& truth, bool allow_lane_change,
                            const LaneGridRules& rules = LaneGridRules());

/// Running totals of lane-grid scores.
struct LaneGridSummary {
  int frames = 0;            ///< frames scored
  int range_frames = 0;      ///< frames with a free cell
  double free_length = 0.0;  ///< sum over frames (m)
  long boundary_cells = 0, boundary_covered = 0;
  long free_cells = 0, free_checked = 0, free_beyond = 0;
  int frames_beyond = 0;     ///< frames with a free cell beyond a boundary
  double worst_beyond = 0.0;
  int worst_frame = -1;
  int next_lane_frames = 0;  ///< frames with the next lane freed across a dashed line
  long next_lane_cells = 0;

  void add(const LaneGridScore& s, int frame);
  void merge(const LaneGridSummary& o);
  /// Covered / checked true boundary cells, % (NaN without any).
  double coveredPercent() const;
  /// Free cells beyond a boundary / checked free cells, % (NaN without any).
  double beyondPercent() const;
  /// Mean free range over the frames with one (m; NaN without any).
  double meanFreeLength() const;
};

/// Lane-grid scores of several sequences and modes: the ego-lane grid (lane changes not
/// allowed, the default) and the grid with lane changes allowed, per sequence, and their table.
class LaneGridReport {
 public:
  /// Add frame @p frame of @p sequence scored for @p mode: @p ego without lane changes,
  /// @p lane_change with them.
  void add(const std::string& sequence, const std::string& mode, int frame,
           const LaneGridScore& ego, const LaneGridScore& lane_change);
  bool empty() const { return entries_.empty(); }
  /// The Markdown table: one row per sequence and mode and one for every sequence pooled.
  void writeMarkdown(std::ostream& md, const std::string& title_suffix = "") const;

 private:
  struct Entry {
    std::string sequence, mode;
    LaneGridSummary ego, lane_change;
    int freed_frames = 0;  ///< frames whose lane-change grid frees more cells (a next lane)
  };
  std::vector<Entry> entries_;
};

}  // namespace tools
}  // namespace rgbd_lane_detector
