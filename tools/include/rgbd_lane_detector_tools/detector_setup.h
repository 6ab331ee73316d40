/**
 * @file detector_setup.h
 * @brief Detector parameters and dataset options from the command line, shared by the
 * runner, the evaluator and the converter.
 */
#pragma once

#include <string>
#include <vector>

#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector_tools/command_line.h"
#include "rgbd_lane_detector_tools/dataset/dataset.h"

namespace rgbd_lane_detector {
namespace tools {

/// Command-line choices that make up the detector's Params.
struct ParamChoice {
  std::string mode = "improved";       ///< paper | improved
  std::string params_file;             ///< YAML overrides (Params field names)
  std::vector<std::string> overrides;  ///< key=value overrides, applied last
  bool colour_only = false;            ///< use_depth = false
};

/// Register --mode, --params, --param and --colour-only.
void addParamOptions(CommandLine& cl, ParamChoice& choice);

/**
 * @brief Build Params: mode preset, then the YAML file, then key=value overrides, then
 * --colour-only. Warnings (unknown YAML keys) are printed to stderr.
 * @return false with @p error on an unknown mode, unreadable file or bad value.
 */
bool buildParams(const ParamChoice& choice, Params& params, std::string& error);

/// Register --type, --camera-info, --depth-scale, --first, --step, --max-frames, the bag topic
/// options, --depth and --sgbm-param on @p options (the path is set separately).
void addDatasetOptions(CommandLine& cl, DatasetOptions& options);

/// Register --sgbm-param key=value (repeatable): StereoSGBM settings (setSgbmParam()).
void addSgbmOptions(CommandLine& cl, SgbmParams& params);

}  // namespace tools
}  // namespace rgbd_lane_detector
