/**
 * @file adaptive_threshold.h
 * @brief Per-row half-binary threshold (named option `adaptive_tau_c`): fog lifts the road's grey
 * with distance, overpasses and shadows lower it, so one fixed tau_c keeps either the road
 * texture or nothing. Each row is thresholded at its median grey plus an offset; on a dark row
 * (night, dense fog, a wet road: median below kDarkRow) the offset is the paint's relative
 * contrast over the median, so that paint 25% brighter than a road of grey 45 (11 levels) is
 * kept where a fixed offset of 30 loses it.
 */
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace rgbd_lane_detector {

/**
 * @brief Half-binary image of a grey image with a threshold per row: the pixels of each row
 * below (row median + its offset) become 0, the others keep their grey value. The row's offset
 * is @p offset; on a dark row (median below kDarkRow, at most kBrightTail of it at or above the
 * fixed threshold), @p relative times the median where that is less, but not less than
 * kMinRowOffset (sensor noise).
 * @param[in] grey CV_8UC1 grey (or half-binary) image.
 * @param[out] out CV_8UC1 of the same size (may be @p grey itself: in place); created when its
 *             size or type differs, and then zeroed; rows outside @p rows are left untouched.
 * @param[in] rows rows to process.
 * @param[in] offset added to the row median at most (clamped to 0..255 after adding).
 * @param[in,out] histogram scratch buffer (256 bins, reused).
 * @param[in] relative the paint's contrast relative to the road on dark rows (0: @p offset on
 *            every row).
 */
void applyRowThreshold(const cv::Mat& grey, cv::Mat& out, const cv::Range& rows, int offset,
                       std::vector<int>& histogram, double relative = 0.0);

/// Smallest row offset of the dark-row rule (grey levels: sensor noise).
constexpr int kMinRowOffset = 8;
/// Rows with a median grey below this are dark (the relative offset applies) ...
constexpr int kDarkRow = 80;
/// ... unless more than this share of their pixels is at or above median + offset (the row
/// shows bright paint, which the fixed offset keeps: a dark asphalt in daylight).
constexpr double kBrightTail = 0.02;

/// Median grey of the pixels 0, stride, 2 stride, ... of one row (the lower median for an even
/// count).
int rowMedian(const uint8_t* row, int width, std::vector<int>& histogram, int stride = 1);

}  // namespace rgbd_lane_detector
