/**
 * @file lane_plane.h
 * @brief Stage 8: the lane plane from traced marker points (section "Lane model fitting").
 */
#pragma once

#include <vector>

#include <Eigen/Core>

#include "rgbd_lane_detector/geometry.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/**
 * @brief Plane through three points, n = (b - a1) x (a2 - a1), oriented toward the camera
 * (n . p + d = 0 with d > 0, so the origin lies on the side n points to).
 * @param[in] a1,b,a2 points in the camera optical frame.
 * @param[out] out plane; invalid for non-finite, coincident or collinear points (angle between
 *             the edges below ~0.5 deg) or a plane through the camera centre.
 * @return out.valid.
 */
bool planeFromThreePoints(const Eigen::Vector3f& a1, const Eigen::Vector3f& b,
                          const Eigen::Vector3f& a2, PlaneEstimate& out);

/**
 * @brief Robust least-squares plane: total least squares on the finite points, then
 * @p iterations re-fits on the points within @p inlier_distance (m) of the current plane.
 * @param[in] points candidate points (non-finite entries are skipped).
 * @param[in] inlier_distance residual bound of the refits.
 * @param[in] iterations number of refits.
 * @param[out] out plane (support = inliers); invalid with fewer than 3 non-collinear points.
 * @return out.valid.
 */
bool fitPlaneLeastSquares(const std::vector<Eigen::Vector3f>& points, double inlier_distance,
                          int iterations, PlaneEstimate& out);

}  // namespace rgbd_lane_detector
