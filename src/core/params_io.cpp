#include "rgbd_lane_detector/params_io.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <type_traits>

namespace rgbd_lane_detector {
namespace {

struct Field {
  std::function<void(Params&, double)> set;
  std::function<double(const Params&)> get;
};

// An integer field from a double: truncated toward zero, saturated at the int range (a cast of
// an out-of-range or NaN double is undefined behaviour); NaN leaves the field unchanged.
// sanitize() then clamps to the field's own range.
bool toInt(double v, int& out) {
  if (std::isnan(v)) return false;
  if (v >= static_cast<double>(std::numeric_limits<int>::max()))
    out = std::numeric_limits<int>::max();
  else if (v <= static_cast<double>(std::numeric_limits<int>::min()))
    out = std::numeric_limits<int>::min();
  else
    out = static_cast<int>(v);
  return true;
}

template <typename T>
Field member(T Params::*m) {
  return {[m](Params& p, double v) {
            if constexpr (std::is_integral_v<T>) {
              int i = 0;
              if (toInt(v, i)) p.*m = static_cast<T>(i);
            } else {
              p.*m = static_cast<T>(v);
            }
          },
          [m](const Params& p) { return static_cast<double>(p.*m); }};
}

Field boolean(bool Params::*m) {
  return {[m](Params& p, double v) { p.*m = v != 0.0; },
          [m](const Params& p) { return p.*m ? 1.0 : 0.0; }};
}

template <typename E>
Field enumeration(E Params::*m) {
  return {[m](Params& p, double v) {
            int i = 0;
            if (toInt(v, i)) p.*m = static_cast<E>(i);
          },
          [m](const Params& p) { return static_cast<double>(static_cast<int>(p.*m)); }};
}

#define RLD_FIELD(kind, name) {#name, kind(&Params::name)}

const std::vector<std::pair<std::string, Field>>& fields() {
  static const std::vector<std::pair<std::string, Field>> table = {
      RLD_FIELD(member, tau_c),
      RLD_FIELD(boolean, adaptive_tau_c),
      RLD_FIELD(member, tau_c_offset),
      RLD_FIELD(member, processing_scale),
      RLD_FIELD(member, roi_top),
      RLD_FIELD(member, roi_bottom),
      RLD_FIELD(member, min_depth),
      RLD_FIELD(member, max_depth),
      RLD_FIELD(member, normal_window),
      RLD_FIELD(member, template_size),
      RLD_FIELD(member, template_line_width),
      RLD_FIELD(member, template_angle_deg),
      RLD_FIELD(boolean, use_depth),
      RLD_FIELD(member, depth_threshold),
      RLD_FIELD(member, alpha),
      RLD_FIELD(member, beta),
      RLD_FIELD(enumeration, depth_term),
      RLD_FIELD(member, tau_g),
      RLD_FIELD(member, up_x),
      RLD_FIELD(member, up_y),
      RLD_FIELD(member, up_z),
      RLD_FIELD(member, pca_threshold),
      RLD_FIELD(boolean, adapt_templates),
      RLD_FIELD(member, jump_step),
      RLD_FIELD(member, trace_threshold),
      RLD_FIELD(member, max_trace_steps),
      RLD_FIELD(member, min_marker_points),
      RLD_FIELD(enumeration, plane_fit),
      RLD_FIELD(member, road_fit_range),
      RLD_FIELD(member, road_inlier_distance),
      RLD_FIELD(member, road_noise_growth),
      RLD_FIELD(member, plane_max_tilt_deg),
      RLD_FIELD(member, plane_distance_min),
      RLD_FIELD(member, plane_distance_max),
      RLD_FIELD(member, gap_steps),
      RLD_FIELD(member, marker_angle_min_deg),
      RLD_FIELD(member, marker_angle_max_deg),
      RLD_FIELD(boolean, ego_lane_seeds),
      RLD_FIELD(boolean, road_gate),
      RLD_FIELD(member, road_gate_cos),
      RLD_FIELD(member, plane_gate),
      RLD_FIELD(member, fill_depth_holes),
      RLD_FIELD(member, plane_smoothing),
      RLD_FIELD(boolean, snap_to_plane),
      RLD_FIELD(member, lane_width_min),
      RLD_FIELD(member, lane_width_max),
      RLD_FIELD(boolean, report_only_complete),
      RLD_FIELD(boolean, track_lanes),
      RLD_FIELD(member, track_memory),
      RLD_FIELD(member, track_max_age),
      RLD_FIELD(member, track_gate),
      RLD_FIELD(member, track_seed_band),
      RLD_FIELD(member, boundary_candidates),
      RLD_FIELD(member, acquisition_angle_deg),
      RLD_FIELD(boolean, adapt_per_side),
      RLD_FIELD(boolean, classify_boundaries),
      RLD_FIELD(member, paint_contrast),
      RLD_FIELD(member, paint_width_min),
      RLD_FIELD(member, paint_width_max),
      RLD_FIELD(member, kerb_height),
      RLD_FIELD(member, edge_chroma),
      RLD_FIELD(member, boundary_offset_min),
      RLD_FIELD(member, boundary_offset_max),
      RLD_FIELD(boolean, lane_model),
      RLD_FIELD(member, model_gate),
      RLD_FIELD(member, model_lost_frames),
      RLD_FIELD(member, dashed_coverage),
      RLD_FIELD(member, yellow_threshold),
  };
  return table;
}

#undef RLD_FIELD

const Field* find(const std::string& name) {
  for (const auto& f : fields())
    if (f.first == name) return &f.second;
  return nullptr;
}

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r\"'");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r\"'");
  return s.substr(a, b - a + 1);
}

bool parseValue(const std::string& text, double& v) {
  static const std::map<std::string, double> words = {
      {"true", 1},  {"True", 1},      {"TRUE", 1},     {"false", 0},       {"False", 0},
      {"FALSE", 0}, {"near_high", 0}, {"far_high", 1}, {"three_point", 0}, {"least_squares", 1},
      {"road_surface", 2}};
  const auto w = words.find(text);
  if (w != words.end()) {
    v = w->second;
    return true;
  }
  char* end = nullptr;
  v = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' && std::isfinite(v);
}

}  // namespace

const std::vector<std::string>& paramNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& f : fields()) n.push_back(f.first);
    return n;
  }();
  return names;
}

bool setParam(Params& p, const std::string& name, double value) {
  const Field* f = find(name);
  if (!f) return false;
  f->set(p, value);
  return true;
}

bool setParamText(Params& p, const std::string& name, const std::string& text,
                  std::string* error) {
  const Field* f = find(name);
  if (!f) {
    if (error) *error = "unknown parameter '" + name + "'";
    return false;
  }
  double v = 0;
  if (!parseValue(trim(text), v)) {
    if (error) *error = "invalid value '" + text + "' for parameter '" + name + "'";
    return false;
  }
  f->set(p, v);
  return true;
}

bool getParam(const Params& p, const std::string& name, double& value) {
  const Field* f = find(name);
  if (!f) return false;
  value = f->get(p);
  return true;
}

bool loadParamsYaml(const std::string& path, Params& p, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    if (error) *error = "cannot open parameter file " + path;
    return false;
  }
  return parseParamsYaml(in, path, p, error);
}

bool parseParamsYaml(std::istream& in, const std::string& path, Params& p, std::string* error) {
  // key/value lines; a mode line selects the preset the other keys apply to, wherever it is
  std::vector<std::pair<std::string, std::string>> entries;
  std::vector<int> line_numbers;
  Params out = p;
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string key = trim(line.substr(0, colon));
    const std::string text = trim(line.substr(colon + 1));
    if (key.empty() || text.empty()) continue;
    if (key == "mode") {
      if (text == "paper") {
        out = Params::paper();
      } else if (text == "improved") {
        out = Params::improved();
      } else {
        if (error) *error = path + ":" + std::to_string(line_no) + ": unknown mode '" + text + "'";
        return false;
      }
      continue;
    }
    entries.emplace_back(key, text);
    line_numbers.push_back(line_no);
  }
  for (size_t i = 0; i < entries.size(); ++i) {
    const Field* f = find(entries[i].first);
    if (!f) continue;
    double v = 0;
    if (!parseValue(entries[i].second, v)) {
      if (error)
        *error = path + ":" + std::to_string(line_numbers[i]) + ": bad value '" +
                 entries[i].second + "' for " + entries[i].first;
      return false;
    }
    f->set(out, v);
  }
  p = out;
  return true;
}

}  // namespace rgbd_lane_detector
