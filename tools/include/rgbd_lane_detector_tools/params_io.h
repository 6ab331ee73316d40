/**
 * @file params_io.h
 * @brief Detector parameters for the offline tools: modes, text values and YAML files, on top
 * of the core's parameters-by-name (rgbd_lane_detector/params_io.h), so every Params field the
 * core knows is available here too.
 *
 * Keys are the Params field names (= cfg/LaneDetector.cfg parameter names); booleans are
 * true/false, enums take their cfg constant name or value (depth_term: near_high | far_high,
 * plane_fit: three_point | least_squares). A `mode: paper|improved` line in a file selects the
 * base preset (core semantics).
 */
#pragma once

#include <string>
#include <vector>

#include "rgbd_lane_detector/params.h"

namespace rgbd_lane_detector {
namespace tools {

/**
 * @brief Set one parameter from text.
 * @return false with @p error for an unknown key or a bad value.
 */
bool setParam(Params& params, const std::string& key, const std::string& value, std::string& error);

/**
 * @brief Override @p params with the keys of a YAML file (core loadParamsYaml()).
 * @param[out] warnings keys that are not detector parameters (ignored), may be null.
 * @return false with @p error when the file cannot be read or a value is invalid.
 */
bool loadParamsYaml(const std::string& path, Params& params, std::string& error,
                    std::vector<std::string>* warnings = nullptr);

/// Every parameter as "key: value" YAML lines, numeric values (readable by loadParamsYaml()).
std::string paramsToYaml(const Params& params);

}  // namespace tools
}  // namespace rgbd_lane_detector
