/**
 * @file sliding_box.h
 * @brief Stage 7: sliding-box tracing of a marker from its best match (Eq. 4).
 */
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace rgbd_lane_detector {

/// Tracing settings.
struct TraceParams {
  int box_size = 32;        ///< box side (the template size)
  int jump = 5;             ///< r: advance along the marker per step (px)
  float threshold = 0.75f;  ///< R above this is marker inside a box
  int max_steps = 400;      ///< per direction
  int gap_steps = 0;        ///< empty boxes crossed before stopping (0: paper, stop at the first)
  bool follow_curve = true; ///< update the direction from successive centroids
  double max_turn = 0.35;   ///< largest direction change from the start (rad, about 20 deg)
};

/**
 * @brief Trace a marker in both directions from a seed.
 *
 * Each step advances the box centre by @c jump along the current direction and re-centres it
 * across the marker on the centroid of the above-threshold pixels in the box, whose position is
 * recorded. A direction stops when the box leaves @p bounds or holds no such pixel (after
 * @c gap_steps empty boxes).
 * @param[in] R CV_32FC1 response map.
 * @param[in] seed start (best match).
 * @param[in] angle marker image angle (rad), pointing down the image (toward the camera).
 * @param[in] params settings.
 * @param[in] bounds region the box centre must stay in (the searched rows).
 * @param[out] centroids box centroids ordered near (bottom) to far (top); cleared first.
 * @param[out] scores R at each centroid.
 */
void traceMarker(const cv::Mat& R, const cv::Point2f& seed, double angle, const TraceParams& params,
                 const cv::Rect& bounds, std::vector<cv::Point2f>& centroids,
                 std::vector<float>& scores);

}  // namespace rgbd_lane_detector
