/**
 * @file response_map.h
 * @brief Stage 5: geometric map G (Eq. 2) and fused response R (Eq. 3).
 */
#pragma once

#include <cmath>
#include <initializer_list>

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/**
 * @brief G at one pixel (Eq. 2 with METHOD.md's resolutions).
 * @param[in] depth z in metres, NaN when unknown.
 * @param[in] n_dot_up n . O_y of the unit normal, NaN when the normal is unknown (counts 0).
 * @param[in] row image row v; @p height the image height (row term v / height).
 * @param[in] p alpha, beta, depth_threshold (T_D) and depth_term are read.
 */
inline float geometricValue(float depth, float n_dot_up, int row, int height, const Params& p) {
  const double normal_term = std::isfinite(n_dot_up) ? std::fabs(n_dot_up) : 0.0;
  double second;
  if (std::isfinite(depth) && depth <= p.depth_threshold) {
    second = p.depth_term == DepthTerm::kNearHigh ? (p.depth_threshold - depth) / p.depth_threshold
                                                  : depth / p.depth_threshold;
  } else {
    second = static_cast<double>(row) / height;
  }
  return static_cast<float>(p.alpha * normal_term + p.beta * second);
}

/// R at one pixel (Eq. 3): M below tau_G, M + G otherwise.
inline float fusedValue(float m, float g, float tau_g) {
  return m < tau_g ? m : m + g;
}

/**
 * @brief Geometric map G over some rows.
 * @param[in] points CV_32FC3 organised points (z = depth, NaN invalid).
 * @param[in] normals CV_32FC3 unit normals (NaN unknown).
 * @param[in] p parameters (alpha, beta, T_D, depth term, up axis).
 * @param[in] rows rows to compute; other rows of @p G are set to 0 when G is (re)allocated.
 * @param[out] G CV_32FC1.
 */
void geometricMap(const cv::Mat& points, const cv::Mat& normals, const Params& p,
                  const cv::Range& rows, cv::Mat& G);

/**
 * @brief Fused response R = M (M < tau_g) or M + G, over some rows. @p R may alias @p M.
 */
void fuseResponse(const cv::Mat& M, const cv::Mat& G, float tau_g, const cv::Range& rows,
                  cv::Mat& R);

/// The most match maps fusionMask() takes (both sides, and both acquisition templates).
constexpr int kMaxFusedMaps = 4;

/**
 * @brief Where G enters R (Eq. 3, fusedValue()): 255 where any of the match maps M is at least
 * tau_g, 0 elsewhere, over some rows. FalsNormals computes G only there.
 * @param[in] maps 1 to kMaxFusedMaps CV_32FC1 maps of one size.
 * @param[in] tau_g tau_G.
 * @param[in] rows rows to compute; other rows of @p mask are 0 when it is (re)allocated.
 * @param[out] mask CV_8UC1 of the maps' size.
 */
void fusionMask(std::initializer_list<const cv::Mat*> maps, float tau_g, const cv::Range& rows,
                cv::Mat& mask);

/**
 * @brief applyPlaneGate() on each pair of maps, then fusionMask() of them, in one pass over the
 * maps (the same maps and mask as the two in turn): the maps are read once, and only where one
 * is at min(tau, tau_g) or above is a point or a map read again.
 * @param[in] points CV_32FC3 organised points (the maps' size).
 * @param[in] plane the previous frame's plane (valid).
 * @param[in] max_off,tau applyPlaneGate()'s.
 * @param[in,out] maps @p count (1 to 4) CV_32FC1 maps, pairs (left, right) in turn; an odd last
 *            map is gated alone (as paired with itself).
 * @param[in] tau_g,rows,mask fusionMask()'s.
 * @param[in] marked @p mask holds already where any map is at min(tau, tau_g) or above over the
 *            rows (NccMatcher::Mark): that pass over the maps is not made again.
 */
void gatedFusionMask(const cv::Mat& points, const PlaneEstimate& plane, float max_off, float tau,
                     cv::Mat* const* maps, int count, float tau_g, const cv::Range& rows,
                     cv::Mat& mask, bool marked = false);

/**
 * @brief fuseResponse() in place on maps whose fusionMask() is @p mask: R differs from M only
 * where M >= tau_g, which the mask holds, so only the mask's pixels are read (the same values as
 * fuseResponse(), without a pass over every map).
 * @param[in,out] maps @p count (1 to kMaxFusedMaps) CV_32FC1 maps of @p mask's size (M in, R out).
 * @param[in] G CV_32FC1 of the same size, set where @p mask is.
 * @param[in] tau_g tau_G.
 * @param[in] rows rows to fuse.
 * @param[in] mask CV_8UC1 fusionMask() of @p maps over @p rows.
 */
void fuseResponseMasked(cv::Mat* const* maps, int count, const cv::Mat& G, float tau_g,
                        const cv::Range& rows, const cv::Mat& mask);

/**
 * @brief The maximum of a CV_32FC1 map and its first position in row-major order: what
 * cv::minMaxLoc(R, nullptr, &max_value, nullptr, &max_location) gives, without its cost.
 * @param[in] R CV_32FC1 (a region of interest of a larger map is fine), no NaN.
 * @param[out] max_value the maximum.
 * @param[out] max_location its first position, relative to @p R.
 */
void maxLocation(const cv::Mat& R, double& max_value, cv::Point& max_location);

/**
 * @brief The maximum of @p n > 0 floats (no NaN) and its first column, vectorised (a row of
 * maxLocation()).
 */
void rowMaximum(const float* r, int n, float& value, int& column);

}  // namespace rgbd_lane_detector
