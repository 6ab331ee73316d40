#include "rgbd_lane_detector/depth_points.h"

#include <algorithm>

namespace rgbd_lane_detector {
namespace {

template <typename T>
void convertRows(const cv::Mat& depth, const DepthDecoder& decode, const Intrinsics& K, int r0,
                 int r1, cv::Mat& points, const int* col_map, const int* row_map) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const double inv_fx = 1.0 / K.fx;
  const double inv_fy = 1.0 / K.fy;
  const int w = points.cols;
  for (int y = r0; y < r1; ++y) {
    const int sy = row_map ? row_map[y] : y;
    const T* src = depth.ptr<T>(sy);
    float* dst = points.ptr<float>(y);
    const float ry = static_cast<float>((sy - K.cy) * inv_fy);
    for (int x = 0; x < w; ++x, dst += 3) {
      const int sx = col_map ? col_map[x] : x;
      const float d = decode(src[sx]);
      if (std::isnan(d)) {
        dst[0] = dst[1] = dst[2] = nan;
        continue;
      }
      dst[0] = static_cast<float>((sx - K.cx) * inv_fx) * d;
      dst[1] = ry * d;
      dst[2] = d;
    }
  }
}

}  // namespace

bool depthToPoints(const cv::Mat& depth, const DepthDecoder& decoder, const Intrinsics& K,
                   const cv::Range& rows, cv::Mat& points, const cv::Mat& col_map,
                   const cv::Mat& row_map) {
  if (depth.type() != CV_16UC1 && depth.type() != CV_32FC1) return false;
  const cv::Size size(col_map.empty() ? depth.cols : static_cast<int>(col_map.total()),
                      row_map.empty() ? depth.rows : static_cast<int>(row_map.total()));
  points.create(size, CV_32FC3);
  const int r0 = std::max(rows.start, 0);
  const int r1 = std::min(rows.end, size.height);
  const int* cm = col_map.empty() ? nullptr : col_map.ptr<int>();
  const int* rm = row_map.empty() ? nullptr : row_map.ptr<int>();
  if (depth.type() == CV_16UC1)
    convertRows<uint16_t>(depth, decoder, K, r0, r1, points, cm, rm);
  else
    convertRows<float>(depth, decoder, K, r0, r1, points, cm, rm);
  return true;
}

void fillDepthHoles(cv::Mat& points, const cv::Range& rows, int max_gap) {
  if (max_gap <= 0 || points.type() != CV_32FC3) return;
  const int r0 = std::max(rows.start, 0);
  const int r1 = std::min(rows.end, points.rows);
  for (int y = r0; y < r1; ++y) {
    cv::Vec3f* row = points.ptr<cv::Vec3f>(y);
    int last_valid = -1;
    for (int x = 0; x < points.cols; ++x) {
      if (std::isnan(row[x][2])) continue;
      const int gap = x - last_valid - 1;
      if (last_valid >= 0 && gap > 0 && gap <= max_gap) {
        // Interpolate x/z, y/z and 1/z: all three are affine in the column on a plane, and the
        // filled point stays on its pixel's ray.
        const cv::Vec3f& a = row[last_valid];
        const cv::Vec3f& b = row[x];
        const float ia = 1.f / a[2], ib = 1.f / b[2];
        const float xa = a[0] * ia, xb = b[0] * ib, ya = a[1] * ia, yb = b[1] * ib;
        for (int k = 1; k <= gap; ++k) {
          const float t = static_cast<float>(k) / static_cast<float>(gap + 1);
          const float z = 1.f / (ia + t * (ib - ia));
          row[last_valid + k] = cv::Vec3f((xa + t * (xb - xa)) * z, (ya + t * (yb - ya)) * z, z);
        }
      }
      last_valid = x;
    }
  }
}

}  // namespace rgbd_lane_detector
