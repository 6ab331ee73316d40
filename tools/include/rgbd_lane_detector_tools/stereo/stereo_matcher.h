/**
 * @file stereo_matcher.h
 * @brief Depth from a rectified colour stereo pair with OpenCV's StereoSGBM, for datasets that
 * have a right image (KITTI) but no depth sensor the way a stereo-camera user has it. Stereo
 * matching belongs to the offline tools: the detector takes depth, however it was made.
 */
#pragma once

#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/disparity_depth.h"

namespace rgbd_lane_detector {
namespace tools {

/**
 * @brief StereoSGBM settings (OpenCV's names in snake_case) plus the matcher's own steps.
 * Defaults: tuned on the two KITTI 2015 frames of ../shared/realdata at full resolution
 * (1242x375) against their LiDAR disparity; docs/RESULTS.md "Stereo depth" has the figures.
 * P1 = 8 cn block_size^2 and P2 = 32 cn block_size^2 (OpenCV's recommendation; cn = 1 for
 * grey, 3 for colour).
 */
struct SgbmParams {
  int num_disparities = 128;  ///< search range 0 .. num_disparities - 1 (a multiple of 16)
  int block_size = 5;         ///< matched block (odd, 1-31)
  std::string mode = "3way";  ///< sgbm (5 paths), hh (8 paths, full DP), 3way, hh4
  bool grey = true;           ///< match the grey images (else the colour ones, cn = 3)
  int uniqueness_ratio = 10;  ///< % margin of the best cost over the second best
  int speckle_window = 100;   ///< largest speckle region removed (px; 0: no speckle filter)
  int speckle_range = 1;      ///< disparity variation within a speckle region (px)
  int disp12_max_diff = 1;    ///< OpenCV's internal left-right check (px; < 0: off)
  int pre_filter_cap = 63;    ///< clip of the x-derivative prefilter
  /// Explicit left-right consistency: a second match of the right image against the left
  /// (the mirrored pair, padded on its left likewise), a left disparity kept only when the
  /// right one it points to agrees within this (px; 0: off). Removes occlusions and
  /// mismatches that disp12_max_diff lets through.
  double lr_check = 1.0;
  /// Pad both images on the left by num_disparities (replicated border), so the left border,
  /// which OpenCV leaves unmatched, gets disparities for points that the right camera sees.
  bool pad_left = true;
};

/**
 * @brief Set one SgbmParams field from text (key = field name).
 * @return false with @p error for an unknown key or a bad value.
 */
bool setSgbmParam(SgbmParams& params, const std::string& key, const std::string& value,
                  std::string& error);

/// Every field as "key=value", space-separated (for reports; setSgbmParam() reads each back).
std::string sgbmParamsText(const SgbmParams& params);

/**
 * @brief StereoSGBM with the steps above. Reuses its buffers: the same size of input
 * allocates nothing after the first pair (OpenCV's own working memory aside).
 */
class StereoMatcher {
 public:
  /// @param[in] params must be valid (as setSgbmParam() checks).
  explicit StereoMatcher(const SgbmParams& params = SgbmParams());

  /**
   * @brief Disparity of the left image.
   * @param[in] left, right rectified CV_8UC3 (BGR) or CV_8UC1 images of the same size.
   * @param[out] disparity CV_32FC1 pixels (d = x_left - x_right), -1 where there is no match
   * (min_disparity - 1, as OpenCV and stereo_image_proc mark it).
   * @return nullptr, or a static description of bad input.
   */
  const char* disparity(const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity);

  /**
   * @brief Depth of the left image: disparity() through disparityToDepth() (Z = f B / d).
   * @param[in] focal rectified focal length (px).
   * @param[in] baseline stereo baseline (m).
   * @param[out] depth CV_32FC1 metres, NaN where there is no match.
   * @return nullptr, or a static description of bad input.
   */
  const char* depth(const cv::Mat& left, const cv::Mat& right, double focal, double baseline,
                    cv::Mat& depth);

  /// The DisparityModel of what disparity() returns (range 0 .. num_disparities - 1, 1/16 px).
  DisparityModel model(double focal, double baseline) const;

  const SgbmParams& params() const { return params_; }

 private:
  SgbmParams params_;
  cv::Ptr<cv::StereoSGBM> sgbm_;
  cv::Mat grey_[2], padded_[2], flipped_[2], raw_left_, raw_right_, disparity_;
};

}  // namespace tools
}  // namespace rgbd_lane_detector
