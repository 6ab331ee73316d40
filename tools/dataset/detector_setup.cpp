#include "rgbd_lane_detector_tools/detector_setup.h"

#include <iostream>

#include "rgbd_lane_detector_tools/params_io.h"

namespace rgbd_lane_detector {
namespace tools {

void addParamOptions(CommandLine& cl, ParamChoice& choice) {
  cl.add("mode", "detector mode: paper (Params::paper()) or improved (Params::improved(), default)",
         &choice.mode);
  cl.add("params", "YAML file of detector parameters (Params / cfg names) over the mode",
         &choice.params_file);
  cl.add("param", "one parameter override, key=value", &choice.overrides);
  cl.addFlag("colour-only", "colour-only ablation (use_depth = false)", &choice.colour_only);
}

bool buildParams(const ParamChoice& choice, Params& params, std::string& error) {
  Params p;
  if (!paramsForMode(choice.mode, p)) {
    error = "unknown mode '" + choice.mode + "' (paper, improved)";
    return false;
  }
  if (!choice.params_file.empty()) {
    std::vector<std::string> warnings;
    if (!loadParamsYaml(choice.params_file, p, error, &warnings)) return false;
    for (const auto& w : warnings)
      std::cerr << "warning: " << choice.params_file << ": " << w << "\n";
  }
  for (const auto& kv : choice.overrides) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos) {
      error = "--param " + kv + ": expected key=value";
      return false;
    }
    if (!setParam(p, kv.substr(0, eq), kv.substr(eq + 1), error)) return false;
  }
  if (choice.colour_only) p.use_depth = false;
  params = sanitize(p);
  return true;
}

void addDatasetOptions(CommandLine& cl, DatasetOptions& o) {
  cl.add("type", "dataset format: auto (default), synthia, tum, tum_frames, kitti, streets, stereo_lidar, bag", &o.type);
  cl.add("camera-info", "camera_info YAML overriding the dataset's intrinsics", &o.camera_info);
  cl.add("depth-scale", "metres per unit of 16-bit depth (default: the format's)", &o.depth_scale);
  cl.add("first", "first frame position to use", &o.first);
  cl.add("step", "use every N-th frame", &o.step);
  cl.add("max-frames", "stop after N frames", &o.max_frames);
  cl.add("colour-topic", "bag colour topic (suffix match, default rgb/image_rect_color)",
         &o.colour_topic);
  cl.add("depth-topic", "bag depth topic (default depth_registered/image_rect)", &o.depth_topic);
  cl.add("info-topic", "bag camera_info topic (default rgb/camera_info)", &o.info_topic);
  cl.add("depth",
         "depth given to the detector: dataset (default: the folder's own, KITTI's LiDAR) or "
         "sgbm (OpenCV StereoSGBM on the colour stereo pair of KITTI folders with *_right.png)",
         &o.depth);
  addSgbmOptions(cl, o.sgbm);
}

void addSgbmOptions(CommandLine& cl, SgbmParams& params) {
  cl.addCustom("sgbm-param", "KEY=VALUE",
               "StereoSGBM setting for --depth sgbm (repeatable; defaults: " +
                   sgbmParamsText(SgbmParams()) + ")",
               [&params](const std::string& kv, std::string& error) {
                 const size_t eq = kv.find('=');
                 if (eq == std::string::npos) {
                   error = "--sgbm-param " + kv + ": expected key=value";
                   return false;
                 }
                 return setSgbmParam(params, kv.substr(0, eq), kv.substr(eq + 1), error);
               });
}

}  // namespace tools
}  // namespace rgbd_lane_detector
