#include "rgbd_lane_detector_tools/lane_grid_scoring.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "rgbd_lane_detector_tools/lane_model_scoring.h"
#include "rgbd_lane_detector_tools/scoring.h"

namespace rgbd_lane_detector {
namespace tools {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kTruthGap = 2.0;  // m: the truth is sampled every 0.5 m; a longer step is a gap

/// What bounds the free cells of one side at one x.
struct Bound {
  double y = kNaN;        ///< the bounding true boundary's y (NaN: none)
  double tolerance = 0.0; ///< its published std + one cell
  double cross_y = kNaN;  ///< a truly dashed ego boundary crossed before it (lane changes)
  double cross_tolerance = 0.0;
};

std::string fmt(const char* f, double v) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof(buf), f, v);
  return buf;
}

double percent(long a, long b) { return b > 0 ? 100.0 * static_cast<double>(a) / b : kNaN; }

}  // namespace

LaneGridScore scoreLaneGrid(const LaneGrid& grid, const LaneModelEstimate& model,
                            const FrameTruth& truth, bool allow_lane_change,
                            const LaneGridRules& rules) {
  LaneGridScore s;
  if (!truth.has_vehicle_frame) return s;
  s.truth_valid = true;
  LateralLine lines[kNumBoundaryLabels];
  bool dashed[kNumBoundaryLabels] = {};
  double tolerance[kNumBoundaryLabels];
  for (int p = 0; p < kNumBoundaryLabels; ++p) {
    const TrueBoundary* t = truth.boundary(static_cast<BoundaryLabel>(p));
    if (t) {
      lines[p] = LateralLine(t->points_base, kTruthGap);
      dashed[p] = trueLineKind(*t) == LineKind::kDashed;
    }
    const LaneBoundaryModel& b = model.boundaries[p];
    const double std_dev = model.valid && b.valid && std::isfinite(b.lateral_std) ? b.lateral_std : 0.0;
    tolerance[p] = std_dev + grid.resolution();
  }
  // the labels of each side, inner to outer
  const int sides[2][3] = {{static_cast<int>(BoundaryLabel::kEgoLeft),
                            static_cast<int>(BoundaryLabel::kNextLeft),
                            static_cast<int>(BoundaryLabel::kRoadEdgeLeft)},
                           {static_cast<int>(BoundaryLabel::kEgoRight),
                            static_cast<int>(BoundaryLabel::kNextRight),
                            static_cast<int>(BoundaryLabel::kRoadEdgeRight)}};
  for (int col = 0; col < grid.cols(); ++col) {
    int free_here = 0;
    for (int row = 0; row < grid.rows(); ++row) free_here += grid.at(row, col) == LaneGrid::kFree;
    if (free_here == 0) continue;
    s.free_cells += free_here;
    ++s.free_columns;
    const double x = grid.cellX(col);
    Bound bound[2];
    for (int side = 0; side < 2; ++side) {
      for (int p : sides[side]) {
        const double y = lines[p].at(x);
        if (!std::isfinite(y)) continue;
        const bool ego = p == sides[side][0];
        if (ego && allow_lane_change && dashed[p]) {  // may be crossed: the next line bounds
          bound[side].cross_y = y;
          bound[side].cross_tolerance = tolerance[p];
          continue;
        }
        bound[side].y = y;
        bound[side].tolerance = tolerance[p];
        break;
      }
    }
    for (int row = 0; row < grid.rows(); ++row) {
      if (grid.at(row, col) != LaneGrid::kFree) continue;
      const double y = grid.cellY(row);
      const double excess[2] = {y - (bound[0].y + bound[0].tolerance),
                                (bound[1].y - bound[1].tolerance) - y};
      if (std::isfinite(bound[0].y) || std::isfinite(bound[1].y)) ++s.free_checked;
      double worst = 0.0;
      for (double e : excess)
        if (e > 0.0) worst = std::max(worst, e);  // NaN (no bound) compares false
      if (worst > 0.0) {
        ++s.free_beyond;
        s.worst_beyond = std::max(s.worst_beyond, worst);
      }
      if (y > bound[0].cross_y + bound[0].cross_tolerance ||
          y < bound[1].cross_y - bound[1].cross_tolerance)
        ++s.next_lane_cells;
    }
    // the true ego boundaries' cells in this column: marked, or next to a marked cell
    for (int side = 0; side < 2; ++side) {
      int row = 0, c = 0;
      if (!grid.cellOf(x, lines[sides[side][0]].at(x), row, c)) continue;  // NaN: outside
      ++s.boundary_cells;
      const int n = rules.neighbourhood;
      bool covered = false;
      for (int dc = -n; dc <= n && !covered; ++dc)
        for (int dr = -n; dr <= n && !covered; ++dr) {
          const int rr = row + dr, cc = col + dc;
          covered = rr >= 0 && rr < grid.rows() && cc >= 0 && cc < grid.cols() &&
                    grid.at(rr, cc) > LaneGrid::kFree;
        }
      s.boundary_covered += covered;
    }
  }
  s.free_length = s.free_columns * grid.resolution();
  return s;
}

void LaneGridSummary::add(const LaneGridScore& s, int frame) {
  if (!s.truth_valid) return;
  LaneGridSummary one;  // this frame alone
  one.frames = 1;
  one.range_frames = s.free_cells > 0;
  one.free_length = s.free_length;
  one.boundary_cells = s.boundary_cells;
  one.boundary_covered = s.boundary_covered;
  one.free_cells = s.free_cells;
  one.free_checked = s.free_checked;
  one.free_beyond = s.free_beyond;
  one.frames_beyond = s.free_beyond > 0;
  one.worst_beyond = s.worst_beyond;
  one.worst_frame = frame;
  one.next_lane_frames = s.next_lane_cells > 0;
  one.next_lane_cells = s.next_lane_cells;
  merge(one);
}

void LaneGridSummary::merge(const LaneGridSummary& o) {
  frames += o.frames;
  range_frames += o.range_frames;
  free_length += o.free_length;
  boundary_cells += o.boundary_cells;
  boundary_covered += o.boundary_covered;
  free_cells += o.free_cells;
  free_checked += o.free_checked;
  free_beyond += o.free_beyond;
  frames_beyond += o.frames_beyond;
  if (o.worst_beyond > worst_beyond) {
    worst_beyond = o.worst_beyond;
    worst_frame = o.worst_frame;
  }
  next_lane_frames += o.next_lane_frames;
  next_lane_cells += o.next_lane_cells;
}

double LaneGridSummary::coveredPercent() const { return percent(boundary_covered, boundary_cells); }
double LaneGridSummary::beyondPercent() const { return percent(free_beyond, free_checked); }
double LaneGridSummary::meanFreeLength() const {
  return range_frames > 0 ? free_length / range_frames : kNaN;
}

void LaneGridReport::add(const std::string& sequence, const std::string& mode, int frame,
                         const LaneGridScore& ego, const LaneGridScore& lane_change) {
  auto it = std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) {
    return e.sequence == sequence && e.mode == mode;
  });
  if (it == entries_.end()) {
    entries_.push_back(Entry{sequence, mode, LaneGridSummary(), LaneGridSummary(), 0});
    it = entries_.end() - 1;
  }
  it->ego.add(ego, frame);
  it->lane_change.add(lane_change, frame);
  it->freed_frames += ego.truth_valid && lane_change.free_cells > ego.free_cells;
}

void LaneGridReport::writeMarkdown(std::ostream& md, const std::string& title_suffix) const {
  md << "#### Lane grid against the truth" << title_suffix << "\n\n"
     << "Rules: `tools/include/rgbd_lane_detector_tools/lane_grid_scoring.h`. Default grid "
        "(0.1 m, 40 m x 20 m; lane changes not allowed): the range is the columns with a free "
        "cell; *covered* = true ego boundary cells in the range that are occupied or within one "
        "cell of an occupied one; *free beyond* = free cells whose centre lies beyond the true "
        "boundary bounding them by more than the published lateral_std + one cell (% of the "
        "free cells with a true boundary beside them; the worst excess beyond that tolerance with "
        "its frame, and the frames with any). With `allow_lane_change`: the frames in which the "
        "grid frees a next lane (more free cells than without), and the free cells beyond a "
        "boundary that may not be crossed (a solid line or road edge, the next lane's far line; "
        "a truly dashed ego line may be crossed).\n\n"
     << "| sequence | mode | frames | frames with a free lane | free range (m, mean) | true "
        "boundary cells | covered % | free cells | free beyond | worst (m, frame) | frames with "
        "one | lane changes allowed: frames with a next lane freed | lane changes allowed: free "
        "beyond a boundary that may not be crossed |\n"
     << "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: "
        "|\n";
  auto row = [&md](const std::string& sequence, const std::string& mode,
                   const LaneGridSummary& e, const LaneGridSummary& lc, int freed) {
    md << "| " << sequence << " | " << mode << " | " << e.frames << " | " << e.range_frames
       << " | " << fmt("%.1f", e.meanFreeLength()) << " | " << e.boundary_cells << " | "
       << fmt("%.2f", e.coveredPercent()) << " | " << e.free_cells << " | " << e.free_beyond
       << " (" << fmt("%.4f", e.beyondPercent()) << "%) | "
       << (e.free_beyond > 0 ? fmt("%.3f", e.worst_beyond) + " (" + std::to_string(e.worst_frame) + ")"
                             : std::string("-"))
       << " | " << e.frames_beyond << " | " << freed << " | " << lc.free_beyond
       << " |\n";
  };
  std::vector<std::string> modes;
  for (const Entry& e : entries_)
    if (std::find(modes.begin(), modes.end(), e.mode) == modes.end()) modes.push_back(e.mode);
  for (const std::string& mode : modes) {
    LaneGridSummary ego, lane_change;
    int freed = 0;
    for (const Entry& e : entries_) {
      if (e.mode != mode) continue;
      row(e.sequence, e.mode, e.ego, e.lane_change, e.freed_frames);
      ego.merge(e.ego);
      lane_change.merge(e.lane_change);
      freed += e.freed_frames;
    }
    row("**all**", mode, ego, lane_change, freed);
  }
  md << "\n";
}

}  // namespace tools
}  // namespace rgbd_lane_detector
