#include "rgbd_lane_detector/params.h"

#include <algorithm>
#include <cmath>

namespace rgbd_lane_detector {
namespace {

double clampFinite(double v, double lo, double hi, double fallback) {
  if (!std::isfinite(v)) return fallback;
  return std::min(std::max(v, lo), hi);
}

}  // namespace

Params Params::improved() {
  Params p;
  p.gap_steps = 12;
  p.ego_lane_seeds = true;
  p.road_gate = true;
  p.plane_gate = 0.3;
  p.plane_fit = PlaneFit::kRoadSurface;
  p.plane_max_tilt_deg = 30.0;
  p.plane_distance_min = 0.3;
  p.plane_distance_max = 5.0;
  p.fill_depth_holes = 0;
  p.snap_to_plane = true;
  p.lane_width_min = 0.8;
  p.lane_width_max = 5.5;
  p.report_only_complete = false;
  p.track_lanes = true;
  p.track_seed_band = 24;
  p.marker_angle_min_deg = 20.0;
  p.marker_angle_max_deg = 88.0;
  p.adaptive_tau_c = true;
  p.tau_c_offset = 30;
  p.boundary_candidates = 3;
  p.acquisition_angle_deg = 70.0;
  p.adapt_per_side = true;
  p.classify_boundaries = true;
  p.lane_model = true;
  return p;
}

Params sanitize(const Params& in) {
  const Params d;  // defaults, used for non-finite input
  Params p = in;
  p.tau_c = std::min(std::max(p.tau_c, 0), 255);
  p.processing_scale = clampFinite(p.processing_scale, 0.05, 1.0, d.processing_scale);
  p.roi_top = clampFinite(p.roi_top, 0.0, 0.95, d.roi_top);
  p.roi_bottom = clampFinite(p.roi_bottom, 0.05, 1.0, d.roi_bottom);
  if (p.roi_bottom <= p.roi_top) p.roi_bottom = std::min(1.0, p.roi_top + 0.05);
  p.min_depth = clampFinite(p.min_depth, 0.0, 1e3, d.min_depth);
  p.max_depth = clampFinite(p.max_depth, p.min_depth + 1e-3, 1e6, d.max_depth);
  // FALS window: odd, 3..7
  p.normal_window = std::min(std::max(p.normal_window, 3), 7);
  if (p.normal_window % 2 == 0) p.normal_window += 1;

  p.template_size = std::min(std::max(p.template_size, 4), 256);
  p.template_line_width = std::min(std::max(p.template_line_width, 1), p.template_size);
  p.template_angle_deg = clampFinite(p.template_angle_deg, 5.0, 85.0, d.template_angle_deg);
  p.depth_threshold = clampFinite(p.depth_threshold, 1e-3, 1e6, d.depth_threshold);
  p.alpha = clampFinite(p.alpha, 0.0, 10.0, d.alpha);
  p.beta = clampFinite(p.beta, 0.0, 10.0, d.beta);
  if (p.depth_term != DepthTerm::kNearHigh && p.depth_term != DepthTerm::kFarHigh)
    p.depth_term = d.depth_term;
  p.tau_g = clampFinite(p.tau_g, 0.0, 1.0, d.tau_g);
  const double up_norm = std::sqrt(p.up_x * p.up_x + p.up_y * p.up_y + p.up_z * p.up_z);
  if (!std::isfinite(up_norm) || up_norm < 1e-9) {
    p.up_x = d.up_x;
    p.up_y = d.up_y;
    p.up_z = d.up_z;
  } else {
    p.up_x /= up_norm;
    p.up_y /= up_norm;
    p.up_z /= up_norm;
  }

  p.pca_threshold = clampFinite(p.pca_threshold, 0.0, 10.0, d.pca_threshold);
  p.jump_step = std::min(std::max(p.jump_step, 1), 1024);
  p.trace_threshold = clampFinite(p.trace_threshold, 0.0, 10.0, d.trace_threshold);
  p.max_trace_steps = std::min(std::max(p.max_trace_steps, 1), 100000);
  p.min_marker_points = std::min(std::max(p.min_marker_points, 1), 100000);
  if (p.plane_fit != PlaneFit::kThreePoint && p.plane_fit != PlaneFit::kLeastSquares &&
      p.plane_fit != PlaneFit::kRoadSurface)
    p.plane_fit = d.plane_fit;
  p.road_fit_range = clampFinite(p.road_fit_range, 2.0, 200.0, d.road_fit_range);
  p.road_inlier_distance = clampFinite(p.road_inlier_distance, 0.005, 1.0, d.road_inlier_distance);
  p.road_noise_growth = clampFinite(p.road_noise_growth, 0.0, 0.1, d.road_noise_growth);
  p.plane_max_tilt_deg = clampFinite(p.plane_max_tilt_deg, 0.1, 90.0, d.plane_max_tilt_deg);
  p.plane_distance_min = clampFinite(p.plane_distance_min, 0.0, 1e3, d.plane_distance_min);
  p.plane_distance_max =
      clampFinite(p.plane_distance_max, p.plane_distance_min, 1e6, d.plane_distance_max);
  p.lane_width_min = clampFinite(p.lane_width_min, 0.0, 100.0, d.lane_width_min);
  p.lane_width_max = clampFinite(p.lane_width_max, 0.0, 100.0, d.lane_width_max);
  p.track_memory = clampFinite(p.track_memory, 0.0, 0.99, d.track_memory);
  p.track_max_age = std::min(std::max(p.track_max_age, 0), 10000);
  p.track_gate = clampFinite(p.track_gate, 0.01, 100.0, d.track_gate);
  p.track_seed_band = std::min(std::max(p.track_seed_band, 0), 10000);
  p.tau_c_offset = std::min(std::max(p.tau_c_offset, -255), 255);
  p.marker_angle_min_deg = clampFinite(p.marker_angle_min_deg, 0.0, 90.0, d.marker_angle_min_deg);
  p.marker_angle_max_deg =
      clampFinite(p.marker_angle_max_deg, p.marker_angle_min_deg, 90.0, d.marker_angle_max_deg);

  p.gap_steps = std::min(std::max(p.gap_steps, 0), 10000);
  p.road_gate_cos = clampFinite(p.road_gate_cos, 0.0, 1.0, d.road_gate_cos);
  p.plane_gate = clampFinite(p.plane_gate, 0.0, 1e3, d.plane_gate);
  p.fill_depth_holes = std::min(std::max(p.fill_depth_holes, 0), 10000);
  p.plane_smoothing = clampFinite(p.plane_smoothing, 0.0, 0.99, d.plane_smoothing);

  p.boundary_candidates = std::min(std::max(p.boundary_candidates, 1), 8);
  p.acquisition_angle_deg = clampFinite(p.acquisition_angle_deg, 0.0, 85.0, d.acquisition_angle_deg);
  if (p.acquisition_angle_deg > 0.0 && p.acquisition_angle_deg < 5.0) p.acquisition_angle_deg = 5.0;
  p.paint_contrast = clampFinite(p.paint_contrast, 0.0, 5.0, d.paint_contrast);
  p.paint_width_min = clampFinite(p.paint_width_min, 0.0, 2.0, d.paint_width_min);
  p.paint_width_max = clampFinite(p.paint_width_max, p.paint_width_min, 5.0, d.paint_width_max);
  p.kerb_height = clampFinite(p.kerb_height, 0.005, 1.0, d.kerb_height);
  p.edge_chroma = clampFinite(p.edge_chroma, 0.0, 1.0, d.edge_chroma);
  p.boundary_offset_min = clampFinite(p.boundary_offset_min, 0.0, 10.0, d.boundary_offset_min);
  p.boundary_offset_max =
      clampFinite(p.boundary_offset_max, p.boundary_offset_min, 20.0, d.boundary_offset_max);
  p.model_gate = clampFinite(p.model_gate, 0.05, 5.0, d.model_gate);
  p.model_lost_frames = std::min(std::max(p.model_lost_frames, 0), 1000);
  p.dashed_coverage = clampFinite(p.dashed_coverage, 0.0, 1.0, d.dashed_coverage);
  p.yellow_threshold = clampFinite(p.yellow_threshold, 0.0, 1.0, d.yellow_threshold);
  return p;
}

bool sameTemplates(const Params& a, const Params& b) {
  return a.template_size == b.template_size && a.template_line_width == b.template_line_width &&
         a.template_angle_deg == b.template_angle_deg &&
         a.acquisition_angle_deg == b.acquisition_angle_deg;
}

}  // namespace rgbd_lane_detector
