/**
 * @file fals_normals.h
 * @brief Stage 3: FALS surface normals (Badino et al. 2011), M^-1 precomputed per pixel.
 */
#pragma once

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/**
 * @brief Fast approximate least-squares normals from an organised point matrix.
 *
 * For each pixel and its w x w window: M = sum v_i v_i^T over unit rays (intrinsics only),
 * b = sum v_i / r_i over the ranges, n = M^-1 b, normalised and oriented toward the camera
 * (n . p < 0). M^-1 is computed once per (size, intrinsics, window) and reused. A window with
 * invalid points uses M built from its valid rays only; fewer than window-side valid points,
 * or an ill-conditioned M, gives a NaN normal.
 */
class FalsNormals {
 public:
  /**
   * @brief Prepare the per-pixel M^-1 for an image geometry (no-op when unchanged).
   * @param[in] size image size.
   * @param[in] K intrinsics of the points' image (after any resampling).
   * @param[in] window window side, 3, 5 or 7.
   * @param[in] col_map optional CV_32SC1 1xW source column of each column (resampled images).
   * @param[in] row_map optional CV_32SC1 1xH source row of each row.
   */
  void configure(const cv::Size& size, const Intrinsics& K, int window,
                 const cv::Mat& col_map = cv::Mat(), const cv::Mat& row_map = cv::Mat());

  /**
   * @brief Normals of the rows @p rows (windows may read neighbouring rows).
   * @param[in] points CV_32FC3 organised points (NaN = invalid) of the configured size.
   * @param[in] rows output rows to compute.
   * @param[out] normals CV_32FC3 unit normals toward the camera, NaN where unknown.
   */
  void compute(const cv::Mat& points, const cv::Range& rows, cv::Mat& normals);

  /// Unit ray through each pixel (CV_32FC3), valid after configure().
  const cv::Mat& rays() const { return rays_; }
  int window() const { return window_; }

 private:
  cv::Size size_;
  Intrinsics K_;
  int window_ = 0;
  cv::Mat col_map_, row_map_;
  cv::Mat rays_;   ///< CV_32FC3 unit rays
  cv::Mat m_inv_;  ///< CV_32FC(6): symmetric M^-1 per pixel (xx, xy, xz, yy, yz, zz)
  cv::Mat q_;      ///< CV_32FC4: v/r per pixel (3) and validity (1)
  cv::Mat col_sums_;  ///< CV_32FC4 one row of vertical window sums
};

}  // namespace rgbd_lane_detector
