/**
 * @file frame_source.h
 * @brief The frames FramePlayerNodelet publishes and transport_bag writes (issue 23): a dataset
 * read with the tools' readers (by default the real RADIATE fog drive of ../shared/realdata), or a
 * generated road when it is absent, resized to the requested size with the intrinsics scaled.
 */
#pragma once

#include <string>
#include <vector>

#include "rgbd_lane_detector_tools/dataset/dataset.h"

namespace rgbd_lane_detector {
namespace tools {

/// What to load.
struct FrameSourceOptions {
  std::string dataset;         ///< folder or bag; empty: the default real sequence, if present
  std::string type = "auto";   ///< reader (DatasetOptions::type)
  std::string filter;          ///< only frames whose name contains this
  int max_frames = 30;         ///< frames loaded
  int width = 1920;            ///< output size (<= 0: the source's own)
  int height = 1080;
};

/**
 * @brief Load and resize the frames: colour (its format kept: bgr8 or rgb8; mono becomes bgr8)
 * linear, depth nearest as CV_32FC1 metres (NaN invalid), intrinsics scaled (pixel centres:
 * (u + 0.5) s - 0.5).
 * @param[out] frames the frames (cleared first).
 * @param[out] source what was loaded (a path, or "a generated road (summer)").
 * @param[out] warning why the dataset was not used, when a generated road was.
 */
void loadFrameSource(const FrameSourceOptions& options, std::vector<DatasetFrame>& frames,
                     std::string& source, std::string& warning);

/// The default real sequence: <realdata>/sequences/radiate_fog (empty when not compiled in).
std::string defaultFrameSourcePath();

}  // namespace tools
}  // namespace rgbd_lane_detector
