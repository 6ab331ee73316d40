/**
 * @file scoring.h
 * @brief Per-frame detection scoring (Table 1 style), METHOD.md section 6 generalised to
 * boundaries reported side by side with a kind (paint / road edge). ROS-free.
 *
 * **A side** (left or right of the ego lane) is scored against the frame's true ego boundary of
 * that side (FrameTruth::egoSide()):
 * - *correct*: reported (MarkerTrace::found), at least 5 finite points of which >= 80% lie
 *   within 0.30 m of the true line of that side, measured laterally in the true road plane (the
 *   point projected onto the plane, distance to the line's polyline; beyond its ends, to the
 *   end segments' extensions), AND the reported kind equals the true kind;
 * - *wrong*: reported, and off the line (fewer points or fewer inliers), or with the wrong kind
 *   (a kerb reported as paint), or where the truth has no boundary;
 * - *missed*: not reported although the truth has a boundary; *none*: neither.
 *
 * **A frame** (outcome):
 * - *TP*: at least one side reported, a valid plane whose normal is within 3 deg of the truth
 *   and points toward the camera, whose offset is within 0.15 m, every true ego side correct and
 *   nothing wrong;
 * - *FP* (wrong): a reported side is wrong, or a side is reported with a missing or wrong plane;
 * - *partial*: something reported, nothing wrong, not TP (one side found, the other missed);
 * - *miss*: no side reported.
 * A valid plane alone is not a lane report (the road surface is published whenever the road is
 * visible): it makes no frame FP or TP and is scored on its own (plane error columns).
 *
 * **Frames that require a lane**: the ego lane has a boundary (FrameTruth::has_lane) and the
 * frame is not flagged lane_optional (an intersection where the ego lines end). TP %, partial %
 * and miss % are over the frames that require a lane; FP % is over all frames (a wrong report
 * counts anywhere; in frames that need no lane, nothing or a correct report is fine). For a
 * sequence where every frame requires a lane, TP + partial + FP + miss = 100%, and METHOD.md's
 * classic FP ("reported and not TP") is partial + FP.
 *
 * **Per side** over a sequence: precision = correct sides / reported sides (all frames);
 * recall = correct sides / true sides (frames that require a lane); kind confusion = reported
 * kind against true kind (paint reported on a road edge, road edge on paint, either where the
 * truth has none); lateral error at 5, 10, 20 and 40 m ahead (issue 14, OpenLane-style near /
 * far x error): |y_reported(x) - y_true(x)| in base_link, both lines interpolated linearly
 * between their points, over every reported side with a true boundary that spans that x.
 */
#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rgbd_lane_detector/types.h"
#include "rgbd_lane_detector_tools/ground_truth.h"

namespace rgbd_lane_detector {
namespace tools {

/// Forward distances (m, base_link x) of the lateral errors.
constexpr int kNumLateralDistances = 4;
constexpr double kLateralDistances[kNumLateralDistances] = {5.0, 10.0, 20.0, 40.0};

/// Thresholds of the rules (METHOD.md section 6 values by default).
struct ScoringRules {
  double max_angle_deg = 3.0;
  double max_offset = 0.15;
  int min_points = 5;
  double min_inlier_fraction = 0.8;
  double max_lateral = 0.30;
};

/// A detection in plain form (from a Result, or made by hand in tests).
struct Detection {
  bool plane_valid = false;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double distance = 0.0;
  bool left_reported = false;  ///< the detector reports this side (MarkerTrace::found)
  bool right_reported = false;
  BoundaryKind left_kind = BoundaryKind::kPaint;  ///< MarkerTrace::kind of a reported side
  BoundaryKind right_kind = BoundaryKind::kPaint;
  double left_confidence = 0.0;  ///< MarkerTrace::confidence
  double right_confidence = 0.0;
  std::vector<Eigen::Vector3d> left;  ///< 3D points (non-finite entries are ignored)
  std::vector<Eigen::Vector3d> right;
};

/// Plain detection of a detector result (sides as reported by MarkerTrace::found).
Detection detectionFromResult(const Result& result);

/// Frame outcome.
enum class Outcome { kTruePositive, kPartial, kWrong, kMiss };
const char* outcomeName(Outcome o);  ///< "TP", "partial", "FP", "miss"

/// How one side fared.
enum class SideOutcome {
  kNone,       ///< no true boundary, nothing reported
  kCorrect,    ///< reported on the true line with the true kind
  kWrongKind,  ///< on the true line, wrong kind (a kerb reported as paint)
  kOffLine,    ///< reported, not on the true line (too few points or inliers)
  kSpurious,   ///< reported where the truth has no boundary
  kMissed,     ///< true boundary, not reported
};
const char* sideOutcomeName(SideOutcome o);  ///< "none", "correct", "wrong_kind", ...

/// Score of one side.
struct SideScore {
  bool truth = false;  ///< the frame has a true boundary on this side
  BoundaryKind true_kind = BoundaryKind::kPaint;
  bool reported = false;
  BoundaryKind reported_kind = BoundaryKind::kPaint;
  double confidence = 0.0;
  int points = 0;             ///< finite reported points
  int inliers = 0;            ///< of those, within max_lateral of the true line
  double mean_lateral = 0.0;  ///< mean lateral distance of the finite points (m), NaN if none
  bool on_line = false;       ///< >= min_points with >= min_inlier_fraction inliers
  SideOutcome outcome = SideOutcome::kNone;
  /// lateralErrorAt() at kLateralDistances (NaN where not measured)
  double lateral_error[kNumLateralDistances];
  bool correct() const { return outcome == SideOutcome::kCorrect; }
  bool wrong() const {
    return outcome == SideOutcome::kWrongKind || outcome == SideOutcome::kOffLine ||
           outcome == SideOutcome::kSpurious;
  }
};

/// Score of one frame.
struct FrameScore {
  Outcome outcome = Outcome::kMiss;
  bool reported = false;       ///< a side was reported (a plane alone is not a report)
  bool lane_required = false;  ///< has_lane and not lane_optional
  bool plane_valid = false;
  double angle_error_deg = 0.0;  ///< NaN without a valid plane
  double offset_error = 0.0;     ///< |d_est - d_true| (m), NaN without a valid plane
  bool plane_ok = false;
  SideScore left, right;
};

/**
 * @brief Lateral distance in the road plane from a point to a line.
 * @param[in] p point (camera optical frame).
 * @param[in] line the line (polyline on the plane), near to far (at least one point).
 * @param[in] normal,distance the true road plane.
 * @return distance (m); +inf for an empty line.
 */
double lateralDistance(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& line,
                       const Eigen::Vector3d& normal, double distance);

/// A line as y(x) in base_link (x forward, y left): its points sorted by x, linear between them.
class LateralLine {
 public:
  LateralLine() = default;
  /// The finite points of @p points (optical frame) mapped by @p base_from_optical.
  LateralLine(const std::vector<Eigen::Vector3d>& points,
              const Eigen::Isometry3d& base_from_optical);
  /// @p points already in base_link; two points more than @p max_gap apart in x leave a gap
  /// (a line interrupted by an intersection).
  explicit LateralLine(const std::vector<Eigen::Vector3d>& points_base,
                       double max_gap = std::numeric_limits<double>::infinity());
  bool empty() const { return xy_.size() < 2; }
  double xMin() const { return xy_.empty() ? 0.0 : xy_.front().x(); }
  double xMax() const { return xy_.empty() ? 0.0 : xy_.back().x(); }
  /// Length in x over which the line exists (gaps excluded).
  double length() const;
  /// y at @p x; NaN outside [xMin(), xMax()] (no extrapolation), in a gap or for an empty line.
  double at(double x) const;

 private:
  void sort();
  std::vector<Eigen::Vector2d> xy_;
  double max_gap_ = std::numeric_limits<double>::infinity();
};

/**
 * @brief Lateral error of a side's points at forward distance @p x in base_link (the frame's
 * base_to_camera): |y_points(x) - y_truth(x)|, both polylines interpolated linearly along x.
 * @return NaN when either does not reach @p x (no extrapolation), or without a vehicle frame.
 */
double lateralErrorAt(const std::vector<Eigen::Vector3d>& points, const TrueBoundary& truth,
                      const FrameTruth& frame, double x);

/**
 * @brief Score one side.
 * @param[in] points the side's reported points (ignored unless @p reported).
 * @param[in] reported,kind,confidence how the detector reported it.
 * @param[in] truth the true boundary of this side, nullptr when there is none.
 * @param[in] frame the frame's truth (its plane measures the lateral distance).
 */
SideScore scoreSide(const std::vector<Eigen::Vector3d>& points, bool reported, BoundaryKind kind,
                    double confidence, const TrueBoundary* truth, const FrameTruth& frame,
                    const ScoringRules& rules = ScoringRules());

/// Score one frame (the rules of the file comment).
FrameScore scoreFrame(const Detection& detection, const FrameTruth& truth,
                      const ScoringRules& rules = ScoringRules());

/// Percentile @p q (0-100, nearest rank) of @p values (NaN when empty).
double percentile(std::vector<double> values, double q);

/// Running totals over a sequence (one Table 1 row and its per-side statistics).
struct ScoreSummary {
  int frames = 0;
  int required = 0;  ///< frames that require a lane
  int tp = 0, partial = 0, miss = 0;  ///< over the frames that require a lane
  int wrong = 0;                      ///< over all frames
  int plane_frames = 0;               ///< frames with a valid plane
  int plane_ok = 0;                   ///< of those, within 3 deg / 0.15 m
  double sum_angle_error = 0.0;       ///< over plane_frames
  double sum_offset_error = 0.0;
  double sum_ms = 0.0;
  // per side
  int sides_reported = 0, sides_correct = 0;    ///< all frames
  int sides_true = 0, sides_true_correct = 0;   ///< frames that require a lane
  /// confusion[true][reported]: true 0 paint, 1 road edge, 2 none; reported 0 paint, 1 edge
  int confusion[3][2] = {{0, 0}, {0, 0}, {0, 0}};
  /// every measured lateral error per distance (m)
  std::vector<double> lateral_errors[kNumLateralDistances];

  void add(const FrameScore& s, double ms);
  double tpPercent() const { return percent(tp, required); }
  double partialPercent() const { return percent(partial, required); }
  double missPercent() const { return percent(miss, required); }
  double fpPercent() const { return percent(wrong, frames); }  ///< FP = wrong, over all frames
  double planePercent() const { return percent(plane_frames, frames); }
  double planeOkPercent() const { return percent(plane_ok, plane_frames); }  ///< of valid planes
  double meanAngleError() const;   ///< NaN without planes
  double meanOffsetError() const;  ///< NaN without planes
  double meanMs() const { return frames ? sum_ms / frames : 0.0; }
  double sidePrecision() const { return percent(sides_correct, sides_reported); }
  double sideRecall() const { return percent(sides_true_correct, sides_true); }
  /// Percentile @p q (0-100, nearest rank) of the lateral errors at distance index @p k (NaN
  /// when none).
  double lateralPercentile(int k, double q) const;
  /// 100 a / b, NaN when b is 0.
  static double percent(int a, int b);
};

}  // namespace tools
}  // namespace rgbd_lane_detector
