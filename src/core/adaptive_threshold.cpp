#include "rgbd_lane_detector/adaptive_threshold.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace rgbd_lane_detector {

int rowMedian(const uint8_t* row, int width, std::vector<int>& histogram, int stride) {
  histogram.assign(256, 0);
  int n = 0;
  for (int x = 0; x < width; x += stride, ++n) ++histogram[row[x]];
  const int half = (n + 1) / 2;
  int seen = 0;
  for (int g = 0; g < 256; ++g) {
    seen += histogram[g];
    if (seen >= half) return g;
  }
  return 255;
}

void applyRowThreshold(const cv::Mat& grey, cv::Mat& out, const cv::Range& rows, int offset,
                       std::vector<int>& histogram) {
  CV_Assert(grey.type() == CV_8UC1);
  if (out.data != grey.data && (out.size() != grey.size() || out.type() != CV_8UC1)) {
    out.create(grey.size(), CV_8UC1);
    out.setTo(0);
  }
  const int r0 = std::max(rows.start, 0), r1 = std::min(rows.end, grey.rows);
  for (int y = r0; y < r1; ++y) {
    const uint8_t* in = grey.ptr<uint8_t>(y);
    // a median of every 4th pixel is as good a level as the exact one, at a quarter of the cost
    const int level = rowMedian(in, grey.cols, histogram, 4);
    const int tau = std::min(std::max(level + offset, 0), 255);
    // THRESH_TOZERO keeps values above the threshold: tau - 1 keeps those >= tau
    cv::threshold(grey.row(y), out.row(y), tau - 1, 255, cv::THRESH_TOZERO);
  }
}

}  // namespace rgbd_lane_detector
