// Stage 1: half-binary image. The per-row kernels are compiled for every SIMD target (simd.h);
// this file is included once per target by Highway's foreach_target.h.
#ifndef RLD_HALF_BINARY_ONCE
#define RLD_HALF_BINARY_ONCE
#include "rgbd_lane_detector/half_binary.h"

#include <algorithm>
#include <cstring>

#include "simd.h"

namespace rgbd_lane_detector {
namespace {
// Half-binary of the columns [from, width) of one row of format F (layout: pixelLayout()).
template <PixelFormat F>
void convertRow(const uint8_t* src, uint8_t* dst, int from, int width, int tau_c) {
  constexpr PixelLayout L = pixelLayout(F);
  src += L.channels * from;
  for (int x = from; x < width; ++x, src += L.channels) {
    const int g = L.channels == 1 ? src[0] : greyValue(src[L.r], src[L.g], src[L.b]);
    dst[x] = g >= tau_c ? static_cast<uint8_t>(g) : 0;
  }
}
// convertRow() of the columns [from, width) of an output row whose pixel x is the source row's
// pixel cm[x].
template <PixelFormat F>
void convertMappedRow(const uint8_t* src, const int* cm, uint8_t* dst, int from, int width,
                      int tau_c) {
  constexpr PixelLayout L = pixelLayout(F);
  for (int x = from; x < width; ++x) {
    const uint8_t* p = src + L.channels * cm[x];
    const int g = L.channels == 1 ? p[0] : greyValue(p[L.r], p[L.g], p[L.b]);
    dst[x] = g >= tau_c ? static_cast<uint8_t>(g) : 0;
  }
}
}  // namespace
}  // namespace rgbd_lane_detector
#endif

#ifdef RLD_HAVE_HWY
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "half_binary.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

RLD_KERNELS_BEGIN

// greyValue() lane for lane, in 32 bits (OpenCV's 15-bit fixed point is exact there), then
// TOZERO at tau: 32-bit lanes for the arithmetic, the pixels as bytes of the same count.
template <class D32>
hn::Vec<D32> greyTozero(D32 d32, hn::Vec<D32> r, hn::Vec<D32> g, hn::Vec<D32> b, int tau) {
  const auto sum = hn::Add(hn::Add(hn::Mul(r, hn::Set(d32, 9798)), hn::Mul(g, hn::Set(d32, 19235))),
                           hn::Add(hn::Mul(b, hn::Set(d32, 3735)), hn::Set(d32, 1 << 14)));
  const auto grey = hn::ShiftRight<15>(sum);
  return hn::IfThenElseZero(hn::Gt(grey, hn::Set(d32, tau - 1)), grey);  // grey >= tau
}

// One row of 1, 3 or 4 channels (r, g, b at channel indices ri, 1, bi); returns the columns done.
template <int cn, int ri, int bi>
int convertRowT(const uint8_t* src, uint8_t* dst, int width, int tau) {
  const hn::ScalableTag<int32_t> d32;
  const hn::Rebind<uint8_t, decltype(d32)> d8;  // one byte per 32-bit lane
  const int N = static_cast<int>(hn::Lanes(d32));
  int x = 0;
  for (; x + N <= width; x += N) {
    hn::Vec<decltype(d8)> c[4];
    if (cn == 3) {
      hn::LoadInterleaved3(d8, src + 3 * x, c[0], c[1], c[2]);
    } else if (cn == 4) {
      hn::LoadInterleaved4(d8, src + 4 * x, c[0], c[1], c[2], c[3]);
    } else {
      c[0] = hn::LoadU(d8, src + x);
    }
    hn::Vec<decltype(d32)> grey;
    if (cn == 1) {
      const auto g = hn::PromoteTo(d32, c[0]);
      grey = hn::IfThenElseZero(hn::Gt(g, hn::Set(d32, tau - 1)), g);
    } else {
      grey = greyTozero(d32, hn::PromoteTo(d32, c[ri]), hn::PromoteTo(d32, c[1]),
                        hn::PromoteTo(d32, c[bi]), tau);
    }
    hn::StoreU(hn::DemoteTo(d8, grey), d8, dst + x);
  }
  return x;
}

// One row of format F, its layout from pixelLayout() (green is channel 1 in every colour format).
template <PixelFormat F>
int convertFormat(const uint8_t* s, uint8_t* d, int w, int tau) {
  constexpr PixelLayout L = pixelLayout(F);
  static_assert(L.channels == 1 || L.g == 1, "convertRowT reads green at channel 1");
  return convertRowT<L.channels, L.r, L.b>(s, d, w, tau);
}
int convertBgr(const uint8_t* s, uint8_t* d, int w, int tau) {
  return convertFormat<PixelFormat::kBgr8>(s, d, w, tau);
}
int convertRgb(const uint8_t* s, uint8_t* d, int w, int tau) {
  return convertFormat<PixelFormat::kRgb8>(s, d, w, tau);
}
int convertBgra(const uint8_t* s, uint8_t* d, int w, int tau) {
  return convertFormat<PixelFormat::kBgra8>(s, d, w, tau);
}
int convertRgba(const uint8_t* s, uint8_t* d, int w, int tau) {
  return convertFormat<PixelFormat::kRgba8>(s, d, w, tau);
}
int convertMono(const uint8_t* s, uint8_t* d, int w, int tau) {
  return convertFormat<PixelFormat::kMono8>(s, d, w, tau);
}

// Through a column map: the pixel of each output column read as one 32-bit lane at byte
// cn cm[x] of the source row (its channels are the lane's bytes; the caller keeps the 4 bytes
// inside the row), then greyTozero() as convertRowT(). Returns the columns done.
template <int cn, int ri, int bi>
int gatherRowT(const uint8_t* src, const int* cm, int n, uint8_t* dst, int tau) {
  const hn::ScalableTag<int32_t> d32;
  const hn::Rebind<uint8_t, decltype(d32)> d8;
  const int N = static_cast<int>(hn::Lanes(d32));
  const auto bytes = hn::Set(d32, cn), low = hn::Set(d32, 0xff);
  const int32_t* base = reinterpret_cast<const int32_t*>(src);
  int x = 0;
  for (; x + N <= n; x += N) {
    const auto v = hn::GatherOffset(d32, base, hn::Mul(hn::LoadU(d32, cm + x), bytes));
    const auto r = hn::And(hn::ShiftRight<8 * ri>(v), low);
    const auto g = hn::And(hn::ShiftRight<8>(v), low);
    const auto b = hn::And(hn::ShiftRight<8 * bi>(v), low);
    hn::StoreU(hn::DemoteTo(d8, greyTozero(d32, r, g, b, tau)), d8, dst + x);
  }
  return x;
}
template <PixelFormat F>
int gatherFormat(const uint8_t* s, const int* cm, int n, uint8_t* d, int tau) {
  constexpr PixelLayout L = pixelLayout(F);
  static_assert(L.channels >= 3 && L.g == 1, "gatherRowT reads green at byte 1");
  return gatherRowT<L.channels, L.r, L.b>(s, cm, n, d, tau);
}
int gatherBgr(const uint8_t* s, const int* cm, int n, uint8_t* d, int tau) {
  return gatherFormat<PixelFormat::kBgr8>(s, cm, n, d, tau);
}
int gatherRgb(const uint8_t* s, const int* cm, int n, uint8_t* d, int tau) {
  return gatherFormat<PixelFormat::kRgb8>(s, cm, n, d, tau);
}
int gatherBgra(const uint8_t* s, const int* cm, int n, uint8_t* d, int tau) {
  return gatherFormat<PixelFormat::kBgra8>(s, cm, n, d, tau);
}
int gatherRgba(const uint8_t* s, const int* cm, int n, uint8_t* d, int tau) {
  return gatherFormat<PixelFormat::kRgba8>(s, cm, n, d, tau);
}

RLD_KERNELS_END
#endif  // RLD_HAVE_HWY

#if HWY_ONCE
namespace rgbd_lane_detector {

namespace {
// The scalar target: no column done by a vector (convertRow() does them all).
int convertScalar(const uint8_t*, uint8_t*, int, int) {
  return 0;
}
constexpr auto convertBgrScalar = convertScalar, convertRgbScalar = convertScalar,
               convertBgraScalar = convertScalar, convertRgbaScalar = convertScalar,
               convertMonoScalar = convertScalar;
int gatherScalar(const uint8_t*, const int*, int, uint8_t*, int) {
  return 0;
}
constexpr auto gatherBgrScalar = gatherScalar, gatherRgbScalar = gatherScalar,
               gatherBgraScalar = gatherScalar, gatherRgbaScalar = gatherScalar;
}  // namespace

#ifdef RLD_HAVE_HWY
HWY_EXPORT(convertBgr);
HWY_EXPORT(convertRgb);
HWY_EXPORT(convertBgra);
HWY_EXPORT(convertRgba);
HWY_EXPORT(convertMono);
HWY_EXPORT(gatherBgr);
HWY_EXPORT(gatherRgb);
HWY_EXPORT(gatherBgra);
HWY_EXPORT(gatherRgba);
#endif

namespace {

// One row: the vector kernel of the format (one per format: their layouts are compile-time),
// then the rest of the row.
void convertAnyRow(PixelFormat format, const uint8_t* src, uint8_t* dst, int w, int tau) {
  using F = PixelFormat;
  switch (format) {
    case PixelFormat::kBgr8:
      convertRow<F::kBgr8>(src, dst, RLD_DISPATCH(convertBgr)(src, dst, w, tau), w, tau);
      break;
    case PixelFormat::kRgb8:
      convertRow<F::kRgb8>(src, dst, RLD_DISPATCH(convertRgb)(src, dst, w, tau), w, tau);
      break;
    case PixelFormat::kBgra8:
      convertRow<F::kBgra8>(src, dst, RLD_DISPATCH(convertBgra)(src, dst, w, tau), w, tau);
      break;
    case PixelFormat::kRgba8:
      convertRow<F::kRgba8>(src, dst, RLD_DISPATCH(convertRgba)(src, dst, w, tau), w, tau);
      break;
    case PixelFormat::kMono8:
      convertRow<F::kMono8>(src, dst, RLD_DISPATCH(convertMono)(src, dst, w, tau), w, tau);
      break;
  }
}

// Columns [0, n) of a row through the column map by the format's gather kernel (colour formats
// only; the 4 bytes read at each pixel must lie inside the row): the columns done.
int gatherAnyRow(PixelFormat format, const uint8_t* src, const int* cm, int n, uint8_t* dst,
                 int tau) {
  switch (format) {
    case PixelFormat::kBgr8:
      return RLD_DISPATCH(gatherBgr)(src, cm, n, dst, tau);
    case PixelFormat::kRgb8:
      return RLD_DISPATCH(gatherRgb)(src, cm, n, dst, tau);
    case PixelFormat::kBgra8:
      return RLD_DISPATCH(gatherBgra)(src, cm, n, dst, tau);
    case PixelFormat::kRgba8:
      return RLD_DISPATCH(gatherRgba)(src, cm, n, dst, tau);
    case PixelFormat::kMono8:
      break;
  }
  return 0;
}

// The per-pixel conversion of the columns [from, w) of a row read through the column map.
void convertMappedFrom(PixelFormat format, const uint8_t* src, const int* cm, uint8_t* dst,
                       int from, int w, int tau) {
  using F = PixelFormat;
  switch (format) {
    case F::kBgr8: convertMappedRow<F::kBgr8>(src, cm, dst, from, w, tau); break;
    case F::kRgb8: convertMappedRow<F::kRgb8>(src, cm, dst, from, w, tau); break;
    case F::kBgra8: convertMappedRow<F::kBgra8>(src, cm, dst, from, w, tau); break;
    case F::kRgba8: convertMappedRow<F::kRgba8>(src, cm, dst, from, w, tau); break;
    case F::kMono8: convertMappedRow<F::kMono8>(src, cm, dst, from, w, tau); break;
  }
}

// Output columns gathered between two prefetches of the next source row's same columns.
constexpr int kPrefetchColumns = 256;

// The output's rows: allocated (and zeroed: rows never converted read as 0) on a new size.
cv::Range outputRows(const cv::Size& size, const cv::Range& rows, cv::Mat& out) {
  if (out.size() != size || out.type() != CV_8UC1) {
    out.create(size, CV_8UC1);
    out = cv::Scalar(0);
  }
  return cv::Range(std::max(rows.start, 0), std::min(rows.end, size.height));
}

// tau_c <= 0 keeps everything; above 255 nothing
int clampTau(int tau_c) {
  return std::min(std::max(tau_c, 0), 256);
}

}  // namespace

void greyPixels(const uint8_t* src, PixelFormat format, int n, uint8_t* dst) {
  convertAnyRow(format, src, dst, n, 0);  // (TOZERO at 0 keeps every grey value)
}

void halfBinary(const cv::Mat& colour, PixelFormat format, int tau_c, const cv::Range& rows,
                cv::Mat& out) {
  const cv::Range r = outputRows(colour.size(), rows, out);
  const int tau = clampTau(tau_c);
  for (int y = r.start; y < r.end; ++y)
    convertAnyRow(format, colour.ptr<uint8_t>(y), out.ptr<uint8_t>(y), colour.cols, tau);
}

void halfBinary(const cv::Mat& colour, PixelFormat format, int tau_c, const cv::Range& rows,
                cv::Mat& out, const cv::Mat& col_map, const cv::Mat& row_map) {
  const int w = static_cast<int>(col_map.total());
  const cv::Range r = outputRows(cv::Size(w, static_cast<int>(row_map.total())), rows, out);
  const int tau = clampTau(tau_c);
  const int* cm = col_map.ptr<int>();
  const int* rm = row_map.ptr<int>();
  const int e = static_cast<int>(colour.elemSize());
  // colour: the columns whose 4 bytes lie inside the source row by the format's gather kernel
  // (one 32-bit lane per pixel), the rest (all of a grey image, all on the scalar target) pixel
  // by pixel through the map
  int w4 = 0;
  while (w4 < w && cm[w4] + 1 < colour.cols) ++w4;
  const int gather_end = e == 4 ? w : e == 3 ? w4 : 0;
  for (int y = r.start; y < r.end; ++y) {
    const uint8_t* src = colour.ptr<uint8_t>(rm[y]);
    uint8_t* dst = out.ptr<uint8_t>(y);
    // the next source row into the cache a few lines at a time, each while the same columns of
    // this row are gathered (a row's prefetches at once wait for each other)
    const uint8_t* next = y + 1 < r.end ? colour.ptr<uint8_t>(rm[y + 1]) : nullptr;
    for (int x0 = 0; x0 < w; x0 += kPrefetchColumns) {
      const int x1 = std::min(w, x0 + kPrefetchColumns);
      if (next) {
        const uint8_t* end = next + e * (cm[x1 - 1] + 1);
        for (const uint8_t* p = next + e * cm[x0]; p < end; p += 64) __builtin_prefetch(p);
        __builtin_prefetch(end - 1);
      }
      const int xg = std::min(x1, gather_end);
      const int done =
          x0 + (xg > x0 ? gatherAnyRow(format, src, cm + x0, xg - x0, dst + x0, tau) : 0);
      convertMappedFrom(format, src, cm, dst, done, x1, tau);
    }
  }
}

}  // namespace rgbd_lane_detector
#endif  // HWY_ONCE
