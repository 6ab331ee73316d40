/**
 * @file pixel_kernels.h
 * @brief The detector's own per-pixel passes: the processing image resampled through index maps
 * (nearest neighbour), and the plane gate of the response maps (named option plane_gate).
 */
#pragma once

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/**
 * @brief dst(y, x) = src(row_map[y], col_map[x]), every channel (nearest-neighbour resampling),
 * for the dst rows @p rows (all when empty).
 * @param[in] src CV_8U image of any channel count.
 * @param[in] col_map,row_map CV_32SC1 rows: the source column of each dst column, the source row
 *            of each dst row.
 * @param[out] dst created (src's type, row_map's length x col_map's length; zero when allocated,
 *             so rows never resampled read as 0); no allocation once sized.
 * @param[in] rows dst rows to resample.
 */
void remapNearest(const cv::Mat& src, const cv::Mat& col_map, const cv::Mat& row_map, cv::Mat& dst,
                  const cv::Range& rows = cv::Range::all());

/**
 * @brief A match on a surface off the lane plane (a truck's stripe, a guard rail) cannot be a road
 * marking: where either map is at @p tau or above and the point is farther than @p max_off from
 * @p plane, both maps are zeroed (a point without depth, NaN, is kept). Below @p tau nothing is
 * looked at.
 * @param[in] points CV_32FC3 organised points (the maps' size).
 * @param[in] rows rows to gate.
 * @param[in] plane the previous frame's plane (valid).
 * @param[in] max_off distance from the plane (m) beyond which a match is removed.
 * @param[in] tau the lowest response that anything takes (seeds, PCA, traces, G).
 * @param[in,out] left,right CV_32FC1 response maps.
 */
void applyPlaneGate(const cv::Mat& points, const cv::Range& rows, const PlaneEstimate& plane,
                    float max_off, float tau, cv::Mat& left, cv::Mat& right);

}  // namespace rgbd_lane_detector
