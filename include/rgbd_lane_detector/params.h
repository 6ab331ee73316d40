/**
 * @file params.h
 * @brief Every tunable value of the detector (fields, ranges and presets from params.def).
 *
 * Field names are the dynamic_reconfigure parameter names of cfg/LaneDetector.cfg, which reads
 * the same table. The ROS-free core reads nothing else.
 */
#pragma once

#include <string>

namespace rgbd_lane_detector {

/// Depth term of the geometric map G (METHOD.md section 2, Eq. 2).
enum class DepthTerm : int {
  kNearHigh = 0,  ///< (T_D - D) / T_D: the authors' code; near rows score higher, like v/H.
  kFarHigh = 1,   ///< D / T_D: as printed in the paper.
};

/// How the lane plane is computed from the traced markers (METHOD.md section 4).
enum class PlaneFit : int {
  kThreePoint = 0,    ///< Paper: plane through the best left match, best right match, furthest right.
  kLeastSquares = 1,  ///< Robust (trimmed) least squares over every traced marker point.
  kRoadSurface = 2,   ///< The road surface from depth, markers or not (RoadSurface).
};

/**
 * @brief Detector configuration: one field per entry of params.def, which gives each field's
 * meaning, range and both presets. A default-constructed Params is the package's recommended
 * (improved) configuration; Params::paper() reproduces Quach et al. and the authors' runs.
 */
struct Params {
#define RLD_PARAM(group, type, name, improved, paper, min, max, level, description) \
  type name = static_cast<type>(improved);
#include "rgbd_lane_detector/params.def"
#undef RLD_PARAM

  /// The paper-faithful configuration (every field at params.def's paper value).
  static Params paper();
  /// The package's recommended configuration: the defaults.
  static Params improved() { return Params(); }
};

/**
 * @brief The preset named @p mode: "improved" (Params::improved()) or "paper" (Params::paper()).
 * @param[in] mode preset name.
 * @param[out] params the preset; unchanged for an unknown name.
 * @return false for an unknown name.
 */
bool paramsForMode(const std::string& mode, Params& params);

/**
 * @brief Clamp and repair a parameter set (odd windows, ranges, ordering), like
 * stereo_image_proc does for its block sizes.
 * @param[in] in parameters as given by a user.
 * @return a valid parameter set; fields already valid are returned unchanged.
 */
Params sanitize(const Params& in);

/// True when two parameter sets give the same matching templates (sizes and default angle).
bool sameTemplates(const Params& a, const Params& b);

}  // namespace rgbd_lane_detector
