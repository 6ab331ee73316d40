// The detector's own per-pixel passes (resampling, the plane gate): plain loops, which the
// compiler vectorises (no Highway kernel: neither is a measurable share of a frame).
#include "rgbd_lane_detector/pixel_kernels.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

namespace rgbd_lane_detector {

void remapNearest(const cv::Mat& src, const cv::Mat& col_map, const cv::Mat& row_map,
                  cv::Mat& dst) {
  dst.create(row_map.cols, col_map.cols, src.type());
  const int elem = src.channels();
  const int* cm = col_map.ptr<int>();
  const int* rm = row_map.ptr<int>();
  for (int y = 0; y < dst.rows; ++y) {
    const uint8_t* s = src.ptr<uint8_t>(rm[y]);
    uint8_t* d = dst.ptr<uint8_t>(y);
    for (int x = 0; x < dst.cols; ++x)
      for (int c = 0; c < elem; ++c) d[x * elem + c] = s[cm[x] * elem + c];
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
