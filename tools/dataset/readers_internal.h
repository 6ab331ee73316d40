// Factories of the individual dataset readers (private to the datasets library).
#pragma once

#include <memory>
#include <string>

#include "rgbd_lane_detector_tools/dataset/dataset.h"

namespace rgbd_lane_detector {
namespace tools {
namespace internal {

std::unique_ptr<DatasetReader> openSynthia(const DatasetOptions& o, std::string& error);
std::unique_ptr<DatasetReader> openTum(const DatasetOptions& o, std::string& error);
std::unique_ptr<DatasetReader> openTumFrames(const DatasetOptions& o, std::string& error);
std::unique_ptr<DatasetReader> openKitti(const DatasetOptions& o, std::string& error);
std::unique_ptr<DatasetReader> openStreets(const DatasetOptions& o, std::string& error);
std::unique_ptr<DatasetReader> openStereoLidarSequence(const DatasetOptions& o, std::string& error);
std::unique_ptr<DatasetReader> openBag(const DatasetOptions& o, std::string& error);

/// Intrinsics override from DatasetOptions::camera_info (no-op when empty).
bool applyCameraInfo(const DatasetOptions& o, Intrinsics& K, std::string& error);

}  // namespace internal
}  // namespace tools
}  // namespace rgbd_lane_detector
