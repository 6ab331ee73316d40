/**
 * @file plane_check.h
 * @brief Check a detected lane plane against measured depth (e.g. KITTI's LiDAR), for data
 * without lane ground truth.
 */
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {
namespace tools {

/// Residual statistics of depth points with respect to a plane.
struct PlaneResiduals {
  int points = 0;            ///< valid depth points in the region
  double mean_abs = 0.0;     ///< mean |n . p + d| (m)
  double median_abs = 0.0;   ///< median |n . p + d| (m)
  double within_10cm = 0.0;  ///< fraction of points with |n . p + d| <= 0.10 m
};

/**
 * @brief The road region used for checks: rows from @p horizon_margin px below the principal
 * point to the bottom, the central @p width_fraction of the columns.
 */
cv::Rect roadCheckRegion(const cv::Size& size, const Intrinsics& K, int horizon_margin = 40,
                         double width_fraction = 0.3);

/**
 * @brief Back-project valid depth in a region (CV_16UC1 with @p scale m/unit, or CV_32FC1 m).
 * @param[in] max_depth points farther than this are skipped.
 * @param[out] points optical-frame points (cleared first).
 */
void regionPoints(const cv::Mat& depth, double scale, const Intrinsics& K, const cv::Rect& region,
                  double max_depth, std::vector<Eigen::Vector3d>& points);

/// Residuals of @p points with respect to the plane n . p + d = 0 (n unit).
PlaneResiduals planeResiduals(const std::vector<Eigen::Vector3d>& points,
                              const Eigen::Vector3d& normal, double distance);

/**
 * @brief Reference plane of the points by RANSAC (fixed seed) plus a least-squares refit on
 * the inliers, oriented toward the camera.
 * @param[in] min_spread the inliers' standard deviation along their second principal axis
 * must reach this (m): inliers along one line (the returns of a single painted line on a wet
 * road) do not fix the plane's tilt about that line.
 * @return false with fewer than 50 points, no plane holding 30% of them, or inliers spread
 * less than @p min_spread across their main axis.
 */
bool ransacPlane(const std::vector<Eigen::Vector3d>& points, double inlier_distance,
                 Eigen::Vector3d& normal, double& distance, double min_spread = 0.5);

}  // namespace tools
}  // namespace rgbd_lane_detector
