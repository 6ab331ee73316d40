#include "default_parameter_file.h"

#include <cstdio>
#include <map>
#include <sstream>
#include <vector>

namespace rgbd_lane_detector {
namespace {

constexpr int kValueColumn = 30;  // descriptions start here when the key and value fit

// The section title of each dynamic_reconfigure group of params.def, in the file's order.
const std::vector<std::pair<std::string, std::string>>& groupTitles() {
  static const std::vector<std::pair<std::string, std::string>> titles = {
      {"preprocessing", "preprocessing"},
      {"response", "response"},
      {"tracing", "tracing"},
      {"plane", "plane"},
      {"improvements", "improvements over the paper (paper preset: all off)"},
      {"boundaries", "real streets: the road surface from depth, each boundary on its own"},
      {"lane_model", "lane model (topic lane_model)"},
      {"lane_grid", "lane grid (topic lane_grid, nav_msgs/OccupancyGrid in lane_model_frame)"},
  };
  return titles;
}

std::string section(const std::string& title) {
  std::string line = "# --- " + title + " ";
  while (line.size() < 96) line += '-';
  return line + "\n";
}

// `key: value` padded to the description column, then `# description`.
std::string entry(const std::string& key, const std::string& value, const std::string& text,
                  const std::string& prefix = "") {
  std::string line = prefix + key + ": " + value;
  line += std::string(line.size() < kValueColumn - 1 ? kValueColumn - 1 - line.size() : 1, ' ');
  return line + "# " + text + "\n";
}

// A C++ literal of node_params.def as YAML: strings without quotes ("" kept).
std::string yamlValue(const std::string& literal) {
  if (literal.size() > 2 && literal.front() == '"') return literal.substr(1, literal.size() - 2);
  return literal;
}

// " (0 near_high: ..., 1 far_high: ...)" for an enum type of param_enums.def, else "".
std::string enumValues(const std::string& type) {
  std::string out;
#define RLD_ENUM(enum_type, enumerator, name, value, description) \
  if (type == #enum_type) out += std::string(out.empty() ? "" : ", ") + #value " " #name " (" description ")";
#include "rgbd_lane_detector/param_enums.def"
#undef RLD_ENUM
  return out.empty() ? out : ": " + out;
}

}  // namespace

std::string defaultParameterFile() {
  std::ostringstream out;
  out << "# Private parameters of rgbd_lane_detector/LaneDetectorNodelet (and lane_detector_node), every\n"
         "# one with its default. Generated from src/ros/node_params.def and\n"
         "# include/rgbd_lane_detector/params.def (write_default_parameters > config/default.yaml;\n"
         "# test_default_parameter_file checks it): do not edit by hand.\n"
         "# Load with <rosparam command=\"load\" file=\"$(find rgbd_lane_detector)/config/default.yaml\"/>.\n"
         "# The detector's values are the improved preset; each is also a dynamic_reconfigure parameter\n"
         "# (cfg/LaneDetector.cfg). For the paper's values (Quach et al.) set `mode: paper` without this\n"
         "# file: config/paper.yaml.\n\n";
  out << section("ROS layer (read once at start-up)");
#define RLD_NODE_PARAM(type, name, default_value, description)                               \
  out << entry(#name, yamlValue(#default_value), description,                                \
               std::string(#name) == "mode" ? "# " : ""); /* mode: given, it overrides the \
                                                             preset values of every key */
#include "node_params.def"
#undef RLD_NODE_PARAM
  // the detector's parameters, by group
  std::map<std::string, std::string> groups;
#define RLD_PARAM(group, type, name, improved, paper, min, max, level, description) \
  groups[#group] += entry(#name, #improved, std::string(description) + enumValues(#type));
#include "rgbd_lane_detector/params.def"
#undef RLD_PARAM
  for (const auto& [group, title] : groupTitles()) {
    const auto it = groups.find(group);
    if (it == groups.end()) continue;
    out << "\n" << section(title) << it->second;
    groups.erase(it);
  }
  groups.erase("none");  // not reconfigurable: the up axis comes from up_frame
  for (const auto& [group, text] : groups) out << "\n" << section(group) << text;  // untitled
  return out.str();
}

}  // namespace rgbd_lane_detector
