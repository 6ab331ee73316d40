#include "rgbd_lane_detector/fals_normals.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

namespace rgbd_lane_detector {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

bool sameIntrinsics(const Intrinsics& a, const Intrinsics& b) {
  return a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy;
}

bool sameMap(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() != b.empty()) return false;
  if (a.empty()) return true;
  return a.total() == b.total() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

// Orient a normal toward the camera: n . p < 0 at the centre point (or its ray).
inline void orientAndStore(double nx, double ny, double nz, const float* p, const float* ray,
                           float* out) {
  const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
  if (!(len > 0.0) || !std::isfinite(len)) {
    out[0] = out[1] = out[2] = kNaN;
    return;
  }
  const float* ref = std::isnan(p[2]) ? ray : p;
  double s = 1.0 / len;
  if (nx * ref[0] + ny * ref[1] + nz * ref[2] > 0.0) s = -s;
  out[0] = static_cast<float>(nx * s);
  out[1] = static_cast<float>(ny * s);
  out[2] = static_cast<float>(nz * s);
}

}  // namespace

void FalsNormals::configure(const cv::Size& size, const Intrinsics& K, int window,
                            const cv::Mat& col_map, const cv::Mat& row_map) {
  if (size == size_ && window == window_ && sameIntrinsics(K, K_) && sameMap(col_map, col_map_) &&
      sameMap(row_map, row_map_) && !rays_.empty())
    return;
  size_ = size;
  K_ = K;
  window_ = window;
  col_map.copyTo(col_map_);
  row_map.copyTo(row_map_);
  const int W = size.width, H = size.height, h = window / 2;

  // Unit rays through the (source) pixel centres.
  rays_.create(size, CV_32FC3);
  cv::Mat vv(size, CV_64FC(6));
  for (int y = 0; y < H; ++y) {
    const int sy = row_map_.empty() ? y : row_map_.at<int>(y);
    const double ry = (sy - K.cy) / K.fy;
    float* ray = rays_.ptr<float>(y);
    double* m = vv.ptr<double>(y);
    for (int x = 0; x < W; ++x, ray += 3, m += 6) {
      const int sx = col_map_.empty() ? x : col_map_.at<int>(x);
      const double rx = (sx - K.cx) / K.fx;
      const double inv = 1.0 / std::sqrt(rx * rx + ry * ry + 1.0);
      const double v[3] = {rx * inv, ry * inv, inv};
      ray[0] = static_cast<float>(v[0]);
      ray[1] = static_cast<float>(v[1]);
      ray[2] = static_cast<float>(v[2]);
      m[0] = v[0] * v[0];
      m[1] = v[0] * v[1];
      m[2] = v[0] * v[2];
      m[3] = v[1] * v[1];
      m[4] = v[1] * v[2];
      m[5] = v[2] * v[2];
    }
  }
  // M = window sum of v v^T (windows clipped at the border), then its inverse.
  cv::Mat vsum(size, CV_64FC(6), cv::Scalar::all(0));
  for (int y = 0; y < H; ++y) {
    double* dst = vsum.ptr<double>(y);
    for (int yy = std::max(0, y - h); yy <= std::min(H - 1, y + h); ++yy) {
      const double* src = vv.ptr<double>(yy);
      for (int i = 0; i < W * 6; ++i) dst[i] += src[i];
    }
  }
  m_inv_.create(size, CV_32FC(6));
  for (int y = 0; y < H; ++y) {
    const double* src = vsum.ptr<double>(y);
    float* dst = m_inv_.ptr<float>(y);
    for (int x = 0; x < W; ++x, dst += 6) {
      Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
      for (int xx = std::max(0, x - h); xx <= std::min(W - 1, x + h); ++xx) {
        const double* s = src + 6 * xx;
        M(0, 0) += s[0];
        M(0, 1) += s[1];
        M(0, 2) += s[2];
        M(1, 1) += s[3];
        M(1, 2) += s[4];
        M(2, 2) += s[5];
      }
      M(1, 0) = M(0, 1);
      M(2, 0) = M(0, 2);
      M(2, 1) = M(1, 2);
      const Eigen::Matrix3d Mi = M.inverse();
      dst[0] = static_cast<float>(Mi(0, 0));
      dst[1] = static_cast<float>(Mi(0, 1));
      dst[2] = static_cast<float>(Mi(0, 2));
      dst[3] = static_cast<float>(Mi(1, 1));
      dst[4] = static_cast<float>(Mi(1, 2));
      dst[5] = static_cast<float>(Mi(2, 2));
    }
  }
  q_.create(size, CV_32FC4);
  col_sums_.create(1, W, CV_64FC4);
}

void FalsNormals::compute(const cv::Mat& points, const cv::Range& rows, cv::Mat& normals) {
  CV_Assert(points.type() == CV_32FC3 && points.size() == size_ && window_ > 0);
  normals.create(size_, CV_32FC3);
  const int W = size_.width, H = size_.height, h = window_ / 2;
  const int r0 = std::max(rows.start, 0), r1 = std::min(rows.end, H);
  if (r0 >= r1) return;

  // q = v / r = p / |p|^2 and a validity flag, on the rows the windows read.
  const int q0 = std::max(0, r0 - h), q1 = std::min(H, r1 + h);
  for (int y = q0; y < q1; ++y) {
    const float* p = points.ptr<float>(y);
    float* q = q_.ptr<float>(y);
    for (int x = 0; x < W; ++x, p += 3, q += 4) {
      const float r2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
      if (r2 > 0.f && std::isfinite(r2)) {
        const float inv = 1.f / r2;
        q[0] = p[0] * inv;
        q[1] = p[1] * inv;
        q[2] = p[2] * inv;
        q[3] = 1.f;
      } else {
        q[0] = q[1] = q[2] = q[3] = 0.f;
      }
    }
  }

  double* cs = col_sums_.ptr<double>();
  for (int y = r0; y < r1; ++y) {
    const int ya = std::max(0, y - h), yb = std::min(H - 1, y + h);
    // vertical window sums (double: b is a small difference of large sums)
    std::fill(cs, cs + 4 * W, 0.0);
    for (int yy = ya; yy <= yb; ++yy) {
      const float* q = q_.ptr<float>(yy);
      for (int i = 0; i < 4 * W; ++i) cs[i] += q[i];
    }
    const float* mi = m_inv_.ptr<float>(y);
    const float* p = points.ptr<float>(y);
    const float* ray = rays_.ptr<float>(y);
    float* out = normals.ptr<float>(y);
    for (int x = 0; x < W; ++x, mi += 6, p += 3, ray += 3, out += 3) {
      const int xa = std::max(0, x - h), xb = std::min(W - 1, x + h);
      double b0 = 0, b1 = 0, b2 = 0, cnt = 0;
      for (int xx = xa; xx <= xb; ++xx) {
        const double* c = cs + 4 * xx;
        b0 += c[0];
        b1 += c[1];
        b2 += c[2];
        cnt += c[3];
      }
      const int full = (xb - xa + 1) * (yb - ya + 1);
      const int n_valid = static_cast<int>(cnt + 0.5);
      if (n_valid == full) {
        const double nx = mi[0] * b0 + mi[1] * b1 + mi[2] * b2;
        const double ny = mi[1] * b0 + mi[3] * b1 + mi[4] * b2;
        const double nz = mi[2] * b0 + mi[4] * b1 + mi[5] * b2;
        orientAndStore(nx, ny, nz, p, ray, out);
        continue;
      }
      if (n_valid < 3) {
        out[0] = out[1] = out[2] = kNaN;
        continue;
      }
      // Partial window: M from the valid rays only; the valid pixels must span two rows and
      // two columns (non-collinear rays), otherwise the plane is undetermined.
      Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
      int min_x = W, max_x = -1, min_y = H, max_y = -1;
      for (int yy = ya; yy <= yb; ++yy) {
        const float* q = q_.ptr<float>(yy);
        const float* rr = rays_.ptr<float>(yy);
        for (int xx = xa; xx <= xb; ++xx) {
          if (q[4 * xx + 3] == 0.f) continue;
          const Eigen::Vector3d v(rr[3 * xx], rr[3 * xx + 1], rr[3 * xx + 2]);
          M.noalias() += v * v.transpose();
          min_x = std::min(min_x, xx);
          max_x = std::max(max_x, xx);
          min_y = std::min(min_y, yy);
          max_y = std::max(max_y, yy);
        }
      }
      if (max_x == min_x || max_y == min_y) {
        out[0] = out[1] = out[2] = kNaN;
        continue;
      }
      const Eigen::Vector3d n = M.ldlt().solve(Eigen::Vector3d(b0, b1, b2));
      orientAndStore(n[0], n[1], n[2], p, ray, out);
    }
  }
}

}  // namespace rgbd_lane_detector
