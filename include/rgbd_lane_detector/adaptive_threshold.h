/**
 * @file adaptive_threshold.h
 * @brief Per-row half-binary threshold (named option `adaptive_tau_c`): fog lifts the road's grey
 * with distance, overpasses and shadows lower it, so one fixed tau_c keeps either the road
 * texture or nothing. Each row is thresholded at its median grey plus an offset.
 */
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace rgbd_lane_detector {

/**
 * @brief Half-binary image of a grey image with a threshold per row: the pixels of each row
 * below (row median + offset) become 0, the others keep their grey value.
 * @param[in] grey CV_8UC1 grey (or half-binary) image.
 * @param[out] out CV_8UC1 of the same size (may be @p grey itself: in place); created when its
 *             size or type differs, and then zeroed; rows outside @p rows are left untouched.
 * @param[in] rows rows to process.
 * @param[in] offset added to the row median (clamped to 0..255 after adding).
 * @param[in,out] histogram scratch buffer (256 bins, reused).
 */
void applyRowThreshold(const cv::Mat& grey, cv::Mat& out, const cv::Range& rows, int offset,
                       std::vector<int>& histogram);

/// Median grey of the pixels 0, stride, 2 stride, ... of one row (the lower median for an even
/// count).
int rowMedian(const uint8_t* row, int width, std::vector<int>& histogram, int stride = 1);

}  // namespace rgbd_lane_detector
