#include "rgbd_lane_detector/half_binary.h"

#include <algorithm>
#include <cstring>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define RLD_HB_AVX2 1
#define RLD_AVX2 __attribute__((target("avx2")))
#endif

#include "rgbd_lane_detector/template_matching.h"  // simdLevel()

namespace rgbd_lane_detector {
namespace {

// Half-binary of one row of interleaved pixels; ri/gi/bi are channel indices, cn the stride.
template <int cn, int ri, int gi, int bi>
void convertRow(const uint8_t* src, uint8_t* dst, int from, int width, int tau_c) {
  src += cn * from;
  for (int x = from; x < width; ++x, src += cn) {
    const int g = greyValue(src[ri], src[gi], src[bi]);
    dst[x] = g >= tau_c ? static_cast<uint8_t>(g) : 0;
  }
}

#ifdef RLD_HB_AVX2
// greyValue() of eight pixels given as 16-bit lanes (r0 g0 r1 g1 ...) and (b0 0 b1 0 ...):
// OpenCV's fixed point (r 9798 + g 19235 + b 3735 + 2^14) >> 15, exact in 32 bits.
RLD_AVX2 inline __m128i grey4(__m128i rg, __m128i b0) {
  const __m128i w_rg = _mm_set1_epi32(9798 | (19235 << 16)), w_b = _mm_set1_epi32(3735);
  const __m128i sum = _mm_add_epi32(_mm_madd_epi16(rg, w_rg), _mm_madd_epi16(b0, w_b));
  return _mm_srli_epi32(_mm_add_epi32(sum, _mm_set1_epi32(1 << 14)), 15);
}

// TOZERO at tau: keep g where g >= tau.
RLD_AVX2 inline __m128i threshold16(__m128i g, __m128i tau) {
  return _mm_and_si128(g, _mm_cmpeq_epi8(_mm_max_epu8(g, tau), g));
}

// 16 pixels of 3 channels per step: byte shuffles gather each channel, then grey4().
template <int ri, int bi>
RLD_AVX2 int convert3Avx2(const uint8_t* src, uint8_t* dst, int width, int tau_c) {
  // shuffle masks: channel c of pixel i (byte 3 i + c of the 48) from block a, b or c
  struct Masks {
    __m128i m[3][3];
  };
  static const Masks masks = [] {
    Masks k;
    for (int c = 0; c < 3; ++c)
      for (int block = 0; block < 3; ++block) {
        alignas(16) int8_t b[16];
        for (int i = 0; i < 16; ++i) {
          const int at = 3 * i + c - 16 * block;
          b[i] = at >= 0 && at < 16 ? static_cast<int8_t>(at) : static_cast<int8_t>(-128);
        }
        k.m[c][block] = _mm_load_si128(reinterpret_cast<const __m128i*>(b));
      }
    return k;
  }();
  const __m128i zero = _mm_setzero_si128(), tau = _mm_set1_epi8(static_cast<char>(tau_c));
  int x = 0;
  for (; x + 16 <= width; x += 16) {
    const uint8_t* p = src + 3 * x;
    const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
    const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + 16));
    const __m128i c = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + 32));
    __m128i ch[3];
    for (int k = 0; k < 3; ++k)
      ch[k] = _mm_or_si128(
          _mm_or_si128(_mm_shuffle_epi8(a, masks.m[k][0]), _mm_shuffle_epi8(b, masks.m[k][1])),
          _mm_shuffle_epi8(c, masks.m[k][2]));
    const __m128i R = ch[ri], G = ch[1], B = ch[bi];
    __m128i grey[2];
    for (int h = 0; h < 2; ++h) {
      const __m128i r16 = h ? _mm_unpackhi_epi8(R, zero) : _mm_unpacklo_epi8(R, zero);
      const __m128i g16 = h ? _mm_unpackhi_epi8(G, zero) : _mm_unpacklo_epi8(G, zero);
      const __m128i b16 = h ? _mm_unpackhi_epi8(B, zero) : _mm_unpacklo_epi8(B, zero);
      const __m128i lo = grey4(_mm_unpacklo_epi16(r16, g16), _mm_unpacklo_epi16(b16, zero));
      const __m128i hi = grey4(_mm_unpackhi_epi16(r16, g16), _mm_unpackhi_epi16(b16, zero));
      grey[h] = _mm_packs_epi32(lo, hi);
    }
    _mm_storeu_si128(reinterpret_cast<__m128i*>(dst + x),
                     threshold16(_mm_packus_epi16(grey[0], grey[1]), tau));
  }
  return x;
}

// 16 pixels of 4 channels per step: one shuffle per 4 pixels gives (r, g) and (b, 0) lanes.
template <int ri, int bi>
RLD_AVX2 int convert4Avx2(const uint8_t* src, uint8_t* dst, int width, int tau_c) {
  const char z = -128;
  const __m128i rg =
      _mm_setr_epi8(ri, z, 1, z, ri + 4, z, 5, z, ri + 8, z, 9, z, ri + 12, z, 13, z);
  const __m128i b0 = _mm_setr_epi8(bi, z, z, z, bi + 4, z, z, z, bi + 8, z, z, z, bi + 12, z, z, z);
  const __m128i tau = _mm_set1_epi8(static_cast<char>(tau_c));
  int x = 0;
  for (; x + 16 <= width; x += 16) {
    __m128i q[4];
    for (int k = 0; k < 4; ++k) {
      const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + 4 * (x + 4 * k)));
      q[k] = grey4(_mm_shuffle_epi8(v, rg), _mm_shuffle_epi8(v, b0));
    }
    const __m128i g = _mm_packus_epi16(_mm_packs_epi32(q[0], q[1]), _mm_packs_epi32(q[2], q[3]));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(dst + x), threshold16(g, tau));
  }
  return x;
}

RLD_AVX2 int convert1Avx2(const uint8_t* src, uint8_t* dst, int width, int tau_c) {
  const __m256i tau = _mm256_set1_epi8(static_cast<char>(tau_c));
  int x = 0;
  for (; x + 32 <= width; x += 32) {
    const __m256i g = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(src + x));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(dst + x),
                        _mm256_and_si256(g, _mm256_cmpeq_epi8(_mm256_max_epu8(g, tau), g)));
  }
  return x;
}
#endif

}  // namespace

void halfBinary(const cv::Mat& colour, PixelFormat format, int tau_c, const cv::Range& rows,
                cv::Mat& out) {
  if (out.size() != colour.size() || out.type() != CV_8UC1) {
    out.create(colour.size(), CV_8UC1);
    out = cv::Scalar(0);  // rows never converted read as 0 (once, on allocation)
  }
  const int r0 = std::max(rows.start, 0);
  const int r1 = std::min(rows.end, colour.rows);
  const int w = colour.cols;
  // tau_c <= 0 keeps everything; above 255 nothing: the vector code compares bytes
  const int tau = std::min(std::max(tau_c, 0), 256);
#ifdef RLD_HB_AVX2
  const bool avx2 = simdLevel() >= 1;
  const bool vec = avx2 && tau <= 255;
#endif
  for (int y = r0; y < r1; ++y) {
    const uint8_t* src = colour.ptr<uint8_t>(y);
    uint8_t* dst = out.ptr<uint8_t>(y);
    int x = 0;
    switch (format) {
      case PixelFormat::kBgr8:
#ifdef RLD_HB_AVX2
        if (vec) x = convert3Avx2<2, 0>(src, dst, w, tau);
#endif
        convertRow<3, 2, 1, 0>(src, dst, x, w, tau);
        break;
      case PixelFormat::kRgb8:
#ifdef RLD_HB_AVX2
        if (vec) x = convert3Avx2<0, 2>(src, dst, w, tau);
#endif
        convertRow<3, 0, 1, 2>(src, dst, x, w, tau);
        break;
      case PixelFormat::kBgra8:
#ifdef RLD_HB_AVX2
        if (vec) x = convert4Avx2<2, 0>(src, dst, w, tau);
#endif
        convertRow<4, 2, 1, 0>(src, dst, x, w, tau);
        break;
      case PixelFormat::kRgba8:
#ifdef RLD_HB_AVX2
        if (vec) x = convert4Avx2<0, 2>(src, dst, w, tau);
#endif
        convertRow<4, 0, 1, 2>(src, dst, x, w, tau);
        break;
      case PixelFormat::kMono8:
#ifdef RLD_HB_AVX2
        if (vec) x = convert1Avx2(src, dst, w, tau);
#endif
        for (; x < w; ++x) dst[x] = src[x] >= tau ? src[x] : 0;
        break;
    }
  }
}

}  // namespace rgbd_lane_detector
