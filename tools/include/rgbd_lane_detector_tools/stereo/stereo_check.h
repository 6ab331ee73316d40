/**
 * @file stereo_check.h
 * @brief Stereo depth measured against a reference depth (KITTI's LiDAR): the KITTI 2015
 * disparity error measures and the depth error over the road region.
 */
#pragma once

#include <array>
#include <vector>

#include <opencv2/core.hpp>

namespace rgbd_lane_detector {
namespace tools {

/**
 * @brief Error statistics of an estimated depth against a reference, accumulated over frames.
 * Disparities are compared as d = f B / Z, so depth from any source can be checked.
 */
class StereoCheck {
 public:
  /// Upper ends (m) of the distance bins of the road-region depth error.
  static constexpr std::array<double, 3> kBins = {{10.0, 20.0, 40.0}};

  /**
   * @brief Add one frame.
   * @param[in] estimate CV_32FC1 depth (m), NaN / <= 0 where there is none.
   * @param[in] reference CV_16UC1 (@p reference_scale m per unit, 0 = none) or CV_32FC1 (m,
   * NaN / <= 0 = none) depth of the same size.
   * @param[in] fb focal length times baseline (px m): d = fb / Z.
   * @param[in] road region whose depth error is binned by the reference distance (<= 40 m).
   * @return false (nothing added) when the sizes or types do not fit.
   */
  bool add(const cv::Mat& estimate, const cv::Mat& reference, double reference_scale, double fb,
           const cv::Rect& road);

  long pixels() const { return pixels_; }        ///< pixels seen
  long estimated() const { return estimated_; }  ///< pixels with an estimate
  long reference() const { return reference_; }  ///< pixels with a reference
  long matched() const { return matched_; }      ///< reference pixels with an estimate
  /// Fraction of all pixels with an estimate.
  double density() const;
  /// Fraction of the reference pixels with an estimate.
  double coverage() const;
  /// Fraction of the matched reference pixels with |d_est - d_ref| > 3 px.
  double outliers3px() const;
  /// KITTI 2015 D1 among the matched pixels: |d_est - d_ref| > 3 px and > 5% of d_ref.
  double d1Matched() const;
  /// KITTI 2015 D1 over every reference pixel, a missing estimate counting as an outlier.
  double d1All() const;
  /// Road region: reference pixels (<= 40 m) with an estimate / all of them.
  double roadCoverage() const;
  /// Road region, distance bin @p bin (kBins) or every bin (-1): mean |Z_est - Z_ref| (m).
  double roadMeanError(int bin = -1) const;
  /// Road region: median |Z_est - Z_ref| (m), bin as above.
  double roadMedianError(int bin = -1) const;
  /// Road region: mean (Z_est - Z_ref) (m), the bias, bin as above.
  double roadBias(int bin = -1) const;
  /// Road region: mean |Z_est - Z_ref| / Z_ref, bin as above.
  double roadRelativeError(int bin = -1) const;
  /// Road region: matched pixels in the bin (or all).
  long roadPoints(int bin = -1) const;

 private:
  struct Sample {
    float error;  // Z_est - Z_ref
    float z_ref;
    int bin;
  };
  long pixels_ = 0, estimated_ = 0, reference_ = 0, matched_ = 0;
  long outliers_3px_ = 0, outliers_d1_ = 0, road_reference_ = 0;
  std::vector<Sample> road_;
};

}  // namespace tools
}  // namespace rgbd_lane_detector
