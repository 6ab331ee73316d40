// Stage 5: G (Eq. 2), R (Eq. 3) and the maximum of R. The per-row kernels are compiled for every
// SIMD target (simd.h); this file is included once per target by Highway's foreach_target.h.
#ifndef RLD_RESPONSE_MAP_ONCE
#define RLD_RESPONSE_MAP_ONCE
#include "rgbd_lane_detector/response_map.h"

#include <algorithm>
#include <limits>

#include "simd.h"
#endif

#ifdef RLD_HAVE_HWY
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "response_map.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

RLD_KERNELS_BEGIN

// R = M below tau, M + G otherwise, over one row; returns the columns done.
int fuseRow(const float* m, const float* g, float tau, int n, float* r) {
  const hn::ScalableTag<float> d;
  const int N = static_cast<int>(hn::Lanes(d));
  const auto t = hn::Set(d, tau);
  int x = 0;
  for (; x + N <= n; x += N) {
    const auto mv = hn::LoadU(d, m + x);
    hn::StoreU(hn::IfThenElse(hn::Lt(mv, t), mv, hn::Add(mv, hn::LoadU(d, g + x))), d, r + x);
  }
  return x;
}

// The maximum of a row's whole vectors and its first column, in one pass (each lane keeps the
// first column of its own maximum); returns the columns read (0: none, value and column unset).
int rowArgMax(const float* r, int n, float& value, int& column) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const int N = static_cast<int>(hn::Lanes(df));
  if (n < N) return 0;
  auto best = hn::LoadU(df, r);
  auto cols = hn::Iota(di, 0), best_cols = cols;
  int x = N;
  for (; x + N <= n; x += N) {
    cols = hn::Add(cols, hn::Set(di, N));
    const auto v = hn::LoadU(df, r + x);
    const auto above = hn::Gt(v, best);
    best = hn::IfThenElse(above, v, best);
    best_cols = hn::IfThenElse(hn::RebindMask(di, above), cols, best_cols);
  }
  value = hn::GetLane(hn::MaxOfLanes(df, best));
  const auto at = hn::RebindMask(di, hn::Eq(best, hn::Set(df, value)));
  column = hn::GetLane(hn::MinOfLanes(
      di, hn::IfThenElse(at, best_cols, hn::Set(di, std::numeric_limits<int>::max()))));
  return x;
}

RLD_KERNELS_END
#endif  // RLD_HAVE_HWY

#if HWY_ONCE
namespace rgbd_lane_detector {

namespace {
// The scalar target: no column done by a vector (the loops below do them all).
int fuseRowScalar(const float*, const float*, float, int, float*) {
  return 0;
}
int rowArgMaxScalar(const float*, int, float&, int&) {
  return 0;
}
}  // namespace

#ifdef RLD_HAVE_HWY
HWY_EXPORT(fuseRow);
HWY_EXPORT(rowArgMax);
#endif

void geometricMap(const cv::Mat& points, const cv::Mat& normals, const Params& p,
                  const cv::Range& rows, cv::Mat& G) {
  if (G.size() != points.size() || G.type() != CV_32FC1) {
    G.create(points.size(), CV_32FC1);
    G.setTo(0);
  }
  const int r0 = std::max(rows.start, 0), r1 = std::min(rows.end, points.rows);
  const float ux = static_cast<float>(p.up_x), uy = static_cast<float>(p.up_y),
              uz = static_cast<float>(p.up_z);
  for (int y = r0; y < r1; ++y) {
    const float* pt = points.ptr<float>(y);
    const float* n = normals.ptr<float>(y);
    float* g = G.ptr<float>(y);
    for (int x = 0; x < points.cols; ++x, pt += 3, n += 3) {
      const float dot = n[0] * ux + n[1] * uy + n[2] * uz;
      g[x] = geometricValue(pt[2], dot, y, points.rows, p);
    }
  }
}

void maxLocation(const cv::Mat& R, double& max_value, cv::Point& max_location) {
  CV_Assert(R.type() == CV_32FC1);
  max_location = cv::Point(-1, -1);
  max_value = 0.0;
  if (R.empty()) return;
  // the maximum and its first occurrence in row-major order (cv::minMaxLoc keeps the first on
  // ties): only a strictly greater value moves it
  float m = R.at<float>(0, 0);
  max_location = cv::Point(0, 0);
  for (int y = 0; y < R.rows; ++y) {
    const float* r = R.ptr<float>(y);
    float v = 0.f;
    int c = 0;
    int x = RLD_DISPATCH(rowArgMax)(r, R.cols, v, c);
    if (x > 0 && v > m) {
      m = v;
      max_location = cv::Point(c, y);
    }
    for (; x < R.cols; ++x) {
      if (r[x] > m) {
        m = r[x];
        max_location = cv::Point(x, y);
      }
    }
  }
  max_value = m;
}

void fuseResponse(const cv::Mat& M, const cv::Mat& G, float tau_g, const cv::Range& rows,
                  cv::Mat& R) {
  if (R.data != M.data && (R.size() != M.size() || R.type() != CV_32FC1)) {
    R.create(M.size(), CV_32FC1);
    R.setTo(0);
  }
  const int r0 = std::max(rows.start, 0), r1 = std::min(rows.end, M.rows);
  for (int y = r0; y < r1; ++y) {
    const float* m = M.ptr<float>(y);
    const float* g = G.ptr<float>(y);
    float* r = R.ptr<float>(y);
    int x = RLD_DISPATCH(fuseRow)(m, g, tau_g, M.cols, r);
    for (; x < M.cols; ++x) r[x] = fusedValue(m[x], g[x], tau_g);
  }
}

}  // namespace rgbd_lane_detector
#endif  // HWY_ONCE
