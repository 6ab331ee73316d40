/**
 * @file params.h
 * @brief Every tunable value of the detector, with the paper's values as defaults.
 *
 * Field names are the dynamic_reconfigure parameter names of cfg/LaneDetector.cfg.
 * The ROS-free core reads nothing else.
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
 * @brief Detector configuration. Defaults reproduce the paper (Quach et al.) and the
 * authors' runs; the "improvement" block defaults to off (paper-faithful mode).
 */
struct Params {
  // --- Pre-processing -------------------------------------------------------
  int tau_c = 100;                ///< half-binary threshold on 0-255 grey (THRESH_TOZERO)
  bool adaptive_tau_c = false;    ///< per-row threshold: the row's median grey + tau_c_offset
  int tau_c_offset = 30;          ///< offset of the adaptive threshold above the row median
  double processing_scale = 1.0;  ///< input is resampled (nearest) by this factor before matching
  double roi_top = 0.41;          ///< first searched row as a fraction of the height (156/380)
  double roi_bottom = 1.0;        ///< one past the last searched row, fraction of the height
  double min_depth = 0.2;         ///< depth below this (m) is invalid
  double max_depth = 120.0;       ///< depth above this (m) is invalid ("huge" depth)
  int normal_window = 5;          ///< FALS window side: 3, 5 or 7

  // --- Response map ---------------------------------------------------------
  int template_size = 32;           ///< square template side (px, at processing scale)
  int template_line_width = 10;     ///< thickness of the template line (px)
  double template_angle_deg = 45.0; ///< default template line angle from the horizontal (deg)
  bool use_depth = true;            ///< false: colour-only ablation (G = 0)
  double depth_threshold = 20.0;    ///< T_D (m)
  double alpha = 0.4;               ///< weight of |n . O_y| in G
  double beta = 0.1;                ///< weight of the depth / row term in G
  DepthTerm depth_term = DepthTerm::kNearHigh;
  double tau_g = 0.5;               ///< G is added where M >= tau_g
  double up_x = 0.0;                ///< road "up" axis O_y in the camera optical frame
  double up_y = -1.0;
  double up_z = 0.0;

  // --- Template enhancement and tracing -------------------------------------
  double pca_threshold = 0.75;   ///< P_PCA: region growing threshold on R, and the adapt condition
  bool adapt_templates = true;   ///< redraw templates at the PCA angle for the next frame
  int jump_step = 5;             ///< r: sliding box step along theta (px)
  double trace_threshold = 0.75; ///< R above this counts as marker inside the sliding box
  int max_trace_steps = 400;     ///< safety bound on sliding-box steps per direction
  int min_marker_points = 5;     ///< fewer traced points: the side is not reported

  // --- Lane plane -----------------------------------------------------------
  PlaneFit plane_fit = PlaneFit::kThreePoint;
  double road_fit_range = 20.0;      ///< road_surface: depth up to this far ahead fits the plane (m)
  double road_inlier_distance = 0.04;  ///< road_surface: inlier band at the camera (m)
  double road_noise_growth = 0.0015;   ///< road_surface: the band grows by this times z^2 (1/m)
  double plane_max_tilt_deg = 90.0;  ///< reject planes tilted more than this from O_y (90: off)
  double plane_distance_min = 0.0;   ///< reject planes closer to the camera than this (m)
  double plane_distance_max = 1e3;   ///< reject planes farther from the camera than this (m)

  // --- Improvements over the paper (named options; all off = paper-faithful) --
  int gap_steps = 0;              ///< sliding box may cross this many empty boxes (dashed lines)
  double marker_angle_min_deg = 0.0;   ///< seeds whose marker is flatter than this are not traced
  double marker_angle_max_deg = 90.0;  ///< seeds whose marker is steeper than this are not traced
  bool ego_lane_seeds = false;    ///< left seed left of the principal point, right seed right of it
  bool road_gate = false;         ///< seeds and traced points need a road-like normal (|n.O_y| >= road_gate_cos) where depth gives one
  double road_gate_cos = 0.9;     ///< cosine threshold of road_gate
  double plane_gate = 0.0;        ///< >0: ignore matches and points farther than this (m) from the previous plane
  int fill_depth_holes = 0;       ///< >0: fill invalid depth from valid neighbours along rows up to this many px
  double plane_smoothing = 0.0;   ///< temporal filter weight of the previous plane in [0, 1)
  bool snap_to_plane = false;     ///< marker points = their pixel rays met with the lane plane
  double lane_width_min = 0.0;    ///< with lane_width_max > 0: reject lanes narrower than this (m)
  double lane_width_max = 0.0;    ///< reject lanes wider than this (m); 0: no check
  bool report_only_complete = false;  ///< report markers only together with a valid plane
  bool track_lanes = false;       ///< temporal lane model in the road plane (implies least squares)
  double track_memory = 0.7;      ///< forgetting factor per frame of the lane model
  int track_max_age = 10;         ///< frames a side survives without evidence
  double track_gate = 0.5;        ///< measurements farther than this from the model are outliers (m)
  int track_seed_band = 0;        ///< >0: seek each seed within this many px of its predicted marker

  // --- Boundaries on real streets (named options; off in the paper mode) -----
  int boundary_candidates = 1;    ///< lines traced per side; the nearest lane boundary among them is kept
  double acquisition_angle_deg = 0.0;  ///< >0: a side without a tracked boundary is also sought with templates at this angle (deg)
  bool adapt_per_side = false;    ///< each side's template follows its own PCA angle (paper: both sides or neither)
  bool classify_boundaries = false;  ///< classify each line as paint, road edge or no boundary
  double paint_contrast = 0.25;   ///< paint is this much brighter than the road beside it (relative)
  double paint_width_min = 0.07;  ///< narrower bright lines are not paint (rail heads) (m)
  double paint_width_max = 0.35;  ///< wider bright bands are not lane lines (zebra stripes 0.4-0.6 m, arrows) (m)
  double kerb_height = 0.05;      ///< a raised surface beyond a line by this much makes it a road edge (m)
  double edge_chroma = 0.03;      ///< rg-chromaticity change across an unpainted road edge
  double boundary_offset_min = 0.15;  ///< a boundary is at least this far beside the camera (m)
  double boundary_offset_max = 4.5;   ///< ... and at most this far (m)

  // --- Lane model for planners (named options; off in the paper mode) --------
  bool lane_model = false;        ///< track the lane model (typed boundaries, width, offset, heading, curvature)
  double model_gate = 0.5;        ///< m: boundaries farther than this from the model are not its
  int model_lost_frames = 10;     ///< frames without an ego boundary before the model is reset
  double dashed_coverage = 0.7;   ///< a paint line painted over less of its length than this is dashed
  double yellow_threshold = 0.25; ///< paint more yellow than this (1 - B'/((R'+G')/2) against the road) is yellow

  /// Paper-faithful configuration (the defaults).
  static Params paper() { return Params(); }
  /// The package's recommended configuration: paper plus the improvements that measured better.
  static Params improved();
};

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
