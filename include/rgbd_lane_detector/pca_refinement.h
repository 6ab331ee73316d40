/**
 * @file pca_refinement.h
 * @brief Stage 6: marker angle from PCA of the high-response region (template enhancement).
 */
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace rgbd_lane_detector {

/// Result of the PCA angle estimate.
struct PcaAngle {
  bool valid = false;      ///< at least 3 pixels and a dominant axis
  double angle = 0.0;      ///< atan2(dv, du) of the first principal axis, dv >= 0
  cv::Point2f centroid;    ///< mean of the region's pixel positions
  int count = 0;           ///< pixels in the region
  double elongation = 0.0; ///< sqrt(lambda1 / lambda2) (inf for a perfect line)
};

/**
 * @brief Grow the 8-connected region of R > threshold around @p peak inside the disc of
 * diameter box_size centred on it (the template-sized patch; a disc keeps the estimate
 * unbiased for thick lines), and return its first principal axis.
 * @param[in] R CV_32FC1 response map.
 * @param[in] peak start pixel (usually the maximum of R).
 * @param[in] threshold P_PCA.
 * @param[in] box_size side of the patch (the template size).
 * @param[in,out] stack scratch buffer (keeps its capacity across calls).
 * @return the angle estimate; invalid when the peak is not above the threshold.
 */
PcaAngle pcaMarkerAngle(const cv::Mat& R, const cv::Point& peak, float threshold, int box_size,
                        std::vector<cv::Point>& stack, std::vector<uint8_t>& visited);

}  // namespace rgbd_lane_detector
