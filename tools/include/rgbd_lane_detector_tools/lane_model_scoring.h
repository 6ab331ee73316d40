/**
 * @file lane_model_scoring.h
 * @brief Scores of the lane model planners consume (LaneModelEstimate, issue 14) against the
 * frame's true lane model (FrameTruth). ROS-free.
 *
 * Everything is compared in base_link (REP-103: x forward, y left): a reported boundary is the
 * cubic y(x) over [x_min, x_max] (LaneBoundaryModel), a true boundary the polyline
 * TrueBoundary::points_base (every 0.5 m of road from 3 to 60 m ahead), interpolated linearly in
 * x and not extrapolated. Distances are lateral: |y_reported(x) - y_true(x)| at the same x.
 *
 * - **Overlap** of a reported boundary with the true boundary of the same position label
 *   (ego_left, ..., road_edge_right; the truth's labels follow the lane under base_link's
 *   origin, so they switch during a lane change): the reported range intersected with the
 *   truth's range, sampled every LaneModelRules::step.
 * - **Match** (ONCE-3DLanes style, with the label): the mean lateral distance over the overlap
 *   is below LaneModelRules::match_distance (0.30 m) and the overlap covers
 *   min(LaneModelRules::min_overlap, the truth's length, the published length) (to within one
 *   step). The truth is taken where it exists: a step of more than 2 m between its points (an
 *   intersection) is a gap. A boundary reported at a label the frame has no truth for never
 *   matches.
 * - **Correct** (what LaneBoundary::confidence estimates): matched, with the true kind and, for
 *   paint, the true colour.
 * - **F1** per position and over all six: TP = matched reported boundaries, FP = the other
 *   reported ones, FN = true boundaries without a match (every true boundary of the frame,
 *   whether or not the camera can see it).
 * - **Lateral error** at kLateralDistances (5, 10, 20, 40 m) of each reported boundary whose
 *   reported range and truth both contain that x (matched or not).
 * - **Geometry** of a valid model against LaneModelTruth: width, offset, heading, curvature
 *   (absolute differences).
 * - **Kind** (solid, dashed, road_edge; a double solid line is solid) over matched boundaries;
 *   **colour** (white, yellow) over matched boundaries whose truth is paint.
 * - **Worst distance** of a reported boundary: the largest lateral distance over its overlap;
 *   +inf when the frame has no true boundary with its label.
 */
#pragma once

#include <array>
#include <utility>
#include <vector>

#include "rgbd_lane_detector/types.h"
#include "rgbd_lane_detector_tools/ground_truth.h"
#include "rgbd_lane_detector_tools/scoring.h"

namespace rgbd_lane_detector {
namespace tools {

/// Thresholds of the lane-model scores.
struct LaneModelRules {
  double match_distance = 0.30;  ///< m: mean lateral distance of a match (ONCE-3DLanes)
  double min_overlap = 5.0;      ///< m: shortest overlap of a match (or the truth's length)
  double step = 0.5;             ///< m: sampling of the overlap along x
  double worst_limit = 0.5;      ///< m: a published boundary farther than this is counted
};

/// The truth's line kind in the lane model's terms (double solid is solid).
LineKind trueLineKind(const TrueBoundary& b);
/// The truth's paint colour in the lane model's terms (kUnknown for a road edge).
rgbd_lane_detector::LineColour trueLineColour(const TrueBoundary& b);

/// Score of one position (label) of one frame.
struct PositionScore {
  bool reported = false;  ///< the model has a boundary at this position
  bool truth = false;     ///< the frame has a true boundary with this label
  bool matched = false;   ///< see the file comment
  bool correct = false;   ///< matched, with the true kind (and colour, for paint)
  double overlap = 0.0;   ///< m of x where both exist
  double mean_distance;   ///< over the overlap (NaN: no overlap)
  double worst_distance;  ///< over the overlap (NaN: no overlap; +inf: reported, no truth)
  double lateral_error[kNumLateralDistances];  ///< NaN where not measured
  LineKind kind = LineKind::kUnknown, true_kind = LineKind::kUnknown;
  rgbd_lane_detector::LineColour colour = rgbd_lane_detector::LineColour::kUnknown;
  rgbd_lane_detector::LineColour true_colour = rgbd_lane_detector::LineColour::kUnknown;
  float confidence = 0.0f;
  float evidence = 0.0f;   ///< LaneBoundaryModel::evidence (the uncalibrated score)
  int age = 0;             ///< LaneBoundaryModel::age
  float lateral_std = 0.0f;
  double x_min = 0.0, x_max = 0.0;  ///< the published range
  PositionScore();
};

/// Score of one frame's lane model.
struct LaneModelScore {
  bool model_valid = false;  ///< LaneModelEstimate::valid
  bool truth_valid = false;  ///< the frame has a vehicle frame and a true lane model
  /// |estimate - truth| of a valid model on a frame with a true lane (NaN otherwise)
  double width_error, offset_error, heading_error, curvature_error;
  std::array<PositionScore, kNumBoundaryPositions> positions;  ///< indexed by BoundaryPosition
  LaneModelScore();
};

/**
 * @brief Score a frame's lane model.
 * @param[in] model the detector's lane model (Result::lane_model), in base_link.
 * @param[in] truth the frame's truth (format 2: boundaries in base_link and the lane model).
 * @param[in] rules thresholds.
 * @return the scores; nothing is measured without a vehicle frame in @p truth.
 */
LaneModelScore scoreLaneModel(const LaneModelEstimate& model, const FrameTruth& truth,
                              const LaneModelRules& rules = LaneModelRules());

/// One bin of a reliability table: reported boundaries with a confidence in [lo, hi).
struct ReliabilityBin {
  double lo = 0.0, hi = 0.0;
  int count = 0;
  int correct = 0;
  double sum_confidence = 0.0;
  double meanConfidence() const;  ///< NaN when empty
  double fractionCorrect() const;  ///< NaN when empty
};

/// Bin edges of the reliability tables: finer where the confidences of a good model lie.
const std::vector<double>& defaultReliabilityEdges();

/**
 * @brief Reliability table of (confidence, correct) pairs in the bins [edges[i], edges[i+1]) (a
 * confidence of exactly the last edge falls into the last bin; outside the edges: clamped).
 * @param[in] samples (confidence, correct) pairs.
 * @param[in] edges increasing bin edges (at least two).
 */
std::vector<ReliabilityBin> reliabilityTable(const std::vector<std::pair<float, bool>>& samples,
                                             const std::vector<double>& edges =
                                                 defaultReliabilityEdges());

/// Expected calibration error of a reliability table: sum over bins of count / total *
/// |mean confidence - fraction correct| (NaN without samples).
double expectedCalibrationError(const std::vector<ReliabilityBin>& table);

/// Running totals of lane-model scores (a sequence, or several pooled with merge()).
struct LaneModelSummary {
  int frames = 0;        ///< frames scored
  int model_frames = 0;  ///< of those, with a valid model
  std::vector<double> lateral[kNumBoundaryPositions][kNumLateralDistances];
  std::vector<double> width, offset, heading, curvature;  ///< errors of valid models
  std::array<int, kNumBoundaryPositions> tp{}, fp{}, fn{};
  std::array<int, kNumBoundaryPositions> kind_total{}, kind_correct{};
  std::array<int, kNumBoundaryPositions> colour_total{}, colour_correct{};
  /// kind_confusion[true kind][reported kind] over matched boundaries (LineKind values)
  int kind_confusion[4][4] = {};
  std::vector<std::pair<float, bool>> calibration;  ///< (confidence, correct) per reported boundary
  double worst = 0.0;  ///< largest worst_distance of any reported boundary (m)
  int worst_frame = -1;
  int worst_position = -1;
  int frames_beyond_limit = 0;  ///< frames publishing a boundary beyond LaneModelRules::worst_limit
  double worst_limit = LaneModelRules().worst_limit;

  /// Add one frame (its index for the worst distance).
  void add(const LaneModelScore& s, int frame);
  /// Add another summary's samples (the worst frame keeps its own index).
  void merge(const LaneModelSummary& o);
  /// Matched / reported, matched / true, and their harmonic mean over @p positions (NaN when
  /// undefined).
  double precision(const std::vector<int>& positions) const;
  double recall(const std::vector<int>& positions) const;
  double f1(const std::vector<int>& positions) const;
  /// Pooled accuracy (%) of the kinds / colours over @p positions (NaN without samples).
  double kindAccuracy(const std::vector<int>& positions) const;
  double colourAccuracy(const std::vector<int>& positions) const;
  int kindSamples(const std::vector<int>& positions) const;
  int colourSamples(const std::vector<int>& positions) const;
  /// Lateral errors at distance index @p k of the given positions, pooled.
  std::vector<double> lateralErrors(const std::vector<int>& positions, int k) const;
};

/// Every position: 0..kNumBoundaryPositions-1.
std::vector<int> allPositions();
/// ego_left and ego_right.
std::vector<int> egoPositions();

}  // namespace tools
}  // namespace rgbd_lane_detector
