/**
 * @file boundary_classifier.h
 * @brief What a traced line is: paint, a road edge, or no lane boundary at all (the improved
 * mode's candidate check, after tracing and before the lane fit).
 *
 * Paint lies flat on the road surface (within a few centimetres) and is a bright band, brighter
 * than the asphalt on both sides, 7-45 cm wide (single and double lines). A road edge is a
 * height step (kerb, guard-rail foot: the surface beyond it is raised above the road that the
 * depth measures on the vehicle's side), or a narrow bright line that is not paint and that the
 * depth places on the road (a rail head is 4-7 cm), or a change of surface (asphalt to grass:
 * the colour changes, not only the brightness; a shadow's edge also changes the colour, but
 * toward blue on its dark side, lit by the sky, and is not taken for an edge). Anything well
 * above the road (a truck's stripe, a guard rail's beam) and anything wider than paint (a zebra
 * stripe, an arrow head) is no boundary.
 */
#pragma once

#include <limits>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/band_profile.h"
#include "rgbd_lane_detector/classifier_input.h"
#include "rgbd_lane_detector/line_follower.h"
#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/// What the classifier measured on one traced line (medians over its measured rows).
struct BoundaryEvidence {
  static constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  bool boundary = false;        ///< a lane boundary (paint or road edge); false: reject
  BoundaryKind kind = BoundaryKind::kPaint;
  const char* reason = "";      ///< static text: why it was classified so (debugging, overlays)
  int rows = 0;                 ///< rows whose profile was measured
  int ridge_rows = 0;           ///< of those, rows where the line is a bright band
  float ridge_contrast = kNaN;  ///< grey levels the line is brighter than the brighter side
  float step_contrast = kNaN;   ///< grey levels the outer side is brighter than the inner one
  float chroma_step = kNaN;     ///< rg-chromaticity distance between the two sides (0 where the
                                ///< darker side is bluer: a shadow's edge)
  float width = kNaN;           ///< width of the bright band (m), where resolved
  int paint_rows = 0;           ///< rows with a band of paint width near the trace
  int narrow_rows = 0;          ///< rows whose nearest band is narrower than paint
  int wide_rows = 0;            ///< rows whose nearest band is wider than paint
  float shift = 0.0f;           ///< the paint's offset from the traced line (m, image right)
  float line_height = kNaN;     ///< the line's depth above the road (m)
  float inner_height = kNaN;    ///< the surface on the vehicle's side of it, above the road (m)
  float outer_height = kNaN;    ///< the surface beyond it, above the road (m)
  float step_height = kNaN;     ///< the surface beyond it above the one on the vehicle's side, in
                                ///< most rows (m; NaN: no consistent step)
  float margin = 0.0f;          ///< in [0, 1]: how clearly the measurements support the kind
  bool raised = false;          ///< a height step: the surface beyond the line, or the line
                                ///< itself, stands a kerb's height above the road beside it

  /// Narrower than paint on at least half of its measured rows (rounded down): a rail head, a
  /// worn dash's core, a rim, or a line that no depth measures.
  bool narrowLine() const { return narrow_rows >= rows / 2; }
};

/**
 * @brief Classifies traced lines as paint, road edge or no boundary from the colour profile
 * across each traced point (BandProfile) and the depth beside it: the decision; the row walks
 * that put a line on its paint or edge are LineFollower's. Reuses its buffers (no allocation in
 * steady state).
 */
class BoundaryClassifier {
 public:
  /// m either side of a traced line's column where followLine() seeks its paint by default
  static constexpr double kTraceReach = LineFollower::kTraceReach;
  /// Pixels of a line the per-line buffers are reserved for (they grow past them once, on a
  /// taller image).
  static constexpr size_t kReservedPixels = LineFollower::kReservedPixels;
  BoundaryClassifier();

  /**
   * @brief Classify one traced line.
   * @param[in] in frame views.
   * @param[in,out] pixels traced centroids (input pixels), near to far; moved onto the paint
   *                when a painted band runs beside the traced line.
   * @param[in] left true for a line left of the vehicle (its outer side is to the left).
   * @param[in] p thresholds (paint_contrast, paint_width_min/max, kerb_height, edge_chroma).
   * @param[out] ev measurements and verdict.
   * @param[in] cut cut the line where it runs into an object first (cutAtObject()); false for a
   *            line cut so already and not moved since (a second cut finds nothing).
   */
  void classify(const ClassifierInput& in, std::vector<cv::Point2f>& pixels, bool left,
                const Params& p, BoundaryEvidence& ev, bool cut = true);

  /**
   * @brief Cut a line where it runs into an object: from the first pixel (near to far) at which
   * the line, or the road beside it on the vehicle's side, reads depth well above the road on two
   * of three measured pixels (a vehicle ahead over the line), when the line lies on the road up
   * to there.
   * @param[in] in frame views.
   * @param[in,out] pixels the line (input pixels), near to far.
   * @param[in] left side of the vehicle the line is on.
   * @param[in] p thresholds (kerb_height).
   * @return true when the line was cut.
   */
  bool cutAtObject(const ClassifierInput& in, std::vector<cv::Point2f>& pixels, bool left,
                   const Params& p);

  /// A bright band much wider than paint just beyond the far end of a painted line (input
  /// pixels, near to far) that narrows to a tip: the line is the shaft of a lane arrow. A tip
  /// tapers on; paint of a line's width running on past kArrowTip beyond the narrowing is the
  /// line itself beyond a wide bright patch (a dash through a patch of sunlight): no head.
  bool arrowHead(const ClassifierInput& in, const std::vector<cv::Point2f>& pixels, const Params& p);

  /**
   * @brief Follow a painted line row by row: on every image row from the bottom of the image
   * (or the road's nearest visible row) to the far end of the line, the centre of the bright band
   * near the line's predicted column (sub-pixel, brightness-weighted over the band at half its
   * contrast), predicted from the trace and then from the last rows found (a straight or gently
   * curving line). The traced centroids of the sliding box sit anywhere on the matched blob;
   * this puts the line on the paint's centre to a fraction of a pixel, and continues it past the
   * trace's ends across dash gaps of up to @p max_gap metres.
   * @param[in] in frame views.
   * @param[in,out] pixels traced centroids (input pixels), near to far; replaced by the rows
   *                found (unchanged when fewer than 3 rows are found).
   * @param[out] points their depth points (optical frame, NaN where no depth).
   * @param[in] p thresholds (paint_contrast, paint_width_max).
   * @param[in] max_gap longest gap between painted stretches that is crossed (m).
   * @param[in] max_range farthest road distance followed (m).
   * @param[in] reach the band is sought this far either side of the predicted column (m).
   * @param[in] painted the line is paint (classified so): beyond the trace only its rows of
   *            paint-like width predict the rows ahead (a seam's rim or a noise peak beside it
   *            does not steer it off its paint); otherwise every row found does (a narrow line).
   * @param[in] seed_line the trace is the straight line through a seed: below it (toward the
   *            car) it continues until the rows found there form a stretch of paint (rows found
   *            one at a time, grains or texture beside a worn dash's end, do not turn it).
   * @return rows found.
   */
  int followLine(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                 std::vector<Eigen::Vector3f>& points, const Params& p, double max_gap,
                 double max_range, double reach = kTraceReach, bool painted = false,
                 bool seed_line = false);

  /**
   * @brief A double line (two painted lines side by side, 0.1-0.2 m apart) is one boundary at
   * its centre: on the rows of a followed line where the gap is resolved, a second band of paint
   * is sought 0.2-0.35 m to either side; when one side shows it on most rows (and the other
   * side does not), every pixel moves onto the pair's centre.
   * @param[in] in frame views.
   * @param[in,out] pixels the followed line (input pixels), near to far.
   * @param[out] points their depth points (re-read where the pixels moved).
   * @param[in] p thresholds (paint_contrast, paint_width_max).
   * @return true when the line was a double line and was moved.
   */
  bool centreDoubleLine(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                        std::vector<Eigen::Vector3f>& points, const Params& p);

  /**
   * @brief Follow a road edge row by row (kerb, unpainted asphalt edge) as followLine() follows
   * paint: on every image row, scanning outward from the road well inside the edge's predicted
   * column, the first stretch of 12 cm that is mostly not road (brighter by the paint contrast,
   * or of another colour by edge_chroma; darker alone is a shadow, not an edge). A kerb is
   * traced on its bright top; its edge is the bottom of its face, where the road ends.
   * @param[in] in frame views.
   * @param[in,out] pixels traced centroids (input pixels), near to far; replaced by the rows
   *                found (unchanged when fewer than 3 rows are found).
   * @param[out] points their depth points (optical frame, NaN where no depth).
   * @param[in] left side of the vehicle the edge is on (its outer side is to the left).
   * @param[in] p thresholds (paint_contrast, edge_chroma).
   * @param[in] max_gap longest stretch without the edge that is crossed (m).
   * @param[in] max_range farthest road distance followed (m).
   * @param[in] reach on the rows the @p pixels give, the scan starts this far inside them (m):
   *            a traced kerb may lie on its top, well beyond the edge; an edge found in the
   *            depth is near it.
   * @return rows found.
   */
  int followEdge(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                 std::vector<Eigen::Vector3f>& points, bool left, const Params& p, double max_gap,
                 double max_range, double reach = 0.7);

  /**
   * @brief Paint along a reported boundary: the share of its length with paint on it (a solid
   * line about 1, a dashed one its dash / period) and how yellow that paint is.
   * @param[in] in frame views.
   * @param[in] pixels the boundary's points (input pixels), near to far.
   * @param[in] left side of the vehicle it is on.
   * @param[in] p thresholds (paint_contrast, paint_width_min/max).
   * @param[out] coverage share of the measured length with paint, -1 when less than 3 m of it
   *             could be measured (a row without paint whose two sides differ by a shadow's
   *             ratio, where paint in the shade may not stand out, is not measured).
   * @param[out] yellowness 1 - B'/((R' + G') / 2) of the paint's colour relative to the road
   *             beside it (white about 0, yellow 0.3 and more; the median of its rows of paint
   *             width, or with fewer than 3 of them also of its worn, narrower rows), -1 with
   *             fewer than 3 rows.
   */
  void measurePaint(const ClassifierInput& in, const std::vector<cv::Point2f>& pixels, bool left,
                    const Params& p, float& coverage, float& yellowness);

 private:
  BandProfile profile_;
  LineFollower follower_;
  std::vector<float> ridge_, step_, chroma_, width_, line_h_, inner_h_, outer_h_, shift_;
  std::vector<float> yellow_;       ///< measurePaint(): yellowness per row of paint width
  std::vector<float> yellow_worn_;  ///< ... per row where the paint is worn narrower
  std::vector<float> row_grey_;  ///< arrowHead(): grey values of a row
  std::vector<signed char> object_;  ///< cutAtObject(): per pixel 1 object, 0 road, 2 off, -1 none
  std::vector<float> pair_step_, pair_raise_;  ///< classify(): per-row outer - inner, line - inner
  std::vector<float> far_step_;  ///< classify(): the outer side's step at kHeightFar, per row
};

}  // namespace rgbd_lane_detector
