/**
 * @file overlay.h
 * @brief Human-readable overlay of a detection (shared by the nodelet's debug_image and the
 * offline runners).
 */
#pragma once

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/lane_fitter.h"
#include "rgbd_lane_detector/lane_grid.h"
#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/**
 * @brief Draw the searched region, both lane boundaries (paint: left green, right orange; road
 * edges red with square points; each with its kind and confidence in the text), the seed
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

/**
 * @brief Draw traced candidate lines with their verdicts (tuning aid): thin lines, cyan for
 * paint, magenta for road edges, grey for rejected ones, each labelled with the classifier's
 * reason and, where measured, the band width (cm) and the height step (cm).
 * @param[in] candidates lines of one side.
 * @param[in] count number of them.
 * @param[in,out] out overlay image (drawOverlay()'s output).
 */
void drawCandidates(const BoundaryCandidate* candidates, int count, cv::Mat& out);

/**
 * @brief Draw the lane grid as a bird's-eye inset in the bottom-right corner of an overlay:
 * x (forward) up, y (left) to the left, the vehicle at the bottom centre, a tick every 10 m;
 * occupied cells red, crossable yellow, free green, unknown the picture darkened. Each inset
 * pixel shows the most important of the cells it covers (occupied > crossable > free > unknown),
 * so one-cell lines stay visible at any scale. Its height is 45% of the picture's.
 * @param[in] grid the frame's lane grid.
 * @param[in,out] out overlay image (bgr8; drawOverlay()'s output); unchanged when too small.
 */
void drawLaneGridInset(const LaneGrid& grid, cv::Mat& out);

}  // namespace rgbd_lane_detector
