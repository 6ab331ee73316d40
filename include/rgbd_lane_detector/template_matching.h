/**
 * @file template_matching.h
 * @brief Stage 4: NCC (TM_CCOEFF_NORMED) of the half-binary image with both line templates.
 */
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/line_template.h"

namespace rgbd_lane_detector {

/**
 * @brief Normalised cross-correlation with TM_CCOEFF_NORMED semantics, clamped to [0, 1].
 *
 * Output layout (both the fast and the reference path): a CV_32FC1 map of the image size whose
 * value at (u, v) is the score of the window with top-left corner (u - s/2, v - s/2), s the
 * template size, when that window lies inside @p region; 0 elsewhere. Negative scores are 0.
 *
 * The fast path uses that a line template is one run per row: the window-template product is a
 * sum of row-prefix differences, and the window mean and energy come from box sums shared by
 * both templates. Results equal cv::matchTemplate within float rounding; flat windows give 0
 * exactly as OpenCV does.
 */
class NccMatcher {
 public:
  /**
   * @brief Match both templates inside a region.
   * @param[in] image CV_8UC1 (the half-binary image).
   * @param[in] region rectangle of @p image searched (clipped to the image).
   * @param[in] left,right templates of equal size.
   * @param[out] response_left,response_right CV_32FC1 image-sized score maps.
   * @return false when the region is smaller than the template (outputs are all 0).
   */
  bool match(const cv::Mat& image, const cv::Rect& region, const LineTemplate& left,
             const LineTemplate& right, cv::Mat& response_left, cv::Mat& response_right);

 private:
  void correlate(const LineTemplate& t, const cv::Rect& region, cv::Mat& response);
  cv::Mat prefix_;      ///< CV_32SC1 row prefix sums of the region, width + 1 columns
  cv::Mat win_sum_;     ///< CV_32SC1 window sums of I over the output positions
  cv::Mat win_sq_;      ///< CV_64FC1 window sums of I^2
  cv::Mat row_sum_;     ///< CV_32SC1 horizontal window sums (scratch)
  cv::Mat row_sq_;      ///< CV_32SC1 horizontal window sums of squares (scratch)
  cv::Mat acc_;         ///< CV_32SC1 one output row of template products (scratch)
};

/**
 * @brief Reference path: cv::matchTemplate(TM_CCOEFF_NORMED) in the same output layout.
 * Allocates; for tests and benchmarks.
 */
void matchTemplateReference(const cv::Mat& image, const cv::Rect& region, const LineTemplate& t,
                            cv::Mat& response);

}  // namespace rgbd_lane_detector
