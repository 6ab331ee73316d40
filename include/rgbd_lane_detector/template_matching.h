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
 * The fast path zeroes the rows outside @p region only when a map is (re)allocated or the region
 * changes: a caller that writes there between calls must clear them itself.
 *
 * The fast path never loops over template pixels. A line template row is one run
 * [b_r, e_r), so its correlation is a sum over rows of row-prefix differences
 * P(y + r, x + e_r) - P(y + r, x + b_r). Run ends clipped by the square sit on a fixed column:
 * their rows are summed by two lookups into the integral image. Unclipped run ends repeat every
 * slope_q rows shifted by slope_p columns, so each residue class of rows is summed by two
 * lookups into a running sum of P along the direction (slope_p, slope_q). A template costs
 * 8 lookups per pixel at slope 1 (the 45-degree defaults) and at most 4 + 4 slope_q, whatever
 * its size; the window mean and energy take 8 more, shared by both templates. All sums are
 * exact integers (mod 2^32, exact for any image size since window sums are far below 2^32),
 * rows are produced in a ring of s + slope_q + 1 rows, and the flat-window rule is OpenCV's,
 * so results equal cv::matchTemplate up to its own float rounding.
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

  /// The most templates one match() pass scores.
  static constexpr int kMaxTemplates = 4;

  /// Where any map of a match() scores at least @p level: fusionMask() of the maps at that
  /// level over the region's rows, marked while the scores are in registers (the detector's
  /// fusion mask without a pass over its maps).
  struct Mark {
    float level = 1.f;  ///< above 0 (0, the score outside the scored positions, is below it)
    cv::Mat* mask = nullptr;  ///< CV_8UC1 of the image's size (allocated when it is not)
    bool marked = false;      ///< set by match(): false on the reference path, a small region
                              ///< or a level of 0 or below (the mask is then not written)
  };

  /**
   * @brief Match 1 to kMaxTemplates templates of equal size in one pass: the integral images,
   * the window mean and energy are computed once for all of them, and templates of the same
   * slope share a running-sum table. Each map equals what a match() of its template alone
   * gives, bit for bit.
   * @param[in] image,region as above.
   * @param[in] templates @p count templates of equal size.
   * @param[out] responses @p count CV_32FC1 image-sized score maps (distinct).
   * @param[in,out] mark optional: also the mask of the scores at or above a level.
   * @return false when the region is smaller than the template (outputs are all 0).
   */
  bool match(const cv::Mat& image, const cv::Rect& region, const LineTemplate* const* templates,
             cv::Mat* const* responses, int count, Mark* mark = nullptr);

 private:
  /// One lookup of a compiled template: +/- table(y + dy, x + dx).
  struct Term {
    int dy;
    int dx;
    bool stair;  ///< the slope's running sum, else the integral image
  };
  /// A template as lookups: correlation = sum(plus) - sum(minus).
  struct Compiled {
    std::vector<Term> plus, minus;
    int p = 0, q = 1;
    int stair = 0;       ///< which running-sum table holds its slope
    double count = 0.0;  ///< line pixels
  };
  void compile(const LineTemplate& t, Compiled& c);
  void produceRow(const cv::Mat& image, const cv::Rect& region, int y);

  Compiled compiled_[kMaxTemplates];
  int templates_ = 0;  ///< templates of this pass
  int tables_ = 0;     ///< running-sum tables of this pass (distinct slopes)
  int table_p_[kMaxTemplates] = {}, table_q_[kMaxTemplates] = {};  ///< each table's slope
  const uint8_t* cleared_[kMaxTemplates] = {};  ///< maps whose rows outside the region are 0
  cv::Rect cleared_region_[kMaxTemplates];
  int ring_ = 0;                  ///< rows held by each table
  int margin_ = 0;                ///< extra columns each side of the running-sum tables
  int width_ = 0;                 ///< region width
  cv::Mat integral_;              ///< CV_32SC1 ring: integral image rows (width + 1 columns)
  cv::Mat integral_sq_;           ///< CV_32SC1 ring: integral of squares
  cv::Mat stair_[kMaxTemplates];  ///< CV_32SC1 rings: running sums of P along a slope
  std::vector<uint32_t> acc_[kMaxTemplates];  ///< one output row of correlations
  std::vector<int> runs_;         ///< output columns [begin, end) of the row with pixels
  std::vector<const uint32_t*> plus_ptr_, minus_ptr_;  ///< lookups of the current row
};

/**
 * @brief Reference path: cv::matchTemplate(TM_CCOEFF_NORMED) in the same output layout.
 * Allocates; for tests and benchmarks.
 */
void matchTemplateReference(const cv::Mat& image, const cv::Rect& region, const LineTemplate& t,
                            cv::Mat& response);

}  // namespace rgbd_lane_detector
