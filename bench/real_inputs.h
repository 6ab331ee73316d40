/**
 * @file real_inputs.h
 * @brief The real corpus frames the benchmarks run (one per camera of ../shared/realdata, at its
 * native size), read in place with the tools' dataset readers: shared by bench_core's
 * BM_Real_* and profile_core's real mode.
 */
#pragma once

#include <string>

#include "rgbd_lane_detector_tools/dataset/dataset.h"

namespace rgbd_lane_detector {
namespace bench {

/// One real frame of the corpus.
struct RealInput {
  const char* label;   ///< benchmark argument name
  const char* type;    ///< dataset reader
  const char* folder;  ///< under the realdata root
  const char* frame;   ///< frame name in it ("" = the first)
};

/// The frames: RADIATE's ZED 672x376, KITTI 1242x375, nuScenes 1600x900, PandaSet 1920x1080,
/// DGP 1936x1216, each with its LiDAR depth.
extern const RealInput kRealInputs[5];

/// The corpus root: $RLD_REALDATA, else the repository's ../shared/realdata.
std::string realdataRoot();

/// Read @p in's frame into @p out; false with @p error when the data or the frame is missing.
bool loadRealFrame(const RealInput& in, tools::DatasetFrame& out, std::string& error);

/// The input labelled @p label, or nullptr.
const RealInput* realInput(const std::string& label);

}  // namespace bench
}  // namespace rgbd_lane_detector
