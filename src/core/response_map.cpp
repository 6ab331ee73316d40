// Stage 5: G (Eq. 2), R (Eq. 3) and the maximum of R. The per-row kernels are compiled for every
// SIMD target (simd.h); this file is included once per target by Highway's foreach_target.h.
#ifndef RLD_RESPONSE_MAP_ONCE
#define RLD_RESPONSE_MAP_ONCE
#include "rgbd_lane_detector/response_map.h"

#include <algorithm>
#include <cstring>
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

// 255 where any of the rows m[0 .. count) is at least tau, 0 elsewhere; returns the columns done.
int maskRow(const float* const* m, int count, float tau, int n, uint8_t* out) {
  const hn::ScalableTag<float> d;
  const hn::RebindToSigned<decltype(d)> di;
  const hn::Rebind<int8_t, decltype(di)> d8;
  const int N = static_cast<int>(hn::Lanes(d));
  const auto t = hn::Set(d, tau);
  int x = 0;
  for (; x + N <= n; x += N) {
    auto any = hn::Ge(hn::LoadU(d, m[0] + x), t);
    for (int i = 1; i < count; ++i) any = hn::Or(any, hn::Ge(hn::LoadU(d, m[i] + x), t));
    // all-ones lanes (-1) narrow to the byte 255
    const auto bytes = hn::DemoteTo(d8, hn::BitCast(di, hn::VecFromMask(d, any)));
    hn::StoreU(bytes, d8, reinterpret_cast<int8_t*>(out + x));
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
int maskRowScalar(const float* const*, int, float, int, uint8_t*) {
  return 0;
}

// fn(x) at each nonzero byte x of m[0, w), in order (fn may zero m[x]): 32 bytes at a time past
// the zeros (most of a fusion mask), then 8.
template <typename F>
void forEachMarked(const uint8_t* m, int w, F&& fn) {
  auto word = [m](int x) {
    uint64_t v;
    std::memcpy(&v, m + x, sizeof(v));
    return v;
  };
  auto bytes = [&](int x0, int x1) {
    for (int j = x0; j < x1; ++j)
      if (m[j]) fn(j);
  };
  auto words = [&](int x0, int x1) {  // (x1 - x0 a multiple of 8)
    for (int k = x0; k < x1; k += 8)
      if (word(k) != 0) bytes(k, k + 8);
  };
  int x = 0;
  for (; x + 32 <= w; x += 32)
    if ((word(x) | word(x + 8) | word(x + 16) | word(x + 24)) != 0) words(x, x + 32);
  const int x8 = x + (w - x) / 8 * 8;
  words(x, x8);
  bytes(x8, w);
}
}  // namespace

#ifdef RLD_HAVE_HWY
HWY_EXPORT(fuseRow);
HWY_EXPORT(rowArgMax);
HWY_EXPORT(maskRow);
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
    float v = 0.f;
    int c = 0;
    rowMaximum(R.ptr<float>(y), R.cols, v, c);
    if (v > m) {
      m = v;
      max_location = cv::Point(c, y);
    }
  }
  max_value = m;
}

void rowMaximum(const float* r, int n, float& value, int& column) {
  value = r[0];
  column = 0;
  // the whole vectors, then the rest (only a strictly greater value moves the first maximum)
  for (int x = RLD_DISPATCH(rowArgMax)(r, n, value, column); x < n; ++x) {
    if (r[x] > value) {
      value = r[x];
      column = x;
    }
  }
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

void fusionMask(std::initializer_list<const cv::Mat*> maps, float tau_g, const cv::Range& rows,
                cv::Mat& mask) {
  CV_Assert(maps.size() > 0 && maps.size() <= kMaxFusedMaps);
  const cv::Size size = (*maps.begin())->size();
  for (const cv::Mat* m : maps) CV_Assert(m->type() == CV_32FC1 && m->size() == size);
  if (mask.size() != size || mask.type() != CV_8UC1) {
    mask.create(size, CV_8UC1);
    mask.setTo(0);
  }
  const int count = static_cast<int>(maps.size());
  const float* row[kMaxFusedMaps];
  const int r0 = std::max(rows.start, 0), r1 = std::min(rows.end, size.height);
  for (int y = r0; y < r1; ++y) {
    int i = 0;
    for (const cv::Mat* m : maps) row[i++] = m->ptr<float>(y);
    uint8_t* out = mask.ptr<uint8_t>(y);
    int x = RLD_DISPATCH(maskRow)(row, count, tau_g, size.width, out);
    for (; x < size.width; ++x) {
      bool any = false;
      for (i = 0; i < count; ++i) any = any || row[i][x] >= tau_g;
      out[x] = any ? 255 : 0;
    }
  }
}

void gatedFusionMask(const cv::Mat& points, const PlaneEstimate& plane, float max_off, float tau,
                     cv::Mat* const* maps, int count, float tau_g, const cv::Range& rows,
                     cv::Mat& mask, bool marked) {
  CV_Assert(count > 0 && count <= kMaxFusedMaps);
  const cv::Size size = maps[0]->size();
  for (int i = 0; i < count; ++i) CV_Assert(maps[i]->type() == CV_32FC1 && maps[i]->size() == size);
  CV_Assert(points.type() == CV_32FC3 && points.size() == size);
  if (mask.size() != size || mask.type() != CV_8UC1) {
    mask.create(size, CV_8UC1);
    mask.setTo(0);
  }
  // (applyPlaneGate()'s expression)
  const float nx = static_cast<float>(plane.normal.x()), ny = static_cast<float>(plane.normal.y()),
              nz = static_cast<float>(plane.normal.z()), pd = static_cast<float>(plane.distance);
  const int w = size.width;
  const float low = std::min(tau, tau_g);
  float* row[kMaxFusedMaps];
  const int r0 = std::max(rows.start, 0), r1 = std::min(rows.end, size.height);
  for (int y = r0; y < r1; ++y) {
    for (int i = 0; i < count; ++i) row[i] = maps[i]->ptr<float>(y);
    const float* q = points.ptr<float>(y);
    uint8_t* out = mask.ptr<uint8_t>(y);
    // 255 where any map is at min(tau, tau_g) or above: only there can the gate or the mask act
    int x = marked ? w : RLD_DISPATCH(maskRow)(row, count, low, w, out);
    for (; x < w; ++x) {
      bool any = false;
      for (int i = 0; i < count; ++i) any = any || row[i][x] >= low;
      out[x] = any ? 255 : 0;
    }
    auto gateAndMask = [&](int j) {
      const float* p = q + 3 * j;
      for (int k = 0; k < count; k += 2) {  // (an odd last map: its own pair)
        float& ml = row[k][j];
        float& mr = row[std::min(k + 1, count - 1)][j];
        if (ml < tau && mr < tau) continue;
        if (std::fabs(nx * p[0] + ny * p[1] + nz * p[2] + pd) > max_off) ml = mr = 0.f;
      }
      bool any = false;
      for (int k = 0; k < count; ++k) any = any || row[k][j] >= tau_g;
      out[j] = any ? 255 : 0;
    };
    forEachMarked(out, w, gateAndMask);
  }
}

void fuseResponseMasked(cv::Mat* const* maps, int count, const cv::Mat& G, float tau_g,
                        const cv::Range& rows, const cv::Mat& mask) {
  CV_Assert(count > 0 && count <= kMaxFusedMaps && mask.type() == CV_8UC1 &&
            G.type() == CV_32FC1 && G.size() == mask.size());
  for (int i = 0; i < count; ++i)
    CV_Assert(maps[i]->type() == CV_32FC1 && maps[i]->size() == mask.size());
  const int w = mask.cols;
  float* row[kMaxFusedMaps];
  const int r0 = std::max(rows.start, 0), r1 = std::min(rows.end, mask.rows);
  for (int y = r0; y < r1; ++y) {
    const uint8_t* mk = mask.ptr<uint8_t>(y);
    const float* g = G.ptr<float>(y);
    for (int i = 0; i < count; ++i) row[i] = maps[i]->ptr<float>(y);
    auto fuse = [&](int x) {
      for (int k = 0; k < count; ++k) row[k][x] = fusedValue(row[k][x], g[x], tau_g);
    };
    forEachMarked(mk, w, fuse);
  }
}

}  // namespace rgbd_lane_detector
#endif  // HWY_ONCE
