#include "rgbd_lane_detector/half_binary.h"

#include <algorithm>

namespace rgbd_lane_detector {
namespace {

// Half-binary of one row of interleaved pixels; ri/gi/bi are channel indices, cn the stride.
template <int cn, int ri, int gi, int bi>
void convertRow(const uint8_t* src, uint8_t* dst, int width, int tau_c) {
  for (int x = 0; x < width; ++x, src += cn) {
    const int g = greyValue(src[ri], src[gi], src[bi]);
    dst[x] = g >= tau_c ? static_cast<uint8_t>(g) : 0;
  }
}

}  // namespace

void halfBinary(const cv::Mat& colour, PixelFormat format, int tau_c, const cv::Range& rows,
                cv::Mat& out) {
  out.create(colour.size(), CV_8UC1);
  const int r0 = std::max(rows.start, 0);
  const int r1 = std::min(rows.end, colour.rows);
  const int w = colour.cols;
  for (int y = r0; y < r1; ++y) {
    const uint8_t* src = colour.ptr<uint8_t>(y);
    uint8_t* dst = out.ptr<uint8_t>(y);
    switch (format) {
      case PixelFormat::kBgr8:
        convertRow<3, 2, 1, 0>(src, dst, w, tau_c);
        break;
      case PixelFormat::kRgb8:
        convertRow<3, 0, 1, 2>(src, dst, w, tau_c);
        break;
      case PixelFormat::kBgra8:
        convertRow<4, 2, 1, 0>(src, dst, w, tau_c);
        break;
      case PixelFormat::kRgba8:
        convertRow<4, 0, 1, 2>(src, dst, w, tau_c);
        break;
      case PixelFormat::kMono8:
        for (int x = 0; x < w; ++x) dst[x] = src[x] >= tau_c ? src[x] : 0;
        break;
    }
  }
}

}  // namespace rgbd_lane_detector
