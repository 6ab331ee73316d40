/**
 * @file disparity_depth.h
 * @brief Stereo disparity to metric depth registered to the left rectified image, Z = f T / d
 * (the geometry of stereo_msgs/DisparityImage), for stereo cameras that give disparity rather
 * than registered depth (stereo_image_proc, ZED, OpenCV StereoSGBM in the offline tools).
 */
#pragma once

#include <limits>

#include <opencv2/core.hpp>

namespace rgbd_lane_detector {

/**
 * @brief Geometry and validity range of a disparity image, as stereo_msgs/DisparityImage
 * states them. Signs follow the source: a rig with d = x_l - x_r > 0 has T > 0, one that
 * reports d = x_r - x_l < 0 (ZED) has T < 0; only Z = f T / d > 0 is depth.
 */
struct DisparityModel {
  double focal = 0.0;     ///< f: focal length of the rectified images (pixels), > 0
  double baseline = 0.0;  ///< T: stereo baseline (metres), non-zero
  /// Disparities below this are invalid (stereo_msgs: "any disparity less than min_disparity
  /// is invalid"; stereo_image_proc marks unmatched pixels with min_disparity - 1).
  double min_disparity = std::numeric_limits<double>::lowest();
  /// Disparities above this are invalid; ignored unless greater than min_disparity (drivers
  /// that leave both fields 0 state no range).
  double max_disparity = std::numeric_limits<double>::infinity();
  /// Disparity resolution: a disparity closer to zero than this cannot be told from zero
  /// (infinite depth) and is invalid. 0: only d = 0 itself.
  double delta_d = 0.0;
  /// Pixels outside this window are invalid (the matcher's border); an empty rectangle means
  /// the whole image. Clipped to the image.
  cv::Rect valid_window;

  /// @return nullptr when f, T and the bounds are usable, else a static description.
  const char* problem() const;
};

/// How many pixels of a disparity image give a depth, and how many would but for its sign.
struct DisparityCounts {
  int valid = 0;  ///< pixels with a finite positive depth
  /// Pixels valid but for the sign of f T / d (within the window and the disparity range, not
  /// zero): a baseline T whose sign does not match the disparities' convention.
  int wrong_sign = 0;
};

/**
 * @brief Depth Z = f T / d of every pixel of a disparity image, NaN where the disparity is
 * invalid: non-finite, below min_disparity, above max_disparity (when that bounds a range),
 * closer to zero than delta_d, outside the valid window, or giving no finite positive Z.
 *
 * Reads and writes row by row through each image's step (either may be a region of a larger
 * image); allocates only when @p depth is not already CV_32FC1 of the disparity's size.
 * @param[in] disparity CV_32FC1 disparity (pixels).
 * @param[in] model f, T and the validity range.
 * @param[out] depth CV_32FC1 metres, the disparity's size; untouched on error. May be the
 * disparity image itself (converted in place).
 * @return nullptr on success, else a static description of the problem (wrong type, empty
 * image, unusable model).
 */
const char* disparityToDepth(const cv::Mat& disparity, const DisparityModel& model,
                             cv::Mat& depth);

/**
 * @brief What disparityToDepth() makes of @p disparity, counted: the pixels with a depth, and
 * those valid but for the sign of f T / d. A second pass over the pixels, for saying why an
 * image gave no depth at all (the conversion itself does not count: 45% slower). Bad input
 * (disparityToDepth()'s errors) counts nothing.
 */
DisparityCounts countDisparities(const cv::Mat& disparity, const DisparityModel& model);

}  // namespace rgbd_lane_detector
