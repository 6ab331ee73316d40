/**
 * @file depth_points.h
 * @brief Stage 2: depth image to an organised matrix of 3D points (Eq. 1).
 */
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/// Depth decoding of one pixel to metres; NaN for invalid (0, NaN, inf, negative, out of range).
struct DepthDecoder {
  double scale = 0.001;   ///< metres per unit for 16-bit depth
  double min_depth = 0.0; ///< metres
  double max_depth = std::numeric_limits<double>::infinity();
  float operator()(uint16_t raw) const {
    const double d = raw * scale;
    return (raw != 0 && d >= min_depth && d <= max_depth) ? static_cast<float>(d)
                                                          : std::numeric_limits<float>::quiet_NaN();
  }
  float operator()(float raw) const {
    return (std::isfinite(raw) && raw > 0.f && raw >= min_depth && raw <= max_depth)
               ? raw
               : std::numeric_limits<float>::quiet_NaN();
  }
};

/// The tables depthToPoints() makes for a call (each column's x factor, the source chunks of each
/// depth block), kept by a caller that converts frame after frame: they only grow, so the calls
/// after the first allocate nothing.
struct DepthPointsTables {
  std::vector<float> ax;
  std::vector<int> spans;
  std::vector<uint8_t> chunk_any;
};

/**
 * @brief Back-project a depth image: x = (u - cx) / fx * D, y = (v - cy) / fy * D, z = D.
 *
 * Invalid depth gives (NaN, NaN, NaN). Source pixel coordinates come from @p col_map and
 * @p row_map when given (used when the detector resamples), so the points stay exact.
 * @param[in] depth CV_16UC1 or CV_32FC1 depth, read by rows through its step.
 * @param[in] decoder depth unit and validity range.
 * @param[in] K intrinsics of the image @p depth is registered to.
 * @param[in] rows rows of the output to fill (others untouched).
 * @param[out] points CV_32FC3, depth size (allocated only when its size or type differs).
 * @param[in] col_map optional: CV_32SC1 1xW source column of each output column.
 * @param[in] row_map optional: CV_32SC1 1xH source row of each output row.
 * @param[out] blocks optional: depthBlocks() of the rows filled (made while they are in cache).
 * @param[in,out] tables optional: the call's tables, kept between calls (without them the call
 *   allocates its own).
 * @return false when the depth type is unsupported.
 */
bool depthToPoints(const cv::Mat& depth, const DepthDecoder& decoder, const Intrinsics& K,
                   const cv::Range& rows, cv::Mat& points, const cv::Mat& col_map = cv::Mat(),
                   const cv::Mat& row_map = cv::Mat(), cv::Mat* blocks = nullptr,
                   DepthPointsTables* tables = nullptr);

/// Columns per byte of a depth block map (depthBlocks()).
constexpr int kDepthBlock = 16;

/**
 * @brief The depth block map of some rows of organised points: a CV_8UC1 of the points' rows
 * and ceil(cols / kDepthBlock) columns, 0 where a row's kDepthBlock columns hold no number at
 * all (no depth: a reader of z may pass them over), 1 elsewhere. Sparse depth (a LiDAR) leaves
 * most blocks empty. Rows outside @p rows are left as they are (0 when allocated).
 */
void depthBlocks(const cv::Mat& points, const cv::Range& rows, cv::Mat& blocks);

/**
 * @brief Fill invalid depth along rows from the nearest valid neighbours, when both ends of a
 * hole of at most @p max_gap pixels are valid (linear interpolation). Used for sparse depth.
 * @param[in,out] points CV_32FC3 organised points; filled points lie on the segment between ends.
 * @param[in] rows rows to process.
 * @param[in] max_gap longest hole that is filled (pixels).
 */
void fillDepthHoles(cv::Mat& points, const cv::Range& rows, int max_gap);

}  // namespace rgbd_lane_detector
