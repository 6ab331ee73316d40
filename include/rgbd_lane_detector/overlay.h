/**
 * @file overlay.h
 * @brief Human-readable overlay of a detection (shared by the nodelet's debug_image and the
 * offline runners).
 */
#pragma once

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/**
 * @brief Draw the searched region, both traced markers (left green, right orange), the seed
 * boxes with their PCA direction, a grid on the lane plane and the scores.
 * @param[in] colour input colour image (any supported PixelFormat).
 * @param[in] format its channel layout.
 * @param[in] K intrinsics of @p colour (for the plane grid).
 * @param[in] result detection of that frame (at any processing scale).
 * @param[in] params parameters used (template size, processing scale).
 * @param[out] out bgr8 image of the colour size (reused).
 */
void drawOverlay(const cv::Mat& colour, PixelFormat format, const Intrinsics& K,
                 const Result& result, const Params& params, cv::Mat& out);

}  // namespace rgbd_lane_detector
