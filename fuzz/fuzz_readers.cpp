// libFuzzer target: the text parsers behind the dataset readers and the parameter files.
// The last byte of an input selects the parser, the rest is the file's text:
//   0 camera_info YAML, 1 camera_info INI (camera_calibration_parsers), 2 SYNTHIA
//   intrinsics.txt, 3 KITTI calib_cam_to_cam.txt, 4 TUM rgb.txt + depth.txt (split at the
//   first "%%\n" line) and their association, 5 TUM associations.txt, 6 parameter YAML
//   (parseParamsYaml, then sanitize and a detector), 7 one `name: value` through setParamText.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include <fuzzer/FuzzedDataProvider.h>
#include <ros/console.h>

#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector/params_io.h"
#include "rgbd_lane_detector_tools/dataset/dataset.h"

namespace rld = rgbd_lane_detector;
namespace tools = rgbd_lane_detector::tools;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // camera_calibration_parsers reports every malformed file through rosconsole: keep the logs
  // to libFuzzer's own lines
  if (ros::console::set_logger_level(ROSCONSOLE_ROOT_LOGGER_NAME, ros::console::levels::Fatal))
    ros::console::notifyLoggerLevelsChanged();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider fdp(data, size);
  const int which = fdp.ConsumeIntegralInRange<int>(0, 7);
  const std::string text = fdp.ConsumeRemainingBytesAsString();
  rld::Intrinsics K;
  std::string error;
  switch (which) {
    case 0:
    case 1: {
      cv::Size image_size;
      if (tools::parseCameraInfo(text, which == 0 ? "yaml" : "ini", "fuzz", K, &image_size,
                                 error) &&
          !K.valid())
        std::abort();
      break;
    }
    case 2: {
      std::istringstream in(text);
      double baseline = 0.0;
      if (tools::parseSynthiaIntrinsics(in, "fuzz", K, &baseline, error) && !K.valid())
        std::abort();
      break;
    }
    case 3: {
      std::istringstream in(text);
      double baseline = 0.0;
      if (tools::parseKittiCalibration(in, "fuzz", K, baseline, error) &&
          (!K.valid() || !(baseline > 0)))
        std::abort();
      break;
    }
    case 4: {
      const size_t split = text.find("%%\n");
      std::istringstream rgb_in(text.substr(0, split));
      std::istringstream depth_in(split == std::string::npos ? std::string()
                                                             : text.substr(split + 3));
      tools::TumList rgb, depth;
      tools::parseTumList(rgb_in, rgb);
      tools::parseTumList(depth_in, depth);
      std::vector<tools::TumPair> pairs;
      tools::associateTumLists(rgb, depth, 0.02, pairs);
      if (pairs.size() > rgb.size() || pairs.size() > depth.size()) std::abort();
      break;
    }
    case 5: {
      std::istringstream in(text);
      std::vector<tools::TumPair> pairs;
      tools::parseTumAssociations(in, pairs);
      break;
    }
    case 6: {
      std::istringstream in(text);
      rld::Params p;
      if (rld::parseParamsYaml(in, "fuzz", p, &error)) {
        const rld::Params s = rld::sanitize(p);
        rld::LaneDetector detector(s);  // builds the templates of the sanitised parameters
        (void)detector;
      }
      break;
    }
    default: {
      const size_t colon = text.find(':');
      rld::Params p;
      if (colon != std::string::npos)
        (void)rld::setParamText(p, text.substr(0, colon), text.substr(colon + 1), &error);
      rld::LaneDetector detector(p);
      (void)detector;
      break;
    }
  }
  return 0;
}
