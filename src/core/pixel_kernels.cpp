// The detector's own per-pixel passes (resampling, the plane gate): plain loops, which the
// compiler vectorises (no Highway kernel: neither is a measurable share of a frame).
#include "rgbd_lane_detector/pixel_kernels.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <Eigen/Core>

namespace rgbd_lane_detector {

namespace {

// remapNearest()'s rows with C channels known at compile time (a run-time channel loop cost
// 2 ms per 1920x1080 frame).
template <int C>
void remapRows(const cv::Mat& src, const int* cm, const int* rm, int r0, int r1, cv::Mat& dst) {
  for (int y = r0; y < r1; ++y) {
    const uint8_t* s = src.ptr<uint8_t>(rm[y]);
    uint8_t* d = dst.ptr<uint8_t>(y);
    for (int x = 0; x < dst.cols; ++x)
      for (int c = 0; c < C; ++c) d[x * C + c] = s[cm[x] * C + c];
  }
}

}  // namespace

void remapNearest(const cv::Mat& src, const cv::Mat& col_map, const cv::Mat& row_map, cv::Mat& dst,
                  const cv::Range& rows) {
  const cv::Size size(col_map.cols, row_map.cols);
  if (dst.size() != size || dst.type() != src.type()) {
    dst.create(size, src.type());
    for (int y = 0; y < dst.rows; ++y)  // (cv::Mat::setTo allocates)
      std::memset(dst.ptr<uint8_t>(y), 0, dst.cols * dst.elemSize());
  }
  const int r0 = rows == cv::Range::all() ? 0 : std::max(rows.start, 0);
  const int r1 = rows == cv::Range::all() ? dst.rows : std::min(rows.end, dst.rows);
  const int* cm = col_map.ptr<int>();
  const int* rm = row_map.ptr<int>();
  switch (src.channels()) {
    case 1:
      remapRows<1>(src, cm, rm, r0, r1, dst);
      break;
    case 3:
      remapRows<3>(src, cm, rm, r0, r1, dst);
      break;
    case 4:
      remapRows<4>(src, cm, rm, r0, r1, dst);
      break;
    default:  // not a colour the detector takes: byte by byte
      for (int y = r0; y < r1; ++y) {
        const int e = static_cast<int>(src.elemSize());
        const uint8_t* s = src.ptr<uint8_t>(rm[y]);
        uint8_t* d = dst.ptr<uint8_t>(y);
        for (int x = 0; x < dst.cols; ++x) std::memcpy(d + x * e, s + cm[x] * e, e);
      }
      break;
  }
}

void applyPlaneGate(const cv::Mat& points, const cv::Range& rows, const PlaneEstimate& plane,
                    float max_off, float tau, cv::Mat& left, cv::Mat& right) {
  const Eigen::Vector3f pn = plane.normal.cast<float>();
  const float pd = static_cast<float>(plane.distance);
  const int width = left.cols;
  constexpr int kBlock = 16;
  for (int y = rows.start; y < rows.end; ++y) {
    const float* q = points.ptr<float>(y);
    float* ml = left.ptr<float>(y);
    float* mr = right.ptr<float>(y);
    for (int x0 = 0; x0 < width; x0 += kBlock) {
      const int x1 = std::min(x0 + kBlock, width);
      // any match in the block at tau or above (an OR of comparisons, which the compiler
      // vectorises; a float max chain is ordered and stays scalar without -ffast-math)
      int any = 0;
      for (int x = x0; x < x1; ++x) any |= static_cast<int>(ml[x] >= tau) | static_cast<int>(mr[x] >= tau);
      if (!any) continue;
      for (int x = x0; x < x1; ++x) {
        if (ml[x] < tau && mr[x] < tau) continue;
        const float* p = q + 3 * x;
        if (std::fabs(pn.x() * p[0] + pn.y() * p[1] + pn.z() * p[2] + pd) > max_off)
          ml[x] = mr[x] = 0.f;  // NaN (no depth) compares false: kept
      }
    }
  }
}

}  // namespace rgbd_lane_detector
