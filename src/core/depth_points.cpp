#include "rgbd_lane_detector/depth_points.h"

#include <algorithm>
#include <cstring>
#include <type_traits>
#include <vector>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define RLD_POINTS_AVX2 1
#define RLD_AVX2 __attribute__((target("avx2")))
#endif

#include "rgbd_lane_detector/template_matching.h"  // simdLevel()

namespace rgbd_lane_detector {
namespace {

#ifdef RLD_POINTS_AVX2
// Four points from x, y, z lanes to interleaved x y z x y z ... (12 floats at dst).
RLD_AVX2 inline void store4(float* dst, __m128 x, __m128 y, __m128 z) {
  const __m128 a = _mm_unpacklo_ps(x, y);                                 // x0 y0 x1 y1
  const __m128 b = _mm_unpackhi_ps(x, y);                                 // x2 y2 x3 y3
  const __m128 t = _mm_unpacklo_ps(z, x);                                 // z0 x0 z1 x1
  const __m128 u = _mm_shuffle_ps(a, t, _MM_SHUFFLE(2, 2, 3, 3));         // y1 y1 z1 z1
  const __m128 w = _mm_shuffle_ps(z, b, _MM_SHUFFLE(3, 2, 3, 2));         // z2 z3 x3 y3
  _mm_storeu_ps(dst, _mm_shuffle_ps(a, t, _MM_SHUFFLE(3, 0, 1, 0)));      // x0 y0 z0 x1
  _mm_storeu_ps(dst + 4, _mm_shuffle_ps(u, b, _MM_SHUFFLE(1, 0, 2, 0)));  // y1 z1 x2 y2
  _mm_storeu_ps(dst + 8, _mm_shuffle_ps(w, w, _MM_SHUFFLE(1, 3, 2, 0)));  // z2 x3 y3 z3
}

// Eight pixels of one row (no column map), the scalar code's values lane for lane: the depth is
// decoded in double and rounded once, x = float((u - cx) / fx) d, y = float((v - cy) / fy) d.
template <typename T>
RLD_AVX2 void rowAvx2(const T* src, int w, const DepthDecoder& dec, double cx, double inv_fx,
                      float ry, float* dst, int& done) {
  const __m256d scale = _mm256_set1_pd(dec.scale), lo = _mm256_set1_pd(dec.min_depth),
                hi = _mm256_set1_pd(dec.max_depth), zero = _mm256_setzero_pd(),
                inf = _mm256_set1_pd(std::numeric_limits<double>::infinity()),
                vcx = _mm256_set1_pd(cx), vfx = _mm256_set1_pd(inv_fx);
  const __m128 vry = _mm_set1_ps(ry), nan = _mm_set1_ps(std::numeric_limits<float>::quiet_NaN());
  int x = 0;
  for (; x + 8 <= w; x += 8) {
    for (int half = 0; half < 2; ++half) {
      const int u = x + 4 * half;
      __m256d d, ok;
      if (std::is_same<T, uint16_t>::value) {
        uint64_t raw4;
        std::memcpy(&raw4, src + u, 8);
        const __m128i r = _mm_cvtepu16_epi32(_mm_cvtsi64_si128(static_cast<int64_t>(raw4)));
        const __m256d rd = _mm256_cvtepi32_pd(r);
        d = _mm256_mul_pd(rd, scale);
        ok = _mm256_cmp_pd(rd, zero, _CMP_NEQ_OQ);
      } else {
        d = _mm256_cvtps_pd(_mm_loadu_ps(reinterpret_cast<const float*>(src) + u));
        ok = _mm256_and_pd(_mm256_cmp_pd(d, zero, _CMP_GT_OQ), _mm256_cmp_pd(d, inf, _CMP_LT_OQ));
      }
      ok = _mm256_and_pd(
          ok, _mm256_and_pd(_mm256_cmp_pd(d, lo, _CMP_GE_OQ), _mm256_cmp_pd(d, hi, _CMP_LE_OQ)));
      const __m128 okf = _mm256_cvtpd_ps(_mm256_and_pd(ok, _mm256_set1_pd(1.0)));
      const __m128 keep = _mm_cmpeq_ps(okf, _mm_set1_ps(1.f));
      const __m128 df = _mm256_cvtpd_ps(d);
      const __m256d us = _mm256_add_pd(_mm256_set1_pd(u), _mm256_setr_pd(0, 1, 2, 3));
      const __m128 ax = _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_sub_pd(us, vcx), vfx));
      auto sel = [&](__m128 v) RLD_AVX2 { return _mm_blendv_ps(nan, v, keep); };
      store4(dst + 3 * u, sel(_mm_mul_ps(ax, df)), sel(_mm_mul_ps(vry, df)), sel(df));
    }
  }
  done = x;
}

// 16-bit depth, eight pixels per step: the decoder's range test as an integer interval of raw
// values [lo, hi] (found with its own double expression), the decode in double rounded once, and
// x from a table of float((u - cx) / fx).
RLD_AVX2 void rowAvx2U16(const uint16_t* src, int w, double scale, uint16_t lo, uint16_t hi,
                         const float* ax, float ry, float* dst, int& done) {
  const __m128i vlo = _mm_set1_epi16(static_cast<short>(lo)),
                vhi = _mm_set1_epi16(static_cast<short>(hi));
  const __m256d vscale = _mm256_set1_pd(scale);
  const __m256 vry = _mm256_set1_ps(ry),
               nan = _mm256_set1_ps(std::numeric_limits<float>::quiet_NaN());
  int x = 0;
  for (; x + 8 <= w; x += 8) {
    const __m128i raw = _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + x));
    const __m128i in = _mm_cmpeq_epi16(raw, _mm_min_epu16(_mm_max_epu16(raw, vlo), vhi));
    const __m256 keep = _mm256_castsi256_ps(_mm256_cvtepi16_epi32(in));
    const __m256i r32 = _mm256_cvtepu16_epi32(raw);
    const __m128 d0 =
        _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_cvtepi32_pd(_mm256_castsi256_si128(r32)), vscale));
    const __m128 d1 = _mm256_cvtpd_ps(
        _mm256_mul_pd(_mm256_cvtepi32_pd(_mm256_extracti128_si256(r32, 1)), vscale));
    const __m256 d = _mm256_set_m128(d1, d0);
    const __m256 X = _mm256_blendv_ps(nan, _mm256_mul_ps(_mm256_loadu_ps(ax + x), d), keep);
    const __m256 Y = _mm256_blendv_ps(nan, _mm256_mul_ps(vry, d), keep);
    const __m256 Z = _mm256_blendv_ps(nan, d, keep);
    store4(dst + 3 * x, _mm256_castps256_ps128(X), _mm256_castps256_ps128(Y),
           _mm256_castps256_ps128(Z));
    store4(dst + 3 * x + 12, _mm256_extractf128_ps(X, 1), _mm256_extractf128_ps(Y, 1),
           _mm256_extractf128_ps(Z, 1));
  }
  done = x;
}

// Raw values r with d = r * scale inside [min_depth, max_depth] and r != 0: an interval, since
// d grows with r. Found with the decoder's own expression; empty when lo > hi.
void validRaw(const DepthDecoder& dec, uint16_t& lo, uint16_t& hi) {
  auto ok_lo = [&](int r) { return r * dec.scale >= dec.min_depth; };
  auto ok_hi = [&](int r) { return r * dec.scale <= dec.max_depth; };
  int a = 1, b = 65536;  // first r >= 1 with ok_lo (65536: none)
  while (a < b) {
    const int m = (a + b) / 2;
    if (ok_lo(m))
      b = m;
    else
      a = m + 1;
  }
  int c = 0, e = 65535;  // last r <= 65535 with ok_hi (0: none)
  while (c < e) {
    const int m = (c + e + 1) / 2;
    if (ok_hi(m))
      c = m;
    else
      e = m - 1;
  }
  if (a > 65535 || c < a || !ok_hi(c)) {
    lo = 1;  // empty: no raw value passes both
    hi = 0;
    return;
  }
  lo = static_cast<uint16_t>(a);
  hi = static_cast<uint16_t>(c);
}
#endif

template <typename T>
void convertRows(const cv::Mat& depth, const DepthDecoder& decode, const Intrinsics& K, int r0,
                 int r1, cv::Mat& points, const int* col_map, const int* row_map) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const double inv_fx = 1.0 / K.fx;
  const double inv_fy = 1.0 / K.fy;
  const int w = points.cols;
#ifdef RLD_POINTS_AVX2
  const bool avx2 = simdLevel() >= 1;
  // 16-bit rows: the valid raw interval and the x factors of the columns, once per call
  // (the table is per thread and only grows)
  uint16_t raw_lo = 1, raw_hi = 0;
  thread_local std::vector<float> ax;
  const bool u16 = std::is_same<T, uint16_t>::value && avx2 && !col_map && decode.scale > 0.0;
  if (u16) {
    validRaw(decode, raw_lo, raw_hi);
    if (static_cast<int>(ax.size()) < w) ax.resize(w);
    for (int x = 0; x < w; ++x) ax[x] = static_cast<float>((x - K.cx) * inv_fx);
  }
#endif
  for (int y = r0; y < r1; ++y) {
    const int sy = row_map ? row_map[y] : y;
    const T* src = depth.ptr<T>(sy);
    float* dst = points.ptr<float>(y);
    const float ry = static_cast<float>((sy - K.cy) * inv_fy);
    int x = 0;
#ifdef RLD_POINTS_AVX2
    if (u16 && raw_lo <= raw_hi)
      rowAvx2U16(reinterpret_cast<const uint16_t*>(src), w, decode.scale, raw_lo, raw_hi, ax.data(),
                 ry, dst, x);
    else if (avx2 && !col_map)
      rowAvx2<T>(src, w, decode, K.cx, inv_fx, ry, dst, x);
#endif
    for (; x < w; ++x) {
      const int sx = col_map ? col_map[x] : x;
      const float d = decode(src[sx]);
      float* q = dst + 3 * x;
      if (std::isnan(d)) {
        q[0] = q[1] = q[2] = nan;
        continue;
      }
      q[0] = static_cast<float>((sx - K.cx) * inv_fx) * d;
      q[1] = ry * d;
      q[2] = d;
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
