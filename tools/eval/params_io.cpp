#include "rgbd_lane_detector_tools/params_io.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <opencv2/core.hpp>

namespace rgbd_lane_detector {
namespace tools {
namespace {

enum class Kind { kInt, kDouble, kBool, kDepthTerm, kPlaneFit };

struct Field {
  const char* name;
  Kind kind;
  void* value;
};

std::vector<Field> fields(Params& p) {
  return {
      {"tau_c", Kind::kInt, &p.tau_c},
      {"processing_scale", Kind::kDouble, &p.processing_scale},
      {"roi_top", Kind::kDouble, &p.roi_top},
      {"roi_bottom", Kind::kDouble, &p.roi_bottom},
      {"min_depth", Kind::kDouble, &p.min_depth},
      {"max_depth", Kind::kDouble, &p.max_depth},
      {"normal_window", Kind::kInt, &p.normal_window},
      {"template_size", Kind::kInt, &p.template_size},
      {"template_line_width", Kind::kInt, &p.template_line_width},
      {"template_angle_deg", Kind::kDouble, &p.template_angle_deg},
      {"use_depth", Kind::kBool, &p.use_depth},
      {"depth_threshold", Kind::kDouble, &p.depth_threshold},
      {"alpha", Kind::kDouble, &p.alpha},
      {"beta", Kind::kDouble, &p.beta},
      {"depth_term", Kind::kDepthTerm, &p.depth_term},
      {"tau_g", Kind::kDouble, &p.tau_g},
      {"up_x", Kind::kDouble, &p.up_x},
      {"up_y", Kind::kDouble, &p.up_y},
      {"up_z", Kind::kDouble, &p.up_z},
      {"pca_threshold", Kind::kDouble, &p.pca_threshold},
      {"adapt_templates", Kind::kBool, &p.adapt_templates},
      {"jump_step", Kind::kInt, &p.jump_step},
      {"trace_threshold", Kind::kDouble, &p.trace_threshold},
      {"max_trace_steps", Kind::kInt, &p.max_trace_steps},
      {"min_marker_points", Kind::kInt, &p.min_marker_points},
      {"plane_fit", Kind::kPlaneFit, &p.plane_fit},
      {"plane_max_tilt_deg", Kind::kDouble, &p.plane_max_tilt_deg},
      {"gap_steps", Kind::kInt, &p.gap_steps},
      {"ego_lane_seeds", Kind::kBool, &p.ego_lane_seeds},
      {"road_gate", Kind::kBool, &p.road_gate},
      {"road_gate_cos", Kind::kDouble, &p.road_gate_cos},
      {"plane_gate", Kind::kDouble, &p.plane_gate},
      {"fill_depth_holes", Kind::kInt, &p.fill_depth_holes},
      {"plane_smoothing", Kind::kDouble, &p.plane_smoothing},
  };
}

bool parseNumber(const std::string& text, double& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return end && *end == '\0' && std::isfinite(out);
}

bool parseBool(const std::string& t, bool& out) {
  if (t == "true" || t == "True" || t == "TRUE" || t == "1" || t == "yes" || t == "on") {
    out = true;
    return true;
  }
  if (t == "false" || t == "False" || t == "FALSE" || t == "0" || t == "no" || t == "off") {
    out = false;
    return true;
  }
  return false;
}

std::string nodeText(const cv::FileNode& n) {
  if (n.isString()) return static_cast<std::string>(n);
  if (n.isInt()) return std::to_string(static_cast<int>(n));
  if (n.isReal()) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.17g", static_cast<double>(n));
    return buf;
  }
  return std::string();
}

}  // namespace

bool paramsForMode(const std::string& mode, Params& params) {
  if (mode == "paper")
    params = Params::paper();
  else if (mode == "improved")
    params = Params::improved();
  else
    return false;
  return true;
}

bool setParam(Params& params, const std::string& key, const std::string& value,
              std::string& error) {
  for (const Field& f : fields(params)) {
    if (key != f.name) continue;
    double num = 0;
    bool ok = true;
    switch (f.kind) {
      case Kind::kInt:
        ok = parseNumber(value, num) && num == std::floor(num) && std::fabs(num) < 1e9;
        if (ok) *static_cast<int*>(f.value) = static_cast<int>(num);
        break;
      case Kind::kDouble:
        ok = parseNumber(value, num);
        if (ok) *static_cast<double*>(f.value) = num;
        break;
      case Kind::kBool:
        ok = parseBool(value, *static_cast<bool*>(f.value));
        break;
      case Kind::kDepthTerm: {
        DepthTerm& t = *static_cast<DepthTerm*>(f.value);
        if (value == "near_high" || value == "0")
          t = DepthTerm::kNearHigh;
        else if (value == "far_high" || value == "1")
          t = DepthTerm::kFarHigh;
        else
          ok = false;
        break;
      }
      case Kind::kPlaneFit: {
        PlaneFit& t = *static_cast<PlaneFit*>(f.value);
        if (value == "three_point" || value == "0")
          t = PlaneFit::kThreePoint;
        else if (value == "least_squares" || value == "1")
          t = PlaneFit::kLeastSquares;
        else
          ok = false;
        break;
      }
    }
    if (!ok) error = "invalid value '" + value + "' for parameter '" + key + "'";
    return ok;
  }
  error = "unknown parameter '" + key + "'";
  return false;
}

bool loadParamsYaml(const std::string& path, Params& params, std::string& error,
                    std::vector<std::string>* warnings) {
  std::ifstream in(path);
  if (!in) {
    error = "cannot open parameter file " + path;
    return false;
  }
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  // cv::FileStorage insists on its YAML directive; ROS parameter files do not carry one
  if (yaml.compare(0, 5, "%YAML") != 0) yaml = "%YAML:1.0\n---\n" + yaml;
  Params p = params;
  try {
    cv::FileStorage fs(
        yaml, cv::FileStorage::READ | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
    if (!fs.isOpened()) {
      error = "cannot parse parameter file " + path;
      return false;
    }
    std::vector<cv::FileNode> maps = {fs.root()};
    for (const auto& n : fs.root())
      if (n.isMap()) maps.push_back(n);  // one level of namespaces
    for (const cv::FileNode& map : maps) {
      for (const auto& n : map) {
        if (n.isMap()) continue;
        const std::string key = n.name();
        std::string err;
        bool known = false;
        for (const Field& f : fields(p)) known = known || key == f.name;
        if (!known) {
          if (warnings) warnings->push_back("unknown parameter '" + key + "' ignored");
          continue;
        }
        if (!setParam(p, key, nodeText(n), err)) {
          error = path + ": " + err;
          return false;
        }
      }
    }
  } catch (const cv::Exception& e) {
    error = "cannot parse parameter file " + path + ": " + e.what();
    return false;
  }
  params = p;
  return true;
}

std::string paramsToYaml(const Params& params) {
  Params p = params;
  std::ostringstream out;
  out.precision(10);
  for (const Field& f : fields(p)) {
    out << f.name << ": ";
    switch (f.kind) {
      case Kind::kInt:
        out << *static_cast<int*>(f.value);
        break;
      case Kind::kDouble:
        out << *static_cast<double*>(f.value);
        break;
      case Kind::kBool:
        out << (*static_cast<bool*>(f.value) ? "true" : "false");
        break;
      case Kind::kDepthTerm:
        out << (*static_cast<DepthTerm*>(f.value) == DepthTerm::kNearHigh ? "near_high"
                                                                          : "far_high");
        break;
      case Kind::kPlaneFit:
        out << (*static_cast<PlaneFit*>(f.value) == PlaneFit::kThreePoint ? "three_point"
                                                                          : "least_squares");
        break;
    }
    out << "\n";
  }
  return out.str();
}

}  // namespace tools
}  // namespace rgbd_lane_detector
