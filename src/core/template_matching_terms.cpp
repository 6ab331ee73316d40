// Stage 4: a line template compiled into the NCC's terms (its correlation with the image as sums
// and differences of running sums: integral-image columns where its runs are clipped, running
// sums along its slope elsewhere), and OpenCV's matchTemplate as the reference of the scores.
#include "rgbd_lane_detector/template_matching.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace rgbd_lane_detector {

void NccMatcher::compile(const LineTemplate& t, Compiled& c) {
  const int s = t.size, p = t.slope_p, q = std::max(t.slope_q, 1);
  c.p = p;
  c.q = q;
  c.count = t.count;
  c.plus.clear();
  c.minus.clear();
  // at most 2 vertical ranges and 2 q residue chains per side (no reallocation when q changes)
  c.plus.reserve(4 + 4 * kMaxSlopeDenominator);
  c.minus.reserve(4 + 4 * kMaxSlopeDenominator);
  auto pair = [&c](Term plus, Term minus) {
    c.plus.push_back(plus);
    c.minus.push_back(minus);
  };
  // Run ends clipped to column 0 (begins) or s (ends): vertical ranges of rows, two
  // integral-image lookups each.
  for (int side = 0; side < 2; ++side) {
    int r = 0;
    while (r < s) {
      auto clipped = [&](int row) {
        const int b = t.run_begin[row], e = t.run_end[row];
        return e > b && (side == 0 ? b == 0 : e == s);
      };
      if (!clipped(r)) {
        ++r;
        continue;
      }
      const int r0 = r;
      while (r < s && clipped(r)) ++r;
      if (side == 0)  // - sum P(y + r, x) over [r0, r)
        pair(Term{r0, 0, false}, Term{r, 0, false});
      else  // + sum P(y + r, x + s)
        pair(Term{r, s, false}, Term{r0, s, false});
    }
  }
  // Other run ends step by (p, q): per residue class of rows, chains of ends that follow the
  // step are summed by two lookups into the running sum along (p, q).
  for (int side = 0; side < 2; ++side) {
    auto end_at = [&](int row) { return side == 0 ? t.run_begin[row] : t.run_end[row]; };
    auto onStair = [&](int row) {
      const int b = t.run_begin[row], e = t.run_end[row];
      return e > b && (side == 0 ? b > 0 : e < s);
    };
    for (int j = 0; j < q; ++j) {
      int r = j;
      while (r < s) {
        if (!onStair(r)) {
          r += q;
          continue;
        }
        const int first = r;
        while (r + q < s && onStair(r + q) && end_at(r + q) == end_at(r) + p) r += q;
        const Term last_term{r, end_at(r), true};
        const Term before_first{first - q, end_at(first) - p, true};
        if (side == 0)
          pair(before_first, last_term);  // - sum P at the run begins
        else
          pair(last_term, before_first);  // + sum P at the run ends
        r += q;
      }
    }
  }
}

void matchTemplateReference(const cv::Mat& image, const cv::Rect& region_in, const LineTemplate& t,
                            cv::Mat& response) {
  response.create(image.size(), CV_32FC1);
  response.setTo(0);
  const cv::Rect region = region_in & cv::Rect(0, 0, image.cols, image.rows);
  const int s = t.size;
  if (region.width < s || region.height < s) return;
  cv::Mat scores;
  cv::matchTemplate(image(region), t.image, scores, cv::TM_CCOEFF_NORMED);
  cv::max(scores, 0.0, scores);
  scores.copyTo(response(cv::Rect(region.x + s / 2, region.y + s / 2, scores.cols, scores.rows)));
}

}  // namespace rgbd_lane_detector
