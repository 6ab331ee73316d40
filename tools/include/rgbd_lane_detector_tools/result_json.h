/**
 * @file result_json.h
 * @brief One detection result as a single-line JSON object (JSON Lines output of the runner).
 *
 * @code
 * {"frame": 12, "name": "000012", "stamp": 1.2, "status": "ok",
 *  "timings_ms": {"preprocess": .., ..., "total": ..},
 *  "plane": {"valid": true, "normal": [x, y, z], "distance": d, "rms": r, "range": m},
 *  "left": {"found": true, "kind": "paint", "confidence": c, "peak_score": s, "angle": rad,
 *           "angle_valid": true, "seed": [u, v], "valid_points": n,
 *           "pixels": [[u, v], ...], "points": [[x, y, z] | null, ...], "scores": [...]},
 *  "right": {...},
 *  "score": {"outcome": "TP", "lane_required": true, "plane_ok": true, "angle_error_deg": ..,
 *            "offset_error": .., "left": {"truth": "paint", "outcome": "correct", "points": n,
 *            "inliers": n, "mean_lateral": m}, "right": {...}}}   (with ground truth)
 * @endcode
 * Non-finite numbers are written as null.
 */
#pragma once

#include <string>

#include "rgbd_lane_detector/types.h"
#include "rgbd_lane_detector_tools/scoring.h"

namespace rgbd_lane_detector {
namespace tools {

/**
 * @brief Serialise a result.
 * @param[in] frame running frame number; @p name source name; @p stamp seconds.
 * @param[in] score optional score against ground truth (null: no "score" member).
 */
std::string resultToJson(int frame, const std::string& name, double stamp, const Result& result,
                         const FrameScore* score = nullptr);

/// Escape a string for JSON (quotes included).
std::string jsonString(const std::string& s);
/// A number for JSON ("null" when not finite).
std::string jsonNumber(double v);

}  // namespace tools
}  // namespace rgbd_lane_detector
