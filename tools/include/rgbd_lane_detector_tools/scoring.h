/**
 * @file scoring.h
 * @brief Per-frame detection scoring of METHOD.md section 6 (Table 1 style), ROS-free.
 *
 * - TP: a valid plane whose normal is within 3 deg of the truth and points toward the camera
 *   (n_est . n_true > 0, d_est > 0), whose offset is within 0.15 m, and, for EACH side, at
 *   least 5 finite marker points of which >= 80% lie within 0.30 m of that side's true centre
 *   line, measured laterally in the road plane (point projected onto the true plane, distance
 *   to the centre line polyline; beyond the polyline's ends, to its end segments' extensions).
 * - FP: a lane was reported (valid plane, or marker points on a reported side) and the frame
 *   is not TP. Without markings (has_lane false) every report is an FP.
 * - Miss: nothing reported. TP + FP + miss = all frames.
 */
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "rgbd_lane_detector/types.h"
#include "rgbd_lane_detector_tools/ground_truth.h"

namespace rgbd_lane_detector {
namespace tools {

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
  std::vector<Eigen::Vector3d> left;  ///< 3D marker points (non-finite entries are ignored)
  std::vector<Eigen::Vector3d> right;
};

/// Plain detection of a detector result (sides as reported by MarkerTrace::found).
Detection detectionFromResult(const Result& result);

enum class Outcome { kTruePositive, kFalsePositive, kMiss };
const char* outcomeName(Outcome o);  ///< "TP", "FP", "miss"

/// How one side fared.
struct SideScore {
  int points = 0;             ///< finite marker points
  int inliers = 0;            ///< of those, within max_lateral of the true line
  double mean_lateral = 0.0;  ///< mean lateral distance of the finite points (m), NaN if none
  bool ok = false;
};

/// Score of one frame.
struct FrameScore {
  Outcome outcome = Outcome::kMiss;
  bool reported = false;
  bool plane_valid = false;
  double angle_error_deg = 0.0;  ///< NaN without a valid plane
  double offset_error = 0.0;     ///< |d_est - d_true| (m), NaN without a valid plane
  bool plane_ok = false;
  SideScore left, right;
};

/**
 * @brief Lateral distance in the road plane from a point to a centre line.
 * @param[in] p point (camera optical frame).
 * @param[in] line centre line on the plane, near to far (at least one point).
 * @param[in] normal,distance the true road plane.
 * @return distance (m); +inf for an empty line.
 */
double lateralDistance(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& line,
                       const Eigen::Vector3d& normal, double distance);

/// Score one side's points against its true line.
SideScore scoreSide(const std::vector<Eigen::Vector3d>& points,
                    const std::vector<Eigen::Vector3d>& line, const FrameTruth& truth,
                    const ScoringRules& rules);

/// Score one frame (METHOD.md section 6).
FrameScore scoreFrame(const Detection& detection, const FrameTruth& truth,
                      const ScoringRules& rules = ScoringRules());

/// Running totals over a sequence (one Table 1 row).
struct ScoreSummary {
  int frames = 0, tp = 0, fp = 0, miss = 0;
  int plane_frames = 0;          ///< frames with a valid plane
  double sum_angle_error = 0.0;  ///< over plane_frames
  double sum_offset_error = 0.0;
  double sum_ms = 0.0;
  void add(const FrameScore& s, double ms);
  double tpPercent() const { return frames ? 100.0 * tp / frames : 0.0; }
  double fpPercent() const { return frames ? 100.0 * fp / frames : 0.0; }
  double missPercent() const { return frames ? 100.0 * miss / frames : 0.0; }
  double meanAngleError() const;   ///< NaN without planes
  double meanOffsetError() const;  ///< NaN without planes
  double meanMs() const { return frames ? sum_ms / frames : 0.0; }
};

}  // namespace tools
}  // namespace rgbd_lane_detector
