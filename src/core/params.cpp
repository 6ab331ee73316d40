#include "rgbd_lane_detector/params.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace rgbd_lane_detector {
namespace {

double clampFinite(double v, double lo, double hi, double fallback) {
  if (!std::isfinite(v)) return fallback;
  return std::min(std::max(v, lo), hi);
}

// A field into its params.def range: numbers clamped (non-finite: the fallback), enums outside
// their values set to the fallback, booleans unchanged.
void clampField(double& v, double lo, double hi, double fallback) {
  v = clampFinite(v, lo, hi, fallback);
}
void clampField(int& v, double lo, double hi, int /*fallback*/) {
  v = std::min(std::max(v, static_cast<int>(lo)), static_cast<int>(hi));
}
void clampField(bool& /*v*/, bool /*lo*/, bool /*hi*/, bool /*fallback*/) {}
template <typename E, typename = std::enable_if_t<std::is_enum_v<E>>>
void clampField(E& v, int lo, int hi, E fallback) {
  const int i = static_cast<int>(v);
  if (i < lo || i > hi) v = fallback;
}

// params.h's enumerators carry the values of param_enums.def, the table of their names
#define RLD_ENUM(type, enumerator, name, value, description) \
  static_assert(static_cast<int>(type::enumerator) == (value), #type "::" #enumerator);
#include "rgbd_lane_detector/param_enums.def"
#undef RLD_ENUM

}  // namespace

Params Params::paper() {
  Params p;
#define RLD_PARAM(group, type, name, improved, paper, min, max, level, description) \
  p.name = static_cast<type>(paper);
#include "rgbd_lane_detector/params.def"
#undef RLD_PARAM
  return p;
}

bool paramsForMode(const std::string& mode, Params& params) {
  if (mode == "improved") {
    params = Params::improved();
  } else if (mode == "paper") {
    params = Params::paper();
  } else {
    return false;
  }
  return true;
}

Params sanitize(const Params& in) {
  const Params d;  // defaults, used for non-finite input
  Params p = in;
  // the up axis: a unit vector (each component then lies in its range)
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
  // every field into its own range
#define RLD_PARAM(group, type, name, improved, paper, min, max, level, description) \
  clampField(p.name, min, max, d.name);
#include "rgbd_lane_detector/params.def"
#undef RLD_PARAM
  // then the rules between fields
  if (p.roi_bottom <= p.roi_top) p.roi_bottom = std::min(1.0, p.roi_top + 0.05);
  p.max_depth = std::max(p.max_depth, p.min_depth + 1e-3);
  if (p.normal_window % 2 == 0) p.normal_window += 1;  // FALS window: odd, 3..7
  p.template_line_width = std::min(p.template_line_width, p.template_size);
  p.plane_distance_max = std::max(p.plane_distance_max, p.plane_distance_min);
  p.marker_angle_max_deg = std::max(p.marker_angle_max_deg, p.marker_angle_min_deg);
  // an acquisition template flatter than the smallest template angle: the smallest
  if (p.acquisition_angle_deg > 0.0 && p.acquisition_angle_deg < 5.0) p.acquisition_angle_deg = 5.0;
  p.paint_width_max = std::max(p.paint_width_max, p.paint_width_min);
  p.boundary_offset_max = std::max(p.boundary_offset_max, p.boundary_offset_min);
  if (p.lane_width_max > 0.0) p.lane_width_max = std::max(p.lane_width_max, p.lane_width_min);
  return p;
}

bool sameTemplates(const Params& a, const Params& b) {
  return a.template_size == b.template_size && a.template_line_width == b.template_line_width &&
         a.template_angle_deg == b.template_angle_deg &&
         a.acquisition_angle_deg == b.acquisition_angle_deg;
}

}  // namespace rgbd_lane_detector
