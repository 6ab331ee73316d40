/**
 * @file half_binary.h
 * @brief Stage 1: colour to 8-bit grey, then THRESH_TOZERO at tau_c (METHOD.md section 1).
 */
#pragma once

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/**
 * @brief Half-binary grey image: grey < tau_c becomes 0, the rest keep their grey value.
 *
 * Grey uses OpenCV's fixed-point BT.601 weights, so it equals cv::cvtColor + cv::threshold
 * (THRESH_TOZERO at tau_c - 1) exactly.
 * @param[in] colour CV_8UC1/3/4 image laid out as @p format says.
 * @param[in] format channel order of @p colour.
 * @param[in] tau_c threshold on 0-255 grey.
 * @param[in] rows rows to convert; the other rows of @p out are left untouched.
 * @param[out] out CV_8UC1 of the colour size (allocated, and zeroed, only when its size or type
 * differs).
 */
void halfBinary(const cv::Mat& colour, PixelFormat format, int tau_c, const cv::Range& rows,
                cv::Mat& out);

/**
 * @brief halfBinary() of the colour resampled through index maps (remapNearest()'s): pixel
 * (x, y) of @p out is the half-binary value of @p colour at (col_map[x], row_map[y]), the same
 * as halfBinary() of the resampled colour, without resampling the colour.
 * @param[in] col_map,row_map CV_32SC1 1xW and 1xH source columns and rows.
 * @param[out] out CV_8UC1 W x H (allocated, and zeroed, only when its size or type differs).
 */
void halfBinary(const cv::Mat& colour, PixelFormat format, int tau_c, const cv::Range& rows,
                cv::Mat& out, const cv::Mat& col_map, const cv::Mat& row_map);

/// greyValue() of the @p n pixels of format @p format at @p src into @p dst (the row kernel of
/// halfBinary(), vectorised: the classifier's profiles read a few hundred pixels a row).
void greyPixels(const uint8_t* src, PixelFormat format, int n, uint8_t* dst);

/// Grey value of one pixel with the weights halfBinary() uses: OpenCV's 15-bit fixed-point
/// BT.601 (0.299, 0.587, 0.114), so it equals cv::cvtColor(..., COLOR_BGR2GRAY) bit for bit.
inline int greyValue(int r, int g, int b) {
  return (r * 9798 + g * 19235 + b * 3735 + (1 << 14)) >> 15;
}

}  // namespace rgbd_lane_detector
