// FALS normal of one pixel straight from the definition (falsNormalAt(), fals_normals.h).
#include <algorithm>
#include <cmath>

#include "fals_window.h"
#include "rgbd_lane_detector/fals_normals.h"

namespace rgbd_lane_detector {

bool falsNormalAt(const cv::Mat& points, int x, int y, int window, const Intrinsics& K,
                  const cv::Mat& col_map, const cv::Mat& row_map, float n[3]) {
  if (points.type() != CV_32FC3 || x < 0 || y < 0 || x >= points.cols || y >= points.rows)
    return false;
  const int h = window / 2;
  double M[6] = {0, 0, 0, 0, 0, 0}, b[3] = {0, 0, 0};
  int count = 0, min_x = x + h, max_x = x - h, min_y = y + h, max_y = y - h;
  for (int yy = std::max(0, y - h); yy <= std::min(points.rows - 1, y + h); ++yy) {
    const int sy = row_map.empty() ? yy : row_map.at<int>(yy);
    const float* row = points.ptr<float>(yy);
    for (int xx = std::max(0, x - h); xx <= std::min(points.cols - 1, x + h); ++xx) {
      const float* p = row + 3 * xx;
      const double r2 = static_cast<double>(p[0]) * p[0] + static_cast<double>(p[1]) * p[1] +
                        static_cast<double>(p[2]) * p[2];
      if (!(r2 > 0.0) || !std::isfinite(r2)) continue;
      const int sx = col_map.empty() ? xx : col_map.at<int>(xx);
      const Eigen::Vector3d w = K.ray(sx, sy);
      double v[3] = {w.x(), w.y(), 1.0};
      const double inv = 1.0 / std::sqrt(v[0] * v[0] + v[1] * v[1] + 1.0);
      for (double& c : v) c *= inv;
      const double inv_r = 1.0 / std::sqrt(r2);
      M[0] += v[0] * v[0];
      M[1] += v[0] * v[1];
      M[2] += v[0] * v[2];
      M[3] += v[1] * v[1];
      M[4] += v[1] * v[2];
      M[5] += v[2] * v[2];
      for (int c = 0; c < 3; ++c) b[c] += v[c] * inv_r;
      ++count;
      min_x = std::min(min_x, xx);
      max_x = std::max(max_x, xx);
      min_y = std::min(min_y, yy);
      max_y = std::max(max_y, yy);
    }
  }
  if (count < 3 || min_x == max_x || min_y == max_y) return false;
  // n = M^-1 b by the adjugate (M symmetric), up to the factor det M
  double a[6], m[3];
  fals::symmetricAdjugate(M, a);
  fals::adjugateTimes(a, b[0], b[1], b[2], m);
  const double nx = m[0], ny = m[1], nz = m[2];
  const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
  if (!(len > 0.0) || !std::isfinite(len)) return false;
  // toward the camera (the determinant's sign is absorbed here)
  const float* c = points.ptr<float>(y) + 3 * x;
  double s = 1.0 / len;
  if (std::isfinite(c[2]) && nx * c[0] + ny * c[1] + nz * c[2] > 0.0) s = -s;
  if (!std::isfinite(c[2])) {
    const int sx = col_map.empty() ? x : col_map.at<int>(x);
    const int sy = row_map.empty() ? y : row_map.at<int>(y);
    if (nx * (sx - K.cx) / K.fx + ny * (sy - K.cy) / K.fy + nz > 0.0) s = -s;
  }
  n[0] = static_cast<float>(nx * s);
  n[1] = static_cast<float>(ny * s);
  n[2] = static_cast<float>(nz * s);
  return true;
}


}  // namespace rgbd_lane_detector
