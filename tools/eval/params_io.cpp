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

bool setParam(Params& params, const std::string& key, const std::string& value,
              std::string& error) {
  return setParamText(params, key, value, &error);
}

bool loadParamsYaml(const std::string& path, Params& params, std::string& error,
                    std::vector<std::string>* warnings) {
  // the core ignores keys that are not parameters (node settings); name them, typos included
  std::vector<std::string> ignored;
  if (!rgbd_lane_detector::loadParamsYaml(path, params, &error, &ignored)) return false;
  if (warnings)
    for (const std::string& key : ignored)
      warnings->push_back("'" + key + "' is not a detector parameter (ignored)");
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
