#include "rgbd_lane_detector/fals_normals.h"

#include "rgbd_lane_detector/template_matching.h"  // referenceStages()

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define RLD_FALS_AVX2 1
#endif

namespace rgbd_lane_detector {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// Planes of one row of vertical sums over the window's rows (offset dv from the centre row):
// box and first moment in dv of t = k / z (valid pixels), box of the valid flag c; where pixels
// are missing also box, first and second moment of kv = k c and the moments of c.
enum Plane { kW0, kW1, kC, kV0, kV1, kV2, kCv1, kCv2, kPlanes };

bool sameIntrinsics(const Intrinsics& a, const Intrinsics& b) {
  return a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy;
}

bool sameMap(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() != b.empty()) return false;
  if (a.empty()) return true;
  return a.total() == b.total() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

// Box, first and second moment of x[-h..h] (offsets step by `stride`), summed in one fixed order
// that the vector code repeats lane for lane.
inline void moments(const float* x, std::ptrdiff_t stride, int h, float& box, float& m1,
                    float& m2) {
  box = x[0];
  m1 = 0.f;
  m2 = 0.f;
  for (int d = 1; d <= h; ++d) {
    const float a = x[d * stride] + x[-d * stride], e = x[d * stride] - x[-d * stride];
    box = box + a;
    m1 = m1 + static_cast<float>(d) * e;
    m2 = m2 + static_cast<float>(d * d) * a;
  }
}

/// Per-row constants of the solve and of G.
struct RowConst {
  float ay = 0.f;              ///< (v - cy) / fy of the row
  float fxs = 0.f, fys = 0.f;  ///< fx / step_u, fy / step_v: n = B^-T m
  float full_rows = 0.f;       ///< window rows inside the image
  // G
  float alpha = 0.f, beta = 0.f, td = 0.f, inv_td = 0.f, row_term = 0.f;
  bool near_high = true;
  float up[3] = {0.f, -1.f, 0.f};
};

// moments() over separate rows: rows[h + d][x] is the value at offset d.
inline void momentsRows(const float* const* rows, std::ptrdiff_t x, int h, float& box, float& m1,
                        float& m2) {
  box = rows[h][x];
  m1 = 0.f;
  m2 = 0.f;
  for (int d = 1; d <= h; ++d) {
    const float a = rows[h + d][x] + rows[h - d][x], e = rows[h + d][x] - rows[h - d][x];
    box = box + a;
    m1 = m1 + static_cast<float>(d) * e;
    m2 = m2 + static_cast<float>(d * d) * a;
  }
}

/// Window sums of a pixel with missing pixels (float path).
struct Partial {
  float K0, Ku, Kv, Kuu, Kuv, Kvv, N, Cu1, Cu2, Cb1, Cb2;
};

/// Windows with missing pixels are solved in float when det Q > this K0 Kuu Kvv (Hadamard ratio;
/// 1 for a diagonal Q), in double otherwise. At 1/16 the float solve stays within 1e-4 rad of
/// the double one (test_fals_normals); thin crescents of valid pixels fall below it.
constexpr float kWellConditioned = 1.f / 16;

/// Verdict on a window with missing pixels.
enum class PartialCase { kNone, kFloat, kExact };

// Windows with missing pixels: none below 3 valid pixels or with all valid pixels in one column
// or one row (exact: the sums are small integers); solved in float when Q is well conditioned
// (det Q > (K0 Kuu Kvv) / 4, diagonal dominance), else left to the exact double path.
inline PartialCase solvePartial(const Partial& q, float T0, float Tu, float Tv, float ax,
                                const RowConst& rc, float n[3]) {
  const bool span =
      q.N >= 3.f && q.N * q.Cu2 - q.Cu1 * q.Cu1 > 0.f && q.N * q.Cb2 - q.Cb1 * q.Cb1 > 0.f;
  const float a00 = q.Kuu * q.Kvv - q.Kuv * q.Kuv;
  const float a01 = q.Kuv * q.Kv - q.Ku * q.Kvv;
  const float a02 = q.Ku * q.Kuv - q.Kuu * q.Kv;
  const float a11 = q.K0 * q.Kvv - q.Kv * q.Kv;
  const float a12 = q.Ku * q.Kv - q.K0 * q.Kuv;
  const float a22 = q.K0 * q.Kuu - q.Ku * q.Ku;
  const float det = (q.K0 * a00 + q.Ku * a01) + q.Kv * a02;
  const bool well = det > kWellConditioned * ((q.K0 * q.Kuu) * q.Kvv);
  const float m0 = (a00 * T0 + a01 * Tu) + a02 * Tv;
  const float m1 = (a01 * T0 + a11 * Tu) + a12 * Tv;
  const float m2 = (a02 * T0 + a12 * Tu) + a22 * Tv;
  n[0] = rc.fxs * m1;
  n[1] = rc.fys * m2;
  n[2] = (m0 - ax * n[0]) - rc.ay * n[1];
  return !span ? PartialCase::kNone : (well ? PartialCase::kFloat : PartialCase::kExact);
}

// Q m = s up to the positive factor det Q, from the precomputed adj(Q) of a window without missing
// pixels: m' = adj(Q) s, then n' = B^-T m' = (fxs m1, fys m2, m0 - ax n'x - ay n'y).
// Same operation order as the vector code.
inline void solveTable(const float a[6], float T0, float Tu, float Tv, float ax, const RowConst& rc,
                       float n[3]) {
  const float m0 = (a[0] * T0 + a[1] * Tu) + a[2] * Tv;
  const float m1 = (a[1] * T0 + a[3] * Tu) + a[4] * Tv;
  const float m2 = (a[2] * T0 + a[4] * Tu) + a[5] * Tv;
  n[0] = rc.fxs * m1;
  n[1] = rc.fys * m2;
  n[2] = (m0 - ax * n[0]) - rc.ay * n[1];
}

// Write the oriented unit normal and/or G of one pixel from its unnormalised normal.
inline void finish(const float n[3], bool ok, const float* p, float ax, const RowConst& rc,
                   float* normal_out, float* g_out) {
  const float len2 = (n[0] * n[0] + n[1] * n[1]) + n[2] * n[2];
  ok = ok && len2 > 0.f && len2 < kInf;
  const float inv_len = 1.f / std::sqrt(ok ? len2 : 1.f);
  const float z = p[2];
  if (normal_out) {
    // toward the camera: n . p < 0 at the centre point, or along its ray when it has no depth
    const bool has_p = z > 0.f && z < kInf;
    const float rx = has_p ? p[0] : ax, ry = has_p ? p[1] : rc.ay, rz = has_p ? z : 1.f;
    const float dot = (n[0] * rx + n[1] * ry) + n[2] * rz;
    const float s = dot > 0.f ? -inv_len : inv_len;
    normal_out[0] = ok ? n[0] * s : kNaN;
    normal_out[1] = ok ? n[1] * s : kNaN;
    normal_out[2] = ok ? n[2] * s : kNaN;
  }
  if (g_out) {
    const float nup = std::fabs((n[0] * rc.up[0] + n[1] * rc.up[1]) + n[2] * rc.up[2]) * inv_len;
    const float normal_term = ok ? nup : 0.f;
    const bool near = z <= rc.td && z > -kInf;
    const float depth_term = rc.near_high ? (rc.td - z) * rc.inv_td : z * rc.inv_td;
    *g_out = rc.alpha * normal_term + rc.beta * (near ? depth_term : rc.row_term);
  }
}

#ifdef RLD_FALS_AVX2
#define RLD_AVX2_INLINE __attribute__((target("avx2"), always_inline)) inline
RLD_AVX2_INLINE __m256 mul(__m256 a, __m256 b) {
  return _mm256_mul_ps(a, b);
}
RLD_AVX2_INLINE __m256 add(__m256 a, __m256 b) {
  return _mm256_add_ps(a, b);
}
RLD_AVX2_INLINE __m256 sub(__m256 a, __m256 b) {
  return _mm256_sub_ps(a, b);
}

// z of eight interleaved points (x, y, z) starting at p.
RLD_AVX2_INLINE __m256 loadZ8(const float* p) {
  const __m256 a = _mm256_loadu_ps(p), b = _mm256_loadu_ps(p + 8), c = _mm256_loadu_ps(p + 16);
  // lanes 0,3,6 from b, 1,4,7 from c, 2,5 from a: [b0 c1 a2 b3 c4 a5 b6 c7]
  const __m256 m = _mm256_blend_ps(_mm256_blend_ps(a, b, 0x49), c, 0x92);
  return _mm256_permutevar8x32_ps(m, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
}

// moments() for eight adjacent x: the value at offset d is at p + d * stride.
template <int H, bool kSecond = false>
RLD_AVX2_INLINE void moments8(const float* p, std::ptrdiff_t stride, __m256& box, __m256& m1,
                              __m256* m2 = nullptr) {
  box = _mm256_loadu_ps(p);
  m1 = _mm256_setzero_ps();
  __m256 second = _mm256_setzero_ps();
  for (int d = 1; d <= H; ++d) {
    const __m256 a0 = _mm256_loadu_ps(p + d * stride), b0 = _mm256_loadu_ps(p - d * stride);
    const __m256 a = add(a0, b0);
    box = add(box, a);
    m1 = add(m1, mul(_mm256_set1_ps(static_cast<float>(d)), sub(a0, b0)));
    if (kSecond) second = add(second, mul(_mm256_set1_ps(static_cast<float>(d * d)), a));
  }
  if (kSecond) *m2 = second;
}

// moments8() over separate rows: the value at offset d is at rows[H + d] + off.
template <int H, bool kSecond = false>
RLD_AVX2_INLINE void moments8Rows(const float* const* rows, std::ptrdiff_t off, __m256& box,
                                  __m256& m1, __m256* m2 = nullptr) {
  box = _mm256_loadu_ps(rows[H] + off);
  m1 = _mm256_setzero_ps();
  __m256 second = _mm256_setzero_ps();
  for (int d = 1; d <= H; ++d) {
    const __m256 a0 = _mm256_loadu_ps(rows[H + d] + off), b0 = _mm256_loadu_ps(rows[H - d] + off);
    const __m256 a = add(a0, b0);
    box = add(box, a);
    m1 = add(m1, mul(_mm256_set1_ps(static_cast<float>(d)), sub(a0, b0)));
    if (kSecond) second = add(second, mul(_mm256_set1_ps(static_cast<float>(d * d)), a));
  }
  if (kSecond) *m2 = second;
}

// Prepared row (kv, t, c and z itself), eight pixels per step; bit b of bad: block b has
// invalid pixels.
__attribute__((target("avx2"))) void prepareAvx2(const float* p, const float* k, int n, float* kv,
                                                 float* t, float* c, float* zs, uint64_t* bad,
                                                 int& done) {
  const __m256 zero = _mm256_setzero_ps(), inf = _mm256_set1_ps(kInf), one = _mm256_set1_ps(1.f);
  int x = 0;
  for (; x + 8 <= n; x += 8) {
    const __m256 z = loadZ8(p + 3 * x), kk = _mm256_loadu_ps(k + x);
    _mm256_storeu_ps(zs + x, z);
    const __m256 valid =
        _mm256_and_ps(_mm256_cmp_ps(z, zero, _CMP_GT_OQ), _mm256_cmp_ps(z, inf, _CMP_LT_OQ));
    _mm256_storeu_ps(kv + x, _mm256_and_ps(valid, kk));
    _mm256_storeu_ps(t + x,
                     _mm256_and_ps(valid, _mm256_div_ps(kk, _mm256_blendv_ps(one, z, valid))));
    _mm256_storeu_ps(c + x, _mm256_and_ps(valid, one));
    if (_mm256_movemask_ps(valid) != 0xFF) bad[x / 512] |= uint64_t{1} << (x / 8 % 64);
  }
  done = x;
}

// Vertical sums of eight columns: rows[H + d] holds the prepared row at offset d (planes kv, t,
// c at 0, W, 2 W). The kv and c moments are only needed near missing pixels (bit b of holes for
// block b).
template <int H>
__attribute__((target("avx2"))) void verticalAvx2(const float* const* rows, int W,
                                                  const uint64_t* holes, float* const* out,
                                                  int& done) {
  int x = 0;
  for (; x + 8 <= W; x += 8) {
    __m256 w0, w1, n, n1, n2;
    moments8Rows<H>(rows, W + x, w0, w1);
    _mm256_storeu_ps(out[kW0] + x, w0);
    _mm256_storeu_ps(out[kW1] + x, w1);
    if (!(holes[x / 512] >> (x / 8 % 64) & 1)) {
      moments8Rows<H>(rows, 2 * W + x, n, n1);
      _mm256_storeu_ps(out[kC] + x, n);
      continue;
    }
    __m256 v0, v1, v2;
    moments8Rows<H, true>(rows, 2 * W + x, n, n1, &n2);
    moments8Rows<H, true>(rows, x, v0, v1, &v2);
    _mm256_storeu_ps(out[kC] + x, n);
    _mm256_storeu_ps(out[kCv1] + x, n1);
    _mm256_storeu_ps(out[kCv2] + x, n2);
    _mm256_storeu_ps(out[kV0] + x, v0);
    _mm256_storeu_ps(out[kV1] + x, v1);
    _mm256_storeu_ps(out[kV2] + x, v2);
  }
  done = x;
}

// Horizontal sums, solve and G of eight pixels per step, the scalar code's operations lane for
// lane. Bit b of holes: missing pixels within reach of block b's windows. Windows without missing
// pixels use the precomputed adj(Q) (table planes at table[j] + x),
// the others solvePartial(), whose ill-conditioned columns are appended to `slow` for the exact
// double path (their G is written there). Normals (rarely wanted) are finished by the scalar
// code from the same n'.
template <int H>
__attribute__((target("avx2"))) void horizontalAvx2(
    const float* const* vert, const float* const* table, int n, const float* ncols, const float* ax,
    const RowConst& rc, const float* prow, const float* zrow, float* nrow, float* grow,
    const uint64_t* holes, int* slow, int& n_slow, int& done) {
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.f), three = _mm256_set1_ps(3.f);
  const __m256 inf = _mm256_set1_ps(kInf), ninf = _mm256_set1_ps(-kInf);
  const __m256 abs_mask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7FFFFFFF));
  const __m256 fxs = _mm256_set1_ps(rc.fxs), fys = _mm256_set1_ps(rc.fys),
               ay = _mm256_set1_ps(rc.ay), full_rows = _mm256_set1_ps(rc.full_rows);
  const __m256 u0 = _mm256_set1_ps(rc.up[0]), u1 = _mm256_set1_ps(rc.up[1]),
               u2 = _mm256_set1_ps(rc.up[2]);
  const __m256 alpha = _mm256_set1_ps(rc.alpha), beta = _mm256_set1_ps(rc.beta),
               td = _mm256_set1_ps(rc.td), inv_td = _mm256_set1_ps(rc.inv_td),
               row_term = _mm256_set1_ps(rc.row_term);
  int x = 0;
  for (; x + 8 <= n; x += 8) {
    __m256 T0, Tu, Tv, N = zero, unused;
    moments8<H>(vert[kW0] + x, 1, T0, Tu);
    moments8<H>(vert[kW1] + x, 1, Tv, unused);
    // without missing pixels in the rows every window is whole
    __m256 whole = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    const bool holed = holes[x / 512] >> (x / 8 % 64) & 1;
    if (holed) {
      moments8<H>(vert[kC] + x, 1, N, unused);
      whole = _mm256_cmp_ps(N, mul(_mm256_loadu_ps(ncols + x), full_rows), _CMP_EQ_OQ);
    }
    __m256 ok = whole;  // whole windows have at least 4 pixels
    __m256 a[6];
    for (int j = 0; j < 6; ++j) a[j] = _mm256_loadu_ps(table[j] + x);
    __m256 m0 = add(add(mul(a[0], T0), mul(a[1], Tu)), mul(a[2], Tv));
    __m256 m1 = add(add(mul(a[1], T0), mul(a[3], Tu)), mul(a[4], Tv));
    __m256 m2 = add(add(mul(a[2], T0), mul(a[4], Tu)), mul(a[5], Tv));
    const bool some =
        holed && _mm256_movemask_ps(_mm256_andnot_ps(whole, _mm256_cmp_ps(N, three, _CMP_GE_OQ)));
    if (some) {
      // windows with 3 or more valid pixels, some missing: solvePartial(), lane for lane
      __m256 K0, Ku, Kuu, Kv, Kuv, Kvv, Cu1, Cu2, Cb1, Cb2, unused;
      moments8<H, true>(vert[kV0] + x, 1, K0, Ku, &Kuu);
      moments8<H>(vert[kV1] + x, 1, Kv, Kuv);
      moments8<H>(vert[kV2] + x, 1, Kvv, unused);
      moments8<H, true>(vert[kC] + x, 1, N, Cu1, &Cu2);
      moments8<H>(vert[kCv1] + x, 1, Cb1, unused);
      moments8<H>(vert[kCv2] + x, 1, Cb2, unused);
      const __m256 span = _mm256_and_ps(
          _mm256_cmp_ps(N, three, _CMP_GE_OQ),
          _mm256_and_ps(_mm256_cmp_ps(sub(mul(N, Cu2), mul(Cu1, Cu1)), zero, _CMP_GT_OQ),
                        _mm256_cmp_ps(sub(mul(N, Cb2), mul(Cb1, Cb1)), zero, _CMP_GT_OQ)));
      const __m256 a00 = sub(mul(Kuu, Kvv), mul(Kuv, Kuv));
      const __m256 a01 = sub(mul(Kuv, Kv), mul(Ku, Kvv));
      const __m256 a02 = sub(mul(Ku, Kuv), mul(Kuu, Kv));
      const __m256 a11 = sub(mul(K0, Kvv), mul(Kv, Kv));
      const __m256 a12 = sub(mul(Ku, Kv), mul(K0, Kuv));
      const __m256 a22 = sub(mul(K0, Kuu), mul(Ku, Ku));
      const __m256 det = add(add(mul(K0, a00), mul(Ku, a01)), mul(Kv, a02));
      const __m256 well = _mm256_cmp_ps(
          det, mul(_mm256_set1_ps(kWellConditioned), mul(mul(K0, Kuu), Kvv)), _CMP_GT_OQ);
      const __m256 part = _mm256_andnot_ps(whole, span);
      const int exact = _mm256_movemask_ps(_mm256_andnot_ps(well, part));
      for (int i = 0; i < 8; ++i)
        if (exact >> i & 1) slow[n_slow++] = x + i;
      const __m256 p0 = add(add(mul(a00, T0), mul(a01, Tu)), mul(a02, Tv));
      const __m256 p1 = add(add(mul(a01, T0), mul(a11, Tu)), mul(a12, Tv));
      const __m256 p2 = add(add(mul(a02, T0), mul(a12, Tu)), mul(a22, Tv));
      m0 = _mm256_blendv_ps(p0, m0, whole);
      m1 = _mm256_blendv_ps(p1, m1, whole);
      m2 = _mm256_blendv_ps(p2, m2, whole);
      ok = _mm256_or_ps(whole, _mm256_and_ps(part, well));
    } else if (holed) {
      ok = whole;  // the others have fewer than 3 valid pixels
    }
    const __m256 n0 = mul(fxs, m1), n1 = mul(fys, m2);
    const __m256 n2 = sub(sub(m0, mul(_mm256_loadu_ps(ax + x), n0)), mul(ay, n1));
    if (nrow) {
      alignas(32) float b0[8], b1[8], b2[8], okf[8];
      _mm256_store_ps(b0, n0);
      _mm256_store_ps(b1, n1);
      _mm256_store_ps(b2, n2);
      _mm256_store_ps(okf, ok);
      for (int i = 0; i < 8; ++i) {
        const float nn[3] = {b0[i], b1[i], b2[i]};
        uint32_t bits;
        std::memcpy(&bits, &okf[i], 4);
        finish(nn, bits != 0, prow + 3 * (x + i), ax[x + i], rc, nrow + 3 * (x + i),
               grow ? grow + x + i : nullptr);
      }
      continue;
    }
    const __m256 len2 = add(add(mul(n0, n0), mul(n1, n1)), mul(n2, n2));
    ok = _mm256_and_ps(ok, _mm256_and_ps(_mm256_cmp_ps(len2, zero, _CMP_GT_OQ),
                                         _mm256_cmp_ps(len2, inf, _CMP_LT_OQ)));
    const __m256 inv_len = _mm256_div_ps(one, _mm256_sqrt_ps(_mm256_blendv_ps(one, len2, ok)));
    const __m256 nup =
        mul(_mm256_and_ps(abs_mask, add(add(mul(n0, u0), mul(n1, u1)), mul(n2, u2))), inv_len);
    const __m256 normal_term = _mm256_and_ps(ok, nup);
    const __m256 z = _mm256_loadu_ps(zrow + x);
    const __m256 near =
        _mm256_and_ps(_mm256_cmp_ps(z, td, _CMP_LE_OQ), _mm256_cmp_ps(z, ninf, _CMP_GT_OQ));
    const __m256 depth_term = rc.near_high ? mul(sub(td, z), inv_td) : mul(z, inv_td);
    _mm256_storeu_ps(grow + x, add(mul(alpha, normal_term),
                                   mul(beta, _mm256_blendv_ps(row_term, depth_term, near))));
  }
  done = x;
}
#endif

}  // namespace

struct FalsNormals::Output {
  cv::Mat* normals = nullptr;
  cv::Mat* G = nullptr;
  RowConst base;  ///< G constants (row fields are filled per row)
};

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

  src_u_.resize(W);
  src_v_.resize(H);
  ax_.resize(W);
  ay_.resize(H);
  for (int x = 0; x < W; ++x) {
    src_u_[x] = col_map_.empty() ? x : col_map_.at<int>(x);
    ax_[x] = static_cast<float>((src_u_[x] - K.cx) / K.fx);
  }
  for (int y = 0; y < H; ++y) {
    src_v_[y] = row_map_.empty() ? y : row_map_.at<int>(y);
    ay_[y] = static_cast<float>((src_v_[y] - K.cy) / K.fy);
  }
  // The separable path needs equally spaced source pixels (x -> a + step x).
  auto uniform = [](const std::vector<int>& m, float& step) {
    step = m.size() > 1 ? static_cast<float>(m[1] - m[0]) : 1.f;
    for (size_t i = 1; i < m.size(); ++i)
      if (m[i] - m[i - 1] != m[1] - m[0]) return false;
    return step > 0.f;
  };
  uniform_ = uniform(src_u_, step_u_) & uniform(src_v_, step_v_);

  rays_.create(size, CV_32FC3);
  k_.create(size, CV_32FC1);
  for (int y = 0; y < H; ++y) {
    const double ry = (src_v_[y] - K.cy) / K.fy;
    float* ray = rays_.ptr<float>(y);
    float* k = k_.ptr<float>(y);
    for (int x = 0; x < W; ++x, ray += 3) {
      const double rx = (src_u_[x] - K.cx) / K.fx;
      const double w2 = rx * rx + ry * ry + 1.0;
      const double inv = 1.0 / std::sqrt(w2);
      ray[0] = static_cast<float>(rx * inv);
      ray[1] = static_cast<float>(ry * inv);
      ray[2] = static_cast<float>(inv);
      k[x] = static_cast<float>(1.0 / w2);
    }
  }
  ncols_.resize(W);
  for (int x = 0; x < W; ++x)
    ncols_[x] = static_cast<float>(std::min(W - 1, x + h) - std::max(0, x - h) + 1);

  // adj(Q) of every window without missing pixels (clipped by the image), in double: moments of
  // k over offsets in processing pixels (the source step is folded into fx / step, fy / step).
  if (uniform_) {
    table_.create(6 * H, W, CV_32FC1);
    std::vector<double> vk(3 * static_cast<size_t>(W));
    for (int y = 0; y < H; ++y) {
      std::fill(vk.begin(), vk.end(), 0.0);
      for (int dv = -h; dv <= h; ++dv) {
        if (y + dv < 0 || y + dv >= H) continue;
        const float* k = k_.ptr<float>(y + dv);
        for (int x = 0; x < W; ++x) {
          vk[3 * x] += k[x];
          vk[3 * x + 1] += dv * static_cast<double>(k[x]);
          vk[3 * x + 2] += dv * dv * static_cast<double>(k[x]);
        }
      }
      for (int x = 0; x < W; ++x) {
        double K0 = 0, Ku = 0, Kv = 0, Kuu = 0, Kuv = 0, Kvv = 0;
        for (int du = -h; du <= h; ++du) {
          if (x + du < 0 || x + du >= W) continue;
          const double* v = &vk[3 * (x + du)];
          K0 += v[0];
          Ku += du * v[0];
          Kuu += du * du * v[0];
          Kv += v[1];
          Kuv += du * v[1];
          Kvv += v[2];
        }
        const double a[6] = {Kuu * Kvv - Kuv * Kuv, Kuv * Kv - Ku * Kvv, Ku * Kuv - Kuu * Kv,
                             K0 * Kvv - Kv * Kv,    Ku * Kv - K0 * Kuv,  K0 * Kuu - Ku * Ku};
        for (int j = 0; j < 6; ++j) table_.ptr<float>(j * H + y)[x] = static_cast<float>(a[j]);
      }
    }
  } else {
    table_.release();
  }
  prep_.create(4 * (2 * h + 1), W, CV_32FC1);
  vert_.create(kPlanes, W + 2 * h, CV_32FC1);
  vert_.setTo(0);  // the h columns each side stay 0: outside the image
  slow_.resize(W);
  column_.resize(kColumnSums * static_cast<size_t>(W));
  column_row_.assign(W, -1);
}

void FalsNormals::prepareRow(const cv::Mat& points, int y, float* kv, float* t, float* c, float* z,
                             uint64_t* bad) const {
  const int W = size_.width;
  std::fill(bad, bad + (W + 511) / 512, uint64_t{0});
  if (y < 0 || y >= size_.height) {  // outside the image: clipped windows, not holes
    std::fill(kv, kv + W, 0.f);
    std::fill(t, t + W, 0.f);
    std::fill(c, c + W, 0.f);
    std::fill(z, z + W, kNaN);
    return;
  }
  const float* p = points.ptr<float>(y);
  const float* k = k_.ptr<float>(y);
  int x = 0;
#ifdef RLD_FALS_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) prepareAvx2(p, k, W, kv, t, c, z, bad, x);
#endif
  for (; x < W; ++x) {
    const float d = z[x] = p[3 * x + 2];
    const bool valid = d > 0.f && d < kInf;
    kv[x] = valid ? k[x] : 0.f;
    t[x] = valid ? k[x] / d : 0.f;
    c[x] = valid ? 1.f : 0.f;
    if (!valid) bad[x / 512] |= uint64_t{1} << (x / 8 % 64);
  }
}

bool FalsNormals::solveWindow(int x, int y, const float* const* kv, const float* const* t,
                              const float* const* c, float n[3]) {
  // Q and s over the valid pixels, in double: a window with missing pixels can leave a thin
  // crescent of valid pixels whose Q is far from diagonal. Offsets are in source pixels. Column
  // sums (moments in the row offset) are cached per row, as neighbouring windows share them.
  const int W = size_.width, H = size_.height, h = window_ / 2;
  for (int xx = std::max(0, x - h); xx <= std::min(W - 1, x + h); ++xx) {
    if (column_row_[xx] == y) continue;
    column_row_[xx] = y;
    double* v = &column_[kColumnSums * xx];
    std::fill(v, v + kColumnSums, 0.0);
    for (int dv = -h; dv <= h; ++dv) {
      if (y + dv < 0 || y + dv >= H || c[h + dv][xx] == 0.f) continue;
      const double fv = src_v_[y + dv] - src_v_[y], k = kv[h + dv][xx], tt = t[h + dv][xx];
      v[0] += k;
      v[1] += k * fv;
      v[2] += k * fv * fv;
      v[3] += tt;
      v[4] += tt * fv;
      v[5] += 1.0;
      v[6] += fv;
      v[7] += fv * fv;
    }
  }
  double K0 = 0, Ku = 0, Kv = 0, Kuu = 0, Kuv = 0, Kvv = 0, T0 = 0, Tu = 0, Tv = 0;
  double N = 0, Nu = 0, Nuu = 0, Nv = 0, Nvv = 0;
  for (int xx = std::max(0, x - h); xx <= std::min(W - 1, x + h); ++xx) {
    const double* v = &column_[kColumnSums * xx];
    const double fu = src_u_[xx] - src_u_[x];
    K0 += v[0];
    Ku += fu * v[0];
    Kuu += fu * fu * v[0];
    Kv += v[1];
    Kuv += fu * v[1];
    Kvv += v[2];
    T0 += v[3];
    Tu += fu * v[3];
    Tv += v[4];
    N += v[5];
    Nu += fu * v[5];
    Nuu += fu * fu * v[5];
    Nv += v[6];
    Nvv += v[7];
  }
  // fewer than 3 valid pixels, or (some missing) all in one column or one row (zero variance of
  // their offsets; exact, the sums are small integers): no normal
  const double full =
      static_cast<double>(ncols_[x]) * (std::min(H - 1, y + h) - std::max(0, y - h) + 1);
  if (N < 3.0 || (N < full && (N * Nuu - Nu * Nu <= 0.0 || N * Nvv - Nv * Nv <= 0.0))) return false;
  const double a00 = Kuu * Kvv - Kuv * Kuv, a01 = Kuv * Kv - Ku * Kvv, a02 = Ku * Kuv - Kuu * Kv;
  const double a11 = K0 * Kvv - Kv * Kv, a12 = Ku * Kv - K0 * Kuv, a22 = K0 * Kuu - Ku * Ku;
  const double m0 = a00 * T0 + a01 * Tu + a02 * Tv, m1 = a01 * T0 + a11 * Tu + a12 * Tv,
               m2 = a02 * T0 + a12 * Tu + a22 * Tv;
  const double n0 = K_.fx * m1, n1 = K_.fy * m2;
  const double n2 = m0 - ax_[x] * n0 - ay_[y] * n1;
  // to unit length before rounding to float (det Q can be tiny)
  const double len = std::sqrt(n0 * n0 + n1 * n1 + n2 * n2);
  if (!(len > 0.0) || !std::isfinite(len)) return false;
  n[0] = static_cast<float>(n0 / len);
  n[1] = static_cast<float>(n1 / len);
  n[2] = static_cast<float>(n2 / len);
  return true;
}

void FalsNormals::compute(const cv::Mat& points, const cv::Range& rows, cv::Mat& normals) {
  CV_Assert(points.type() == CV_32FC3 && points.size() == size_ && window_ > 0);
  normals.create(size_, CV_32FC3);
  Output out;
  out.normals = &normals;
  run(points, rows, out);
}

void FalsNormals::computeGeometric(const cv::Mat& points, const cv::Range& rows, const Params& p,
                                   cv::Mat& G, cv::Mat* normals) {
  CV_Assert(points.type() == CV_32FC3 && points.size() == size_ && window_ > 0);
  if (G.size() != size_ || G.type() != CV_32FC1) {
    G.create(size_, CV_32FC1);
    G.setTo(0);
  }
  if (normals) normals->create(size_, CV_32FC3);
  Output out;
  out.G = &G;
  out.normals = normals;
  RowConst& rc = out.base;
  rc.alpha = static_cast<float>(p.alpha);
  rc.beta = static_cast<float>(p.beta);
  rc.td = static_cast<float>(p.depth_threshold);
  rc.inv_td = static_cast<float>(1.0 / p.depth_threshold);
  rc.near_high = p.depth_term == DepthTerm::kNearHigh;
  rc.up[0] = static_cast<float>(p.up_x);
  rc.up[1] = static_cast<float>(p.up_y);
  rc.up[2] = static_cast<float>(p.up_z);
  run(points, rows, out);
}

void FalsNormals::run(const cv::Mat& points, const cv::Range& rows, const Output& out) {
  const int W = size_.width, H = size_.height, h = window_ / 2, span = 2 * h + 1;
  const int r0 = std::max(rows.start, 0), r1 = std::min(rows.end, H);
  if (r0 >= r1) return;
#ifdef RLD_FALS_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2");
#endif

  // Ring of prepared rows (planes kv, t, c, z), row r in slot r mod span.
  auto slot = [&](int r) { return prep_.ptr<float>(4 * (((r % span) + span) % span)); };
  // per 8-pixel block: invalid pixels in a prepared row (bad_), near the windows of a block
  // (blocks within 1 for the horizontal pass, within 2 for the vertical sums it reads)
  const int nw = (W + 511) / 512;  // 64-bit words of block bits
  bad_.resize(static_cast<size_t>(span) * nw);
  near_.resize(3 * static_cast<size_t>(nw));
  auto prepare = [&](int r) {
    float* a = slot(r);
    const int i = ((r % span) + span) % span;
    prepareRow(points, r, a, a + W, a + 2 * W, a + 3 * W, &bad_[static_cast<size_t>(i) * nw]);
  };
  for (int r = r0 - h; r < r0 + h; ++r) prepare(r);
  std::fill(column_row_.begin(), column_row_.end(), -1);

  float* vert[kPlanes];
  for (int k = 0; k < kPlanes; ++k) vert[k] = vert_.ptr<float>(k) + h;
  const float* kv_rows[7];  // rows y - h .. y + h: plane kv, then t at + W, c at + 2 W
  const float* t_rows[7];
  const float* c_rows[7];

  for (int y = r0; y < r1; ++y) {
    prepare(y + h);
    for (int d = -h; d <= h; ++d) {
      kv_rows[d + h] = slot(y + d);
      t_rows[d + h] = slot(y + d) + W;
      c_rows[d + h] = slot(y + d) + 2 * W;
    }
    RowConst rc = out.base;
    rc.ay = ay_[y];
    rc.fxs = static_cast<float>(K_.fx) / step_u_;
    rc.fys = static_cast<float>(K_.fy) / step_v_;
    rc.full_rows = static_cast<float>(std::min(H - 1, y + h) - std::max(0, y - h) + 1);
    rc.row_term = static_cast<float>(static_cast<double>(y) / H);
    const float* prow = points.ptr<float>(y);
    float* nrow = out.normals ? out.normals->ptr<float>(y) : nullptr;
    float* grow = out.G ? out.G->ptr<float>(y) : nullptr;
    // the exact path: normals already of unit length
    auto exact = [&](int x) {
      float n[3] = {0.f, 0.f, 0.f};
      const bool ok = solveWindow(x, y, kv_rows, t_rows, c_rows, n);
      finish(n, ok, prow + 3 * x, ax_[x], rc, nrow ? nrow + 3 * x : nullptr,
             grow ? grow + x : nullptr);
    };

    // resampled at an uneven step (no separable sums), or the reference: every window exactly
    if (!uniform_ || referenceStages()) {
      for (int x = 0; x < W; ++x) exact(x);
      continue;
    }

    // vertical sums of this row (the k and count moments only where pixels are missing)
    uint64_t* band = near_.data();
    uint64_t* near_h = band + nw;      // bad blocks within 1: the horizontal pass
    uint64_t* near_v = band + 2 * nw;  // within 2: the vertical sums it reads
    for (int j = 0; j < nw; ++j) {
      band[j] = 0;
      for (int i = 0; i < span; ++i) band[j] |= bad_[static_cast<size_t>(i) * nw + j];
    }
    auto shifted = [&](int j, int d) {  // bit b: block b + d
      if (d > 0) return (band[j] >> d) | (j + 1 < nw ? band[j + 1] << (64 - d) : 0);
      return (band[j] << -d) | (j > 0 ? band[j - 1] >> (64 + d) : 0);
    };
    for (int j = 0; j < nw; ++j) {
      near_h[j] = band[j] | shifted(j, 1) | shifted(j, -1);
      near_v[j] = near_h[j] | shifted(j, 2) | shifted(j, -2);
    }
    int x = 0;
#ifdef RLD_FALS_AVX2
    if (avx2) {
      if (h == 1) verticalAvx2<1>(kv_rows, W, near_v, vert, x);
      if (h == 2) verticalAvx2<2>(kv_rows, W, near_v, vert, x);
      if (h == 3) verticalAvx2<3>(kv_rows, W, near_v, vert, x);
    }
#endif
    for (; x < W; ++x) {
      float unused;
      momentsRows(t_rows, x, h, vert[kW0][x], vert[kW1][x], unused);
      momentsRows(c_rows, x, h, vert[kC][x], vert[kCv1][x], vert[kCv2][x]);
      momentsRows(kv_rows, x, h, vert[kV0][x], vert[kV1][x], vert[kV2][x]);
    }

    // horizontal sums, solve and outputs; ill-conditioned windows go to the exact path
    const float* table[6];
    for (int j = 0; j < 6; ++j) table[j] = table_.ptr<float>(j * H + y);
    int n_slow = 0;
    x = 0;
#ifdef RLD_FALS_AVX2
    if (avx2) {
      const float* const* v = vert;
      const float *nc = ncols_.data(), *ax = ax_.data();
      int* sl = slow_.data();
      float* g = grow;
      const uint64_t* nh = near_h;
      const float* z = kv_rows[h] + 3 * W;
      if (h == 1) horizontalAvx2<1>(v, table, W, nc, ax, rc, prow, z, nrow, g, nh, sl, n_slow, x);
      if (h == 2) horizontalAvx2<2>(v, table, W, nc, ax, rc, prow, z, nrow, g, nh, sl, n_slow, x);
      if (h == 3) horizontalAvx2<3>(v, table, W, nc, ax, rc, prow, z, nrow, g, nh, sl, n_slow, x);
    }
#endif
    for (; x < W; ++x) {
      float T0, Tu, Tv, N, unused;
      moments(vert[kW0] + x, 1, h, T0, Tu, unused);
      moments(vert[kW1] + x, 1, h, Tv, unused, unused);
      moments(vert[kC] + x, 1, h, N, unused, unused);
      float n[3];
      bool ok = true;
      if (N == ncols_[x] * rc.full_rows) {
        const float a[6] = {table[0][x], table[1][x], table[2][x],
                            table[3][x], table[4][x], table[5][x]};
        solveTable(a, T0, Tu, Tv, ax_[x], rc, n);
      } else {
        Partial q;
        moments(vert[kV0] + x, 1, h, q.K0, q.Ku, q.Kuu);
        moments(vert[kV1] + x, 1, h, q.Kv, q.Kuv, unused);
        moments(vert[kV2] + x, 1, h, q.Kvv, unused, unused);
        moments(vert[kC] + x, 1, h, q.N, q.Cu1, q.Cu2);
        moments(vert[kCv1] + x, 1, h, q.Cb1, unused, unused);
        moments(vert[kCv2] + x, 1, h, q.Cb2, unused, unused);
        const PartialCase pc = solvePartial(q, T0, Tu, Tv, ax_[x], rc, n);
        if (pc == PartialCase::kExact) {
          slow_[n_slow++] = x;
          continue;
        }
        ok = pc == PartialCase::kFloat;
      }
      finish(n, ok, prow + 3 * x, ax_[x], rc, nrow ? nrow + 3 * x : nullptr,
             grow ? grow + x : nullptr);
    }
    for (int i = 0; i < n_slow; ++i) exact(slow_[i]);
  }
}

}  // namespace rgbd_lane_detector
