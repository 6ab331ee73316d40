#include "rgbd_lane_detector_tools/params_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "rgbd_lane_detector/params_io.h"

namespace rgbd_lane_detector {
namespace tools {
namespace {

bool isParamName(const std::string& key) {
  const auto& names = paramNames();
  return std::find(names.begin(), names.end(), key) != names.end();
}

}  // namespace

bool setParam(Params& params, const std::string& key, const std::string& value,
              std::string& error) {
  return setParamText(params, key, value, &error);
}

bool loadParamsYaml(const std::string& path, Params& params, std::string& error,
                    std::vector<std::string>* warnings) {
  if (!rgbd_lane_detector::loadParamsYaml(path, params, &error)) return false;
  if (!warnings) return true;
  // the core ignores keys that are not parameters (node settings); name them, typos included
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string key = line.substr(0, colon), value = line.substr(colon + 1);
    key.erase(0, key.find_first_not_of(" \t"));
    key.erase(key.find_last_not_of(" \t\r") + 1);
    if (value.find_first_not_of(" \t\r") == std::string::npos) continue;  // a namespace line
    if (!key.empty() && key != "mode" && !isParamName(key))
      warnings->push_back("'" + key + "' is not a detector parameter (ignored)");
  }
  return true;
}

std::string paramsToYaml(const Params& params) {
  std::ostringstream out;
  for (const std::string& name : paramNames()) {
    double v = 0;
    if (!getParam(params, name, v)) continue;
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.10g", v);
    out << name << ": " << buf << "\n";
  }
  return out.str();
}

}  // namespace tools
}  // namespace rgbd_lane_detector
