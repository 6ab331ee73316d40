/**
 * @file default_parameter_file.h
 * @brief config/default.yaml made from the parameter tables (src/ros/node_params.def,
 * include/rgbd_lane_detector/params.def and param_enums.def): every parameter with its default
 * and its description. test_default_parameter_file regenerates it and compares byte for byte;
 * `write_default_parameters > config/default.yaml` writes it.
 */
#pragma once

#include <string>

namespace rgbd_lane_detector {

/// The text of config/default.yaml.
std::string defaultParameterFile();

}  // namespace rgbd_lane_detector
