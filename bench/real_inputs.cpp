#include "real_inputs.h"

#include <cstdlib>
#include <filesystem>

namespace rgbd_lane_detector {
namespace bench {

const RealInput kRealInputs[5] = {
    {"radiate_fog", "stereo_lidar", "sequences/radiate_fog", ""},
    {"kitti", "streets", "streets", "kittiobj_train000001"},
    {"nuscenes", "streets", "streets", "nuscenes_n015_CAMFRONT_1532402927612460"},
    {"pandaset", "streets", "streets", "pandaset_002_40"},
    {"dgp", "streets", "streets", "dgp_scene02_15616458249936530"},
};

std::string realdataRoot() {
  if (const char* env = std::getenv("RLD_REALDATA")) return env;
  return RLD_DEFAULT_REALDATA;
}

bool loadRealFrame(const RealInput& in, tools::DatasetFrame& out, std::string& error) {
  tools::DatasetOptions o;
  o.path = (std::filesystem::path(realdataRoot()) / in.folder).string();
  o.type = in.type;
  auto reader = tools::openDataset(o, error);
  if (!reader) return false;
  while (reader->next(out))
    if (in.frame[0] == '\0' || out.name == in.frame) return true;
  error = reader->error().empty() ? std::string("frame ") + in.frame + " not found" : reader->error();
  return false;
}

const RealInput* realInput(const std::string& label) {
  for (const RealInput& in : kRealInputs)
    if (label == in.label) return &in;
  return nullptr;
}

}  // namespace bench
}  // namespace rgbd_lane_detector
