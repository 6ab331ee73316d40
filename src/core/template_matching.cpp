#include "rgbd_lane_detector/template_matching.h"

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstring>

#include <opencv2/imgproc.hpp>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

// Plain loops are compiled for AVX-512, AVX2 and the baseline, chosen at load time; integer sums
// are exact, so every clone gives the same bits. Not under ThreadSanitizer: the clones' IFUNC
// resolver would run, instrumented, before the TSan runtime is initialised.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__SANITIZE_THREAD__)
#define RLD_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define RLD_CLONES
#endif

namespace rgbd_lane_detector {
namespace {

// Zero a rectangle of a map row by row (cv::Mat::setTo allocates a scratch buffer per call).
void zero(cv::Mat& m, const cv::Rect& r) {
  if (r.width <= 0 || r.height <= 0) return;
  for (int y = r.y; y < r.br().y; ++y)
    std::memset(m.ptr<uint8_t>(y) + r.x * m.elemSize(), 0, r.width * m.elemSize());
}

// acc[x] (+)= sum of (plus_i[x] - minus_i[x]) over 1, 2 or 4 pairs, all mod 2^32.
RLD_CLONES void pairs1(uint32_t* acc, bool add, const uint32_t* a, const uint32_t* b, int n) {
  if (add)
    for (int x = 0; x < n; ++x) acc[x] += a[x] - b[x];
  else
    for (int x = 0; x < n; ++x) acc[x] = a[x] - b[x];
}
RLD_CLONES void pairs2(uint32_t* acc, bool add, const uint32_t* a, const uint32_t* b,
                       const uint32_t* c, const uint32_t* d, int n) {
  if (add)
    for (int x = 0; x < n; ++x) acc[x] += (a[x] - b[x]) + (c[x] - d[x]);
  else
    for (int x = 0; x < n; ++x) acc[x] = (a[x] - b[x]) + (c[x] - d[x]);
}
RLD_CLONES void pairs4(uint32_t* acc, bool add, const uint32_t* const* p, const uint32_t* const* m,
                       int n) {
  const uint32_t *a = p[0], *b = m[0], *c = p[1], *d = m[1], *e = p[2], *f = m[2], *g = p[3],
                 *h = m[3];
  if (add)
    for (int x = 0; x < n; ++x)
      acc[x] += ((a[x] - b[x]) + (c[x] - d[x])) + ((e[x] - f[x]) + (g[x] - h[x]));
  else
    for (int x = 0; x < n; ++x)
      acc[x] = ((a[x] - b[x]) + (c[x] - d[x])) + ((e[x] - f[x]) + (g[x] - h[x]));
}

void accumulate(uint32_t* acc, const uint32_t* const* plus, const uint32_t* const* minus, int pairs,
                int n) {
  if (pairs == 0) {
    std::fill(acc, acc + n, 0u);
    return;
  }
  int i = 0;
  for (; i + 4 <= pairs; i += 4) pairs4(acc, i > 0, plus + i, minus + i, n);
  if (i + 2 <= pairs) {
    pairs2(acc, i > 0, plus[i], minus[i], plus[i + 1], minus[i + 1], n);
    i += 2;
  }
  if (i < pairs) pairs1(acc, i > 0, plus[i], minus[i], n);
}

/// One new image row: its prefix sums P(X) = sum of src[0, X) extend the integral images
/// (new = old + P) and the running sums along each slope (new(X) = P(X) + older(X - p)) over
/// the columns X in [1, w]; column 0 and the margins are done by the caller.
struct RowUpdate {
  const uint8_t* src;
  int w;
  const uint32_t* ii_old;
  uint32_t* ii_new;
  const uint32_t* sq_old;
  uint32_t* sq_new;
  int tables;
  const uint32_t* e_old[2];  ///< already shifted by -p: e_new[X] = P[X] + e_old[X]
  uint32_t* e_new[2];
};

// Scalar columns [c, w) continuing from the prefix values a (of I) and b (of I^2).
inline uint32_t updateTail(const RowUpdate& u, int c, uint32_t a, uint32_t b) {
  for (; c < u.w; ++c) {
    a += u.src[c];
    b += static_cast<uint32_t>(u.src[c]) * u.src[c];
    const int X = c + 1;
    u.ii_new[X] = u.ii_old[X] + a;
    u.sq_new[X] = u.sq_old[X] + b;
    for (int t = 0; t < u.tables; ++t) u.e_new[t][X] = u.e_old[t][X] + a;
  }
  return a;
}

/// Inputs of one output row of scores.
struct ScoreRow {
  const uint32_t* acc[2];  ///< template correlations (sum of I over the line)
  const uint32_t* top;     ///< integral row at the window top, column x
  const uint32_t* bottom;  ///< integral row below the window
  const uint32_t* top_sq;  ///< same for the squares
  const uint32_t* bottom_sq;
  int s;     ///< template side: window columns x .. x + s
  int area;  ///< s * s
  double inv_area;
  int count[2];  ///< line pixels of each template
  float k[2];    ///< 1 / (area |T - mean T|), T in {0, 1}
  float* out[2];
};

// One pixel, the definition every vector lane follows operation for operation:
// diff2 = sum2 - sum^2 / area (exact in double, as OpenCV evaluates it); OpenCV's flat rule
// diff2 <= min(0.5, 10 FLT_EPSILON sum2) scores 0; otherwise with the exact integer
// N = area acc - count sum = area sum (I - mean I)(T - mean T),
// score = N / (area |I - mean I| |T - mean T|), clamped to [0, 1].
inline void scorePixel(const ScoreRow& r, int x) {
  const int32_t S =
      static_cast<int32_t>((r.bottom[x + r.s] - r.bottom[x]) - (r.top[x + r.s] - r.top[x]));
  const int32_t Q = static_cast<int32_t>((r.bottom_sq[x + r.s] - r.bottom_sq[x]) -
                                         (r.top_sq[x + r.s] - r.top_sq[x]));
  const double sum = S, sum2 = Q;
  const double diff2 = sum2 - sum * sum * r.inv_area;
  const bool keep = diff2 > std::min(0.5, 10 * FLT_EPSILON * sum2);
  const float inv_sd =
      (1.f / std::sqrt(static_cast<float>(keep ? diff2 : 1.0))) * (keep ? 1.f : 0.f);
  for (int k = 0; k < 2; ++k) {
    const int64_t N = static_cast<int64_t>(r.area) * static_cast<int32_t>(r.acc[k][x]) -
                      static_cast<int64_t>(r.count[k]) * S;
    const float v = static_cast<float>(N) * (inv_sd * r.k[k]);
    r.out[k][x] = std::max(std::min(v, 1.f), 0.f);
  }
}

#if defined(__SSE2__)
// Prefix sums by in-register scans, four columns per step (SSE2, the x86-64 baseline).
// Returns P(w).
uint32_t updateRowSse2(const RowUpdate& u) {
  const __m128i zero = _mm_setzero_si128();
  __m128i carry = zero, carry2 = zero;
  int c = 0;
  for (; c + 4 <= u.w; c += 4) {
    int32_t word;
    std::memcpy(&word, u.src + c, 4);
    const __m128i v16 = _mm_unpacklo_epi8(_mm_cvtsi32_si128(word), zero);
    __m128i v = _mm_unpacklo_epi16(v16, zero);
    __m128i q = _mm_unpacklo_epi16(_mm_mullo_epi16(v16, v16), zero);  // 255^2 fits 16 bits
    v = _mm_add_epi32(v, _mm_slli_si128(v, 4));
    q = _mm_add_epi32(q, _mm_slli_si128(q, 4));
    v = _mm_add_epi32(_mm_add_epi32(v, _mm_slli_si128(v, 8)), carry);
    q = _mm_add_epi32(_mm_add_epi32(q, _mm_slli_si128(q, 8)), carry2);
    carry = _mm_shuffle_epi32(v, 0xFF);
    carry2 = _mm_shuffle_epi32(q, 0xFF);
    const int X = c + 1;
    auto at = [X](const uint32_t* p) {
      return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + X));
    };
    auto put = [X](uint32_t* p, __m128i x) {
      _mm_storeu_si128(reinterpret_cast<__m128i*>(p + X), x);
    };
    put(u.ii_new, _mm_add_epi32(at(u.ii_old), v));
    put(u.sq_new, _mm_add_epi32(at(u.sq_old), q));
    for (int t = 0; t < u.tables; ++t) put(u.e_new[t], _mm_add_epi32(at(u.e_old[t]), v));
  }
  return updateTail(u, c, static_cast<uint32_t>(_mm_cvtsi128_si32(carry)),
                    static_cast<uint32_t>(_mm_cvtsi128_si32(carry2)));
}

__attribute__((target("avx2"))) inline __m256i load8(const uint32_t* p) {
  return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
}

// The same with AVX2, eight columns per step.
__attribute__((target("avx2"))) uint32_t updateRowAvx2(const RowUpdate& u) {
  __m256i carry = _mm256_setzero_si256(), carry2 = carry;
  const __m256i last = _mm256_set1_epi32(7);
  int c = 0;
  for (; c + 8 <= u.w; c += 8) {
    int64_t word;
    std::memcpy(&word, u.src + c, 8);
    const __m128i v16 = _mm_cvtepu8_epi16(_mm_cvtsi64_si128(word));
    __m256i v = _mm256_cvtepu16_epi32(v16);
    __m256i q = _mm256_cvtepu16_epi32(_mm_mullo_epi16(v16, v16));  // 255^2 fits 16 bits
    // scan inside each 128-bit lane, then carry the low lane's total into the high lane
    v = _mm256_add_epi32(v, _mm256_slli_si256(v, 4));
    q = _mm256_add_epi32(q, _mm256_slli_si256(q, 4));
    v = _mm256_add_epi32(v, _mm256_slli_si256(v, 8));
    q = _mm256_add_epi32(q, _mm256_slli_si256(q, 8));
    const __m256i tv = _mm256_shuffle_epi32(v, 0xFF), tq = _mm256_shuffle_epi32(q, 0xFF);
    v = _mm256_add_epi32(_mm256_add_epi32(v, _mm256_permute2x128_si256(tv, tv, 0x08)), carry);
    q = _mm256_add_epi32(_mm256_add_epi32(q, _mm256_permute2x128_si256(tq, tq, 0x08)), carry2);
    carry = _mm256_permutevar8x32_epi32(v, last);
    carry2 = _mm256_permutevar8x32_epi32(q, last);
    const int X = c + 1;
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(u.ii_new + X),
                        _mm256_add_epi32(load8(u.ii_old + X), v));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(u.sq_new + X),
                        _mm256_add_epi32(load8(u.sq_old + X), q));
    for (int t = 0; t < u.tables; ++t)
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(u.e_new[t] + X),
                          _mm256_add_epi32(load8(u.e_old[t] + X), v));
  }
  return updateTail(u, c, static_cast<uint32_t>(_mm256_cvtsi256_si32(carry)),
                    static_cast<uint32_t>(_mm256_cvtsi256_si32(carry2)));
}

uint32_t updateRow(const RowUpdate& u) {
  return simdLevel() >= 1 ? updateRowAvx2(u) : updateRowSse2(u);
}

// Four pixels with SSE2 (x86-64 baseline).
void scoreRowSse2(const ScoreRow& r, int n) {
  const __m128d inv_area = _mm_set1_pd(r.inv_area), eps = _mm_set1_pd(10 * FLT_EPSILON),
                half = _mm_set1_pd(0.5), one = _mm_set1_pd(1.0), area = _mm_set1_pd(r.area);
  const __m128d count[2] = {_mm_set1_pd(r.count[0]), _mm_set1_pd(r.count[1])};
  const __m128 kk[2] = {_mm_set1_ps(r.k[0]), _mm_set1_ps(r.k[1])};
  const __m128 f_one = _mm_set1_ps(1.f), f_zero = _mm_setzero_ps();
  int x = 0;
  for (; x + 4 <= n; x += 4) {
    auto load = [x](const uint32_t* p) {
      return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + x));
    };
    const __m128i S = _mm_sub_epi32(_mm_sub_epi32(load(r.bottom + r.s), load(r.bottom)),
                                    _mm_sub_epi32(load(r.top + r.s), load(r.top)));
    if (_mm_movemask_epi8(_mm_cmpeq_epi32(S, _mm_setzero_si128())) == 0xFFFF) {
      _mm_storeu_ps(r.out[0] + x, f_zero);  // windows of zeros are flat
      _mm_storeu_ps(r.out[1] + x, f_zero);
      continue;
    }
    const __m128i Q = _mm_sub_epi32(_mm_sub_epi32(load(r.bottom_sq + r.s), load(r.bottom_sq)),
                                    _mm_sub_epi32(load(r.top_sq + r.s), load(r.top_sq)));
    const __m128i A[2] = {load(r.acc[0]), load(r.acc[1])};
    __m128 d_f[2], keep_f[2], num_f[2][2];
    for (int h = 0; h < 2; ++h) {
      const __m128i Sh = h ? _mm_unpackhi_epi64(S, S) : S;
      const __m128i Qh = h ? _mm_unpackhi_epi64(Q, Q) : Q;
      const __m128d sum = _mm_cvtepi32_pd(Sh), sum2 = _mm_cvtepi32_pd(Qh);
      const __m128d diff2 = _mm_sub_pd(sum2, _mm_mul_pd(_mm_mul_pd(sum, sum), inv_area));
      const __m128d keep = _mm_cmpgt_pd(diff2, _mm_min_pd(half, _mm_mul_pd(eps, sum2)));
      d_f[h] = _mm_cvtpd_ps(_mm_or_pd(_mm_and_pd(keep, diff2), _mm_andnot_pd(keep, one)));
      keep_f[h] = _mm_cvtpd_ps(_mm_and_pd(keep, one));
      for (int k = 0; k < 2; ++k) {
        const __m128i Ah = h ? _mm_unpackhi_epi64(A[k], A[k]) : A[k];
        // exact integers below 2^53
        num_f[k][h] = _mm_cvtpd_ps(
            _mm_sub_pd(_mm_mul_pd(area, _mm_cvtepi32_pd(Ah)), _mm_mul_pd(count[k], sum)));
      }
    }
    const __m128 inv_sd = _mm_mul_ps(_mm_div_ps(f_one, _mm_sqrt_ps(_mm_movelh_ps(d_f[0], d_f[1]))),
                                     _mm_movelh_ps(keep_f[0], keep_f[1]));
    for (int k = 0; k < 2; ++k) {
      const __m128 v =
          _mm_mul_ps(_mm_movelh_ps(num_f[k][0], num_f[k][1]), _mm_mul_ps(inv_sd, kk[k]));
      _mm_storeu_ps(r.out[k] + x, _mm_max_ps(_mm_min_ps(v, f_one), f_zero));
    }
  }
  for (; x < n; ++x) scorePixel(r, x);
}

// Eight pixels with AVX2, the same values lane for lane (N is computed in exact 32-bit
// integers, which needs area * acc < 2^31: templates up to 45 px).
__attribute__((target("avx2"))) void scoreRowAvx2(const ScoreRow& r, int n, int from = 0) {
  const __m256d inv_area = _mm256_set1_pd(r.inv_area), eps = _mm256_set1_pd(10 * FLT_EPSILON),
                half = _mm256_set1_pd(0.5), one = _mm256_set1_pd(1.0);
  const __m256i area = _mm256_set1_epi32(r.area);
  const __m256i count[2] = {_mm256_set1_epi32(r.count[0]), _mm256_set1_epi32(r.count[1])};
  const __m256 kk[2] = {_mm256_set1_ps(r.k[0]), _mm256_set1_ps(r.k[1])};
  const __m256 f_one = _mm256_set1_ps(1.f), f_zero = _mm256_setzero_ps();
  int x = from;
  for (; x + 8 <= n; x += 8) {
    const __m256i S =
        _mm256_sub_epi32(_mm256_sub_epi32(load8(r.bottom + r.s + x), load8(r.bottom + x)),
                         _mm256_sub_epi32(load8(r.top + r.s + x), load8(r.top + x)));
    if (_mm256_testz_si256(S, S)) {
      _mm256_storeu_ps(r.out[0] + x, f_zero);  // windows of zeros are flat
      _mm256_storeu_ps(r.out[1] + x, f_zero);
      continue;
    }
    const __m256i Q =
        _mm256_sub_epi32(_mm256_sub_epi32(load8(r.bottom_sq + r.s + x), load8(r.bottom_sq + x)),
                         _mm256_sub_epi32(load8(r.top_sq + r.s + x), load8(r.top_sq + x)));
    __m128 d_f[2], keep_f[2];
    for (int h = 0; h < 2; ++h) {
      const __m128i Sh = h ? _mm256_extracti128_si256(S, 1) : _mm256_castsi256_si128(S);
      const __m128i Qh = h ? _mm256_extracti128_si256(Q, 1) : _mm256_castsi256_si128(Q);
      const __m256d sum = _mm256_cvtepi32_pd(Sh), sum2 = _mm256_cvtepi32_pd(Qh);
      const __m256d diff2 = _mm256_sub_pd(sum2, _mm256_mul_pd(_mm256_mul_pd(sum, sum), inv_area));
      const __m256d keep =
          _mm256_cmp_pd(diff2, _mm256_min_pd(half, _mm256_mul_pd(eps, sum2)), _CMP_GT_OQ);
      d_f[h] = _mm256_cvtpd_ps(_mm256_blendv_pd(one, diff2, keep));
      keep_f[h] = _mm256_cvtpd_ps(_mm256_and_pd(keep, one));
    }
    const __m256 inv_sd =
        _mm256_mul_ps(_mm256_div_ps(f_one, _mm256_sqrt_ps(_mm256_set_m128(d_f[1], d_f[0]))),
                      _mm256_set_m128(keep_f[1], keep_f[0]));
    for (int k = 0; k < 2; ++k) {
      const __m256i N = _mm256_sub_epi32(_mm256_mullo_epi32(area, load8(r.acc[k] + x)),
                                         _mm256_mullo_epi32(count[k], S));
      const __m256 v = _mm256_mul_ps(_mm256_cvtepi32_ps(N), _mm256_mul_ps(inv_sd, kk[k]));
      _mm256_storeu_ps(r.out[k] + x, _mm256_max_ps(_mm256_min_ps(v, f_one), f_zero));
    }
  }
  for (; x < n; ++x) scorePixel(r, x);
}

// GCC 12 warns about its own _mm512_undefined_*() inside avx512fintrin.h (PR105593).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#define RLD_AVX512 __attribute__((target("avx512f"), always_inline)) inline
RLD_AVX512 __m512i ld(const uint32_t* p) {
  return _mm512_loadu_si512(p);
}
RLD_AVX512 __m512d toDouble(__m256i v) {
  return _mm512_maskz_cvtepi32_pd(0xFF, v);
}
RLD_AVX512 __m512 join(__m256 lo, __m256 hi) {
  return _mm512_castpd_ps(_mm512_mask_insertf64x4(
      _mm512_castps_pd(_mm512_castps256_ps512(lo)), 0xFF,
      _mm512_castps_pd(_mm512_castps256_ps512(lo)), _mm256_castps_pd(hi), 1));
}

// Sixteen pixels with AVX-512, the same values lane for lane (no FMA contraction).
__attribute__((target("avx512f"), optimize("fp-contract=off"))) void scoreRowAvx512(
    const ScoreRow& r, int n) {
  const __m512d inv_area = _mm512_set1_pd(r.inv_area), eps = _mm512_set1_pd(10 * FLT_EPSILON),
                half = _mm512_set1_pd(0.5), one = _mm512_set1_pd(1.0);
  const __m512i area = _mm512_set1_epi32(r.area);
  const __m512i count[2] = {_mm512_set1_epi32(r.count[0]), _mm512_set1_epi32(r.count[1])};
  const __m512 kk[2] = {_mm512_set1_ps(r.k[0]), _mm512_set1_ps(r.k[1])};
  const __m512 f_one = _mm512_set1_ps(1.f), f_zero = _mm512_setzero_ps();
  int x = 0;
  for (; x + 16 <= n; x += 16) {
    const __m512i S = _mm512_sub_epi32(_mm512_sub_epi32(ld(r.bottom + r.s + x), ld(r.bottom + x)),
                                       _mm512_sub_epi32(ld(r.top + r.s + x), ld(r.top + x)));
    if (_mm512_test_epi32_mask(S, S) == 0) {
      _mm512_storeu_ps(r.out[0] + x, f_zero);  // windows of zeros are flat
      _mm512_storeu_ps(r.out[1] + x, f_zero);
      continue;
    }
    const __m512i Q =
        _mm512_sub_epi32(_mm512_sub_epi32(ld(r.bottom_sq + r.s + x), ld(r.bottom_sq + x)),
                         _mm512_sub_epi32(ld(r.top_sq + r.s + x), ld(r.top_sq + x)));
    __m256 d_f[2], keep_f[2];
    for (int h = 0; h < 2; ++h) {
      const __m256i Sh = h ? _mm512_maskz_extracti64x4_epi64(0xF, S, 1) : _mm512_castsi512_si256(S);
      const __m256i Qh = h ? _mm512_maskz_extracti64x4_epi64(0xF, Q, 1) : _mm512_castsi512_si256(Q);
      const __m512d sum = toDouble(Sh), sum2 = toDouble(Qh);
      const __m512d diff2 = _mm512_sub_pd(sum2, _mm512_mul_pd(_mm512_mul_pd(sum, sum), inv_area));
      const __mmask8 keep =
          _mm512_cmp_pd_mask(diff2, _mm512_min_pd(half, _mm512_mul_pd(eps, sum2)), _CMP_GT_OQ);
      d_f[h] = _mm512_maskz_cvtpd_ps(0xFF, _mm512_mask_blend_pd(keep, one, diff2));
      keep_f[h] = _mm512_maskz_cvtpd_ps(0xFF, _mm512_maskz_mov_pd(keep, one));
    }
    const __m512 inv_sd =
        _mm512_mul_ps(_mm512_div_ps(f_one, _mm512_maskz_sqrt_ps(0xFFFF, join(d_f[0], d_f[1]))),
                      join(keep_f[0], keep_f[1]));
    for (int k = 0; k < 2; ++k) {
      const __m512i N = _mm512_sub_epi32(_mm512_mullo_epi32(area, ld(r.acc[k] + x)),
                                         _mm512_mullo_epi32(count[k], S));
      const __m512 v = _mm512_mul_ps(_mm512_cvtepi32_ps(N), _mm512_mul_ps(inv_sd, kk[k]));
      _mm512_storeu_ps(r.out[k] + x, _mm512_max_ps(_mm512_min_ps(v, f_one), f_zero));
    }
  }
  scoreRowAvx2(r, n, x);
}
#pragma GCC diagnostic pop

void scoreRow(const ScoreRow& r, int n) {
  const int level = simdLevel();
  if (level == 2 && r.s <= 45)
    scoreRowAvx512(r, n);
  else if (level == 1 && r.s <= 45)
    scoreRowAvx2(r, n);
  else
    scoreRowSse2(r, n);
}
#else
uint32_t updateRow(const RowUpdate& u) {
  return updateTail(u, 0, 0, 0);
}

void scoreRow(const ScoreRow& r, int n) {
  for (int x = 0; x < n; ++x) scorePixel(r, x);
}
#endif

}  // namespace

void NccMatcher::compile(const LineTemplate& t, Compiled& c) {
  const int s = t.size, p = t.slope_p, q = std::max(t.slope_q, 1);
  c.p = p;
  c.q = q;
  c.count = t.count;
  c.plus.clear();
  c.minus.clear();
  // at most 2 vertical ranges and 2 q residue chains per side (no reallocation when q changes)
  c.plus.reserve(4 + 4 * kMaxSlopeDenominator);
  c.minus.reserve(4 + 4 * kMaxSlopeDenominator);
  auto pair = [&c](Term plus, Term minus) {
    c.plus.push_back(plus);
    c.minus.push_back(minus);
  };
  // Run ends clipped to column 0 (begins) or s (ends): vertical ranges of rows, two
  // integral-image lookups each.
  for (int side = 0; side < 2; ++side) {
    int r = 0;
    while (r < s) {
      auto clipped = [&](int row) {
        const int b = t.run_begin[row], e = t.run_end[row];
        return e > b && (side == 0 ? b == 0 : e == s);
      };
      if (!clipped(r)) {
        ++r;
        continue;
      }
      const int r0 = r;
      while (r < s && clipped(r)) ++r;
      if (side == 0)  // - sum P(y + r, x) over [r0, r)
        pair(Term{r0, 0, false}, Term{r, 0, false});
      else  // + sum P(y + r, x + s)
        pair(Term{r, s, false}, Term{r0, s, false});
    }
  }
  // Other run ends step by (p, q): per residue class of rows, chains of ends that follow the
  // step are summed by two lookups into the running sum along (p, q).
  for (int side = 0; side < 2; ++side) {
    auto end_at = [&](int row) { return side == 0 ? t.run_begin[row] : t.run_end[row]; };
    auto onStair = [&](int row) {
      const int b = t.run_begin[row], e = t.run_end[row];
      return e > b && (side == 0 ? b > 0 : e < s);
    };
    for (int j = 0; j < q; ++j) {
      int r = j;
      while (r < s) {
        if (!onStair(r)) {
          r += q;
          continue;
        }
        const int first = r;
        while (r + q < s && onStair(r + q) && end_at(r + q) == end_at(r) + p) r += q;
        const Term last_term{r, end_at(r), true};
        const Term before_first{first - q, end_at(first) - p, true};
        if (side == 0)
          pair(before_first, last_term);  // - sum P at the run begins
        else
          pair(last_term, before_first);  // + sum P at the run ends
        r += q;
      }
    }
  }
}

void NccMatcher::produceRow(const cv::Mat& image, const cv::Rect& region, int y) {
  const int w = width_, m = margin_;
  RowUpdate u;
  u.src = image.ptr<uint8_t>(region.y + y) + region.x;
  u.w = w;
  u.ii_old = integral_.ptr<uint32_t>(y % ring_);
  u.ii_new = integral_.ptr<uint32_t>((y + 1) % ring_);
  u.sq_old = integral_sq_.ptr<uint32_t>(y % ring_);
  u.sq_new = integral_sq_.ptr<uint32_t>((y + 1) % ring_);
  u.tables = compiled_[1].stair == 1 ? 2 : 1;
  const uint32_t* older[2];
  for (int k = 0; k < u.tables; ++k) {
    older[k] = stair_[k].ptr<uint32_t>((y - compiled_[k].q + ring_) % ring_) + m;
    u.e_old[k] = older[k] - compiled_[k].p;
    u.e_new[k] = stair_[k].ptr<uint32_t>(y % ring_) + m;
  }
  const uint32_t total = updateRow(u);
  u.ii_new[0] = u.ii_old[0];
  u.sq_new[0] = u.sq_old[0];
  // running sums at column 0 and in the margins, where P is 0 left of the region and the row
  // total right of it: E(y, X) = P(X) + E(y - q, X - p), E outside [-m, w + m] counting 0
  for (int k = 0; k < u.tables; ++k) {
    const int p = compiled_[k].p;
    auto step = [&](int X) {
      const uint32_t P = X <= 0 ? 0u : total;
      u.e_new[k][X] = P + (X - p >= -m && X - p <= w + m ? older[k][X - p] : 0u);
    };
    for (int X = -m; X <= 0; ++X) step(X);
    for (int X = w + 1; X <= w + m; ++X) step(X);
  }
}

namespace {
std::atomic<bool> g_reference_stages{false};
std::atomic<int> g_max_simd_level{2};
}  // namespace

void setMaxSimdLevel(int level) {
  g_max_simd_level = level;
}

int simdLevel() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const int cpu =
      __builtin_cpu_supports("avx512f") ? 2 : (__builtin_cpu_supports("avx2") ? 1 : 0);
#else
  static const int cpu = 0;
#endif
  return std::min(cpu, g_max_simd_level.load(std::memory_order_relaxed));
}

void setReferenceStages(bool enabled) {
  g_reference_stages = enabled;
}
bool referenceStages() {
  return g_reference_stages;
}

bool NccMatcher::match(const cv::Mat& image, const cv::Rect& region_in, const LineTemplate& left,
                       const LineTemplate& right, cv::Mat& response_left, cv::Mat& response_right) {
  CV_Assert(image.type() == CV_8UC1 && left.size == right.size);
  if (referenceStages()) {
    matchTemplateReference(image, region_in, left, response_left);
    matchTemplateReference(image, region_in, right, response_right);
    const cv::Rect region = region_in & cv::Rect(0, 0, image.cols, image.rows);
    return region.width >= left.size && region.height >= left.size;
  }
  response_left.create(image.size(), CV_32FC1);
  response_right.create(image.size(), CV_32FC1);
  const cv::Rect region = region_in & cv::Rect(0, 0, image.cols, image.rows);
  const int s = left.size;
  if (region.width < s || region.height < s) {
    zero(response_left, cv::Rect(0, 0, image.cols, image.rows));
    zero(response_right, cv::Rect(0, 0, image.cols, image.rows));
    return false;
  }
  const int w = region.width, h = region.height;
  const int ow = w - s + 1, oh = h - s + 1;  // output positions
  const int off = s / 2;

  // Scores are written at rows [y0, y0 + oh) and columns [x0, x0 + ow); zero the rest. Rows
  // outside the region only when the map is new or the region moved: nobody writes there, and
  // at 1280x760 they are 3.5 MB a frame.
  const int y0 = region.y + off, x0 = region.x + off;
  const int rb = region.br().y;
  for (int k = 0; k < 2; ++k) {
    cv::Mat& R = k ? response_right : response_left;
    if (R.data != cleared_[k] || region != cleared_region_[k] || R.size() != image.size()) {
      zero(R, cv::Rect(0, 0, image.cols, region.y));
      zero(R, cv::Rect(0, rb, image.cols, image.rows - rb));
      cleared_[k] = R.data;
      cleared_region_[k] = region;
    }
    zero(R, cv::Rect(0, region.y, image.cols, y0 - region.y));
    zero(R, cv::Rect(0, y0 + oh, image.cols, rb - y0 - oh));
    zero(R, cv::Rect(0, y0, x0, oh));
    zero(R, cv::Rect(x0 + ow, y0, image.cols - x0 - ow, oh));
  }

  compile(left, compiled_[0]);
  compile(right, compiled_[1]);
  compiled_[0].stair = 0;
  const bool same_slope = compiled_[1].p == compiled_[0].p && compiled_[1].q == compiled_[0].q;
  compiled_[1].stair = same_slope ? 0 : 1;
  width_ = w;
  margin_ = std::max(std::abs(compiled_[0].p), std::abs(compiled_[1].p));
  ring_ = s + std::max(compiled_[0].q, compiled_[1].q) + 1;
  const int cols = w + 1 + 2 * margin_;
  // Buffers only grow: a template slope that changes between frames (ring rows, margins) must
  // not reallocate in steady state.
  auto ensure = [](cv::Mat& m, int rows, int c) {
    if (m.rows < rows || m.cols < c)
      m.create(std::max(rows, m.rows), std::max(c, m.cols), CV_32SC1);
  };
  ensure(integral_, ring_, w + 1);
  ensure(integral_sq_, ring_, w + 1);
  ensure(stair_[0], ring_, cols);
  ensure(stair_[1], ring_, cols);
  for (auto& a : acc_) a.resize(ow);
  plus_ptr_.reserve(4 + 4 * kMaxSlopeDenominator);
  minus_ptr_.reserve(4 + 4 * kMaxSlopeDenominator);
  plus_ptr_.resize(std::max(compiled_[0].plus.size(), compiled_[1].plus.size()));
  minus_ptr_.resize(plus_ptr_.size());
  // integral row 0 and the running sums before the region are zero
  zero(integral_, cv::Rect(0, 0, w + 1, 1));
  zero(integral_sq_, cv::Rect(0, 0, w + 1, 1));
  for (int k = 0; k < 2; ++k)
    for (int y = -compiled_[k].q; y < 0; ++y)
      zero(stair_[compiled_[k].stair], cv::Rect(0, y + ring_, cols, 1));

  const int area = s * s;
  const double inv_area = 1.0 / area;
  float k_t[2];
  for (int k = 0; k < 2; ++k) {
    // sum (T - mean T)^2 for a binary template, in units where T is 1 on the line; an empty or
    // full template has no defined correlation and scores 0
    const double n_t = compiled_[k].count;
    const double var = n_t - n_t * n_t * inv_area;
    k_t[k] = var > 0.0 ? static_cast<float>(1.0 / (area * std::sqrt(var))) : 0.f;
  }

  for (int y = 0; y < s - 1; ++y) produceRow(image, region, y);
  for (int y = 0; y < oh; ++y) {
    produceRow(image, region, y + s - 1);
    auto row = [&](bool stair, int table, int dy) -> const uint32_t* {
      const int slot = (y + dy + ring_) % ring_;
      return stair ? stair_[table].ptr<uint32_t>(slot) + margin_ : integral_.ptr<uint32_t>(slot);
    };
    for (int k = 0; k < 2; ++k) {
      const Compiled& c = compiled_[k];
      const int pairs = static_cast<int>(c.plus.size());
      for (int i = 0; i < pairs; ++i) {
        plus_ptr_[i] = row(c.plus[i].stair, c.stair, c.plus[i].dy) + c.plus[i].dx;
        minus_ptr_[i] = row(c.minus[i].stair, c.stair, c.minus[i].dy) + c.minus[i].dx;
      }
      accumulate(acc_[k].data(), plus_ptr_.data(), minus_ptr_.data(), pairs, ow);
    }
    ScoreRow sr;
    sr.acc[0] = acc_[0].data();
    sr.acc[1] = acc_[1].data();
    sr.top = integral_.ptr<uint32_t>(y % ring_);
    sr.bottom = integral_.ptr<uint32_t>((y + s) % ring_);
    sr.top_sq = integral_sq_.ptr<uint32_t>(y % ring_);
    sr.bottom_sq = integral_sq_.ptr<uint32_t>((y + s) % ring_);
    sr.s = s;
    sr.area = area;
    sr.inv_area = inv_area;
    for (int k = 0; k < 2; ++k) {
      sr.count[k] = static_cast<int>(compiled_[k].count);
      sr.k[k] = k_t[k];
    }
    sr.out[0] = response_left.ptr<float>(y0 + y) + x0;
    sr.out[1] = response_right.ptr<float>(y0 + y) + x0;
    scoreRow(sr, ow);
  }
  return true;
}

void matchTemplateReference(const cv::Mat& image, const cv::Rect& region_in, const LineTemplate& t,
                            cv::Mat& response) {
  response.create(image.size(), CV_32FC1);
  response.setTo(0);
  const cv::Rect region = region_in & cv::Rect(0, 0, image.cols, image.rows);
  const int s = t.size;
  if (region.width < s || region.height < s) return;
  cv::Mat scores;
  cv::matchTemplate(image(region), t.image, scores, cv::TM_CCOEFF_NORMED);
  cv::max(scores, 0.0, scores);
  scores.copyTo(response(cv::Rect(region.x + s / 2, region.y + s / 2, scores.cols, scores.rows)));
}

}  // namespace rgbd_lane_detector
