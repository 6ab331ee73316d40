/**
 * @file params_io.h
 * @brief Parameters by name (the dynamic_reconfigure names) and YAML parameter files (yaml-cpp).
 */
#pragma once

#include <istream>
#include <string>
#include <vector>

#include "rgbd_lane_detector/params.h"

namespace rgbd_lane_detector {

/// Names of every Params field, in declaration order (the names of cfg/LaneDetector.cfg plus
/// up_x, up_y, up_z).
const std::vector<std::string>& paramNames();

/**
 * @brief Set one field by name. Booleans take 0/1, enums their integer value.
 * @return false for an unknown name (the parameters are unchanged).
 */
bool setParam(Params& p, const std::string& name, double value);

/**
 * @brief Set one field by name from text as in a YAML file: a number, true/false, or an enum
 * name (param_enums.def: near_high, far_high, three_point, least_squares, road_surface).
 * @return false for an unknown name or a malformed value (@p error says which).
 */
bool setParamText(Params& p, const std::string& name, const std::string& text,
                  std::string* error = nullptr);

/// Read one field by name as a double; false for an unknown name.
bool getParam(const Params& p, const std::string& name, double& value);

/**
 * @brief Apply a YAML parameter file (ROS parameter file style: a map of `name: value`) on top of
 * @p p, read with yaml-cpp. Values: numbers, true/false, and the enum names of param_enums.def
 * (near_high, far_high, three_point, least_squares, road_surface). A `mode: paper|improved` key
 * (anywhere) selects that preset as the base the other keys apply to. Keys that are not
 * parameters (node settings such as queue_size) are ignored and listed in @p ignored; the keys of
 * a nested map (a node's namespace) count as the file's own.
 * @param[in] path file to read.
 * @param[in,out] p parameters to update.
 * @param[out] error message when the file cannot be read, is not a YAML map, or a value is
 *             malformed (with its line).
 * @param[out] ignored keys that are not parameters, in file order (may be null).
 * @return false on error (then @p p is unchanged).
 */
bool loadParamsYaml(const std::string& path, Params& p, std::string* error = nullptr,
                    std::vector<std::string>* ignored = nullptr);

/// loadParamsYaml() on a stream; @p source names it in error messages.
bool parseParamsYaml(std::istream& in, const std::string& source, Params& p,
                     std::string* error = nullptr, std::vector<std::string>* ignored = nullptr);

}  // namespace rgbd_lane_detector
