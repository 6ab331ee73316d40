#include "detector_config.h"

#include <cmath>
#include <utility>

#include "rgbd_lane_detector/params_io.h"
#include "rgbd_lane_detector/ros/conversions.h"

namespace rgbd_lane_detector {
namespace conv = conversions;

ModePreset applyModePreset(ros::NodeHandle& pnh, const std::string& mode) {
  ModePreset result;
  result.mode = mode;
  Params preset_params, other_params;
  if (!paramsForMode(mode, preset_params)) {
    result.known = false;
    result.mode = "improved";
    preset_params = Params::improved();
  }
  paramsForMode(result.mode == "improved" ? "paper" : "improved", other_params);
  LaneDetectorConfig preset = LaneDetectorConfig::__getDefault__();
  LaneDetectorConfig other = preset;
  conv::paramsToConfig(preset_params, preset);
  conv::paramsToConfig(other_params, other);
  for (const auto& param : LaneDetectorConfig::__getParamDescriptions__()) {
    std::string text;
    if (pnh.getParam(param->name, text)) {  // (a string only)
      // the value the core's parameter files take for this text (setParamText()'s one table)
      Params scratch;
      double value = 0.0;
      if (setParamText(scratch, param->name, text) && getParam(scratch, param->name, value)) {
        if (param->type == "int")
          pnh.setParam(param->name, static_cast<int>(std::lround(value)));
        else if (param->type == "bool")
          pnh.setParam(param->name, value != 0.0);
        else
          pnh.setParam(param->name, value);
        result.converted += " " + param->name;
      } else {
        result.invalid += " " + param->name + "='" + text + "'";
        pnh.deleteParam(param->name);
      }
    }
    if (!pnh.hasParam(param->name)) {
      param->toServer(pnh, preset);
      continue;
    }
    dynamic_reconfigure::Config preset_value, other_value;
    param->toMessage(preset_value, preset);
    param->toMessage(other_value, other);
    if (!(preset_value == other_value)) result.overridden += " " + param->name;
  }
  return result;
}

Params paramsFromConfig(LaneDetectorConfig& config, const Params& base, int& unmapped) {
  Params p = base;
  unmapped = conv::configToParams(config, p);
  p = sanitize(p);
  conv::paramsToConfig(p, config);
  return p;
}

DetectorReconfigure::DetectorReconfigure(ros::NodeHandle& pnh,
                                         std::function<void(const Params&, int)> apply)
    : apply_(std::move(apply)),
      server_(new dynamic_reconfigure::Server<LaneDetectorConfig>(mutex_, pnh)) {
  server_->setCallback([this](LaneDetectorConfig& config, uint32_t /*level*/) {
    int unmapped = 0;
    params_ = paramsFromConfig(config, params_, unmapped);
    apply_(params_, unmapped);
  });
}

}  // namespace rgbd_lane_detector
