// Stage 2: depth to organised points. The per-row kernels are compiled for every SIMD target
// (simd.h); this file is included once per target by Highway's foreach_target.h.
#ifndef RLD_DEPTH_POINTS_ONCE
#define RLD_DEPTH_POINTS_ONCE
#include "rgbd_lane_detector/depth_points.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>

#include "simd.h"

namespace rgbd_lane_detector {
namespace {
// Source columns per chunk of a resampled 16-bit row told empty (all 0) at once.
constexpr int kChunk = 32;
// Chunks scanned between two prefetches of the next source row's same columns.
constexpr int kPrefetchChunks = 16;
}  // namespace
}  // namespace rgbd_lane_detector
#endif

#ifdef RLD_HAVE_HWY
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "depth_points.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

RLD_KERNELS_BEGIN

// x = ax d, y = ry d, z = d where keep, NaN elsewhere, stored as interleaved points.
template <class DF>
void storePoints(DF df, hn::Mask<DF> keep, hn::Vec<DF> d, const float* ax, float ry, float* dst) {
  const auto nan = hn::Set(df, std::numeric_limits<float>::quiet_NaN());
  hn::StoreInterleaved3(hn::IfThenElse(keep, hn::Mul(hn::LoadU(df, ax), d), nan),
                        hn::IfThenElse(keep, hn::Mul(hn::Set(df, ry), d), nan),
                        hn::IfThenElse(keep, d, nan), df, dst);
}

// A vector of N columns without depth: three vectors of NaN (what storePoints() stores where no
// lane is kept, without the products and the interleaving; a sparse LiDAR's rows are mostly this).
template <class DF>
void storeNaN(DF df, float* dst) {
  const auto nan = hn::Set(df, std::numeric_limits<float>::quiet_NaN());
  const size_t N = hn::Lanes(df);
  hn::StoreU(nan, df, dst);
  hn::StoreU(nan, df, dst + N);
  hn::StoreU(nan, df, dst + 2 * N);
}

// Per chunk of kChunk 16-bit source values: 1 when any is not 0 (raw 0 is no depth). Returns
// the chunks done (all, or none when a vector is wider than a chunk).
int chunksWithDepth(const uint16_t* src, int chunks, uint8_t* out) {
  const hn::ScalableTag<uint16_t> d;
  const int N = static_cast<int>(hn::Lanes(d));
  if (N > kChunk) return 0;
  for (int c = 0; c < chunks; ++c) {
    const uint16_t* p = src + c * kChunk;
    auto any = hn::LoadU(d, p);
    for (int k = N; k < kChunk; k += N) any = hn::Or(any, hn::LoadU(d, p + k));
    out[c] = !hn::AllTrue(d, hn::Eq(any, hn::Zero(d)));
  }
  return chunks;
}

// NaN points at the n columns from dst. Returns the columns done.
int nanColumns(float* dst, int n) {
  const hn::ScalableTag<float> df;
  const int N = static_cast<int>(hn::Lanes(df));
  int x = 0;
  for (; x + N <= n; x += N) storeNaN(df, dst + 3 * x);
  return x;
}

// The depth block map of a vector of N columns from x: its blocks (one when N divides
// kDepthBlock) hold depth when any lane is kept.
template <class DF>
void markBlocks(DF df, hn::Mask<DF> keep, int x, int N, uint8_t* blocks) {
  if (!blocks || hn::AllFalse(df, keep)) return;
  if (N <= kDepthBlock && kDepthBlock % N == 0) {  // x is a multiple of N: one block
    blocks[x / kDepthBlock] = 1;
    return;
  }
  for (int b = x / kDepthBlock; b <= (x + N - 1) / kDepthBlock; ++b) blocks[b] = 1;
}

// Points from the raw 16-bit values of a vector of N columns from x: the decoder's range test as
// the interval [lo, hi] of raw values, the decode in double rounded once, x from the table ax of
// float((u - cx) / fx).
template <class D32>
void pointsU16(D32 d32, hn::Vec<D32> raw, int x, double scale, int lo, int hi, const float* ax,
               float ry, float* dst, uint8_t* blocks) {
  const hn::Rebind<float, D32> df;
  const hn::Half<decltype(df)> dfh;
  const hn::Half<D32> d32h;
  const hn::Rebind<double, decltype(d32h)> dd;
  const int N = static_cast<int>(hn::Lanes(d32));
  const auto in = hn::And(hn::Gt(raw, hn::Set(d32, lo - 1)), hn::Lt(raw, hn::Set(d32, hi + 1)));
  if (hn::AllFalse(d32, in)) {  // (no block to mark either)
    storeNaN(df, dst + 3 * x);
    return;
  }
  const auto vscale = hn::Set(dd, scale);
  const auto d0 = hn::DemoteTo(dfh, hn::Mul(hn::PromoteTo(dd, hn::LowerHalf(d32h, raw)), vscale));
  const auto d1 = hn::DemoteTo(dfh, hn::Mul(hn::PromoteTo(dd, hn::UpperHalf(d32h, raw)), vscale));
  storePoints(df, hn::RebindMask(df, in), hn::Combine(df, d1, d0), ax + x, ry, dst + 3 * x);
  markBlocks(df, hn::RebindMask(df, in), x, N, blocks);
}

// Points of a vector of N columns from x with float depth d: valid when in (0, inf) and in
// [lo, hi], the float bounds that compare as the decoder's double ones.
template <class DF>
void pointsF32(DF df, hn::Vec<DF> d, int x, float lo, float hi, const float* ax, float ry,
               float* dst, uint8_t* blocks) {
  const int N = static_cast<int>(hn::Lanes(df));
  const auto ok = hn::And(hn::And(hn::Gt(d, hn::Zero(df)),
                                  hn::Lt(d, hn::Set(df, std::numeric_limits<float>::infinity()))),
                          hn::And(hn::Ge(d, hn::Set(df, lo)), hn::Le(d, hn::Set(df, hi))));
  if (hn::AllFalse(df, ok)) {
    storeNaN(df, dst + 3 * x);
    return;
  }
  storePoints(df, ok, d, ax + x, ry, dst + 3 * x);
  markBlocks(df, ok, x, N, blocks);
}

// 16-bit depth of one row (no column map): pointsU16() of each vector. Returns the columns done.
int rowU16(const uint16_t* src, int w, double scale, int lo, int hi, const float* ax, float ry,
           float* dst, uint8_t* blocks) {
  const hn::ScalableTag<int32_t> d32;
  const hn::Rebind<uint16_t, decltype(d32)> d16;
  const int N = static_cast<int>(hn::Lanes(d32));
  int x = 0;
  for (; x + N <= w; x += N)
    pointsU16(d32, hn::PromoteTo(d32, hn::LoadU(d16, src + x)), x, scale, lo, hi, ax, ry, dst,
              blocks);
  return x;
}

// 16-bit depth of one row through a column map, the raw value of column x read straight from the
// source row as the low half of a 32-bit lane at byte 2 cm[x] (no row gathered first: a wide
// load of values just stored one by one waits for the stores; the caller keeps the 4 bytes
// inside the row). Returns the columns done.
int rowU16Map(const uint16_t* src, const int* cm, int w, double scale, int lo, int hi,
              const float* ax, float ry, float* dst, uint8_t* blocks) {
  const hn::ScalableTag<int32_t> d32;
  const int N = static_cast<int>(hn::Lanes(d32));
  const int32_t* base = reinterpret_cast<const int32_t*>(src);
  const auto low = hn::Set(d32, 0xffff);
  int x = 0;
  for (; x + N <= w; x += N) {
    const auto offsets = hn::ShiftLeft<1>(hn::LoadU(d32, cm + x));  // bytes
    const auto raw = hn::And(hn::GatherOffset(d32, base, offsets), low);  // little-endian
    pointsU16(d32, raw, x, scale, lo, hi, ax, ry, dst, blocks);
  }
  return x;
}

// Float depth of one row (no column map): pointsF32() of each vector. Returns the columns done.
int rowF32(const float* src, int w, float lo, float hi, const float* ax, float ry, float* dst,
           uint8_t* blocks) {
  const hn::ScalableTag<float> df;
  const int N = static_cast<int>(hn::Lanes(df));
  int x = 0;
  for (; x + N <= w; x += N) pointsF32(df, hn::LoadU(df, src + x), x, lo, hi, ax, ry, dst, blocks);
  return x;
}

// Float depth of one row through a column map, read straight from the source row. Returns the
// columns done.
int rowF32Map(const float* src, const int* cm, int w, float lo, float hi, const float* ax,
              float ry, float* dst, uint8_t* blocks) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const int N = static_cast<int>(hn::Lanes(df));
  int x = 0;
  for (; x + N <= w; x += N)
    pointsF32(df, hn::GatherIndex(df, src, hn::LoadU(di, cm + x)), x, lo, hi, ax, ry, dst, blocks);
  return x;
}

RLD_KERNELS_END
#endif  // RLD_HAVE_HWY

#if HWY_ONCE
namespace rgbd_lane_detector {
namespace {

// The scalar target: no column done by a vector (convertRows() does them all).
int rowU16Scalar(const uint16_t*, int, double, int, int, const float*, float, float*, uint8_t*) {
  return 0;
}
int rowU16MapScalar(const uint16_t*, const int*, int, double, int, int, const float*, float,
                    float*, uint8_t*) {
  return 0;
}
int rowF32Scalar(const float*, int, float, float, const float*, float, float*, uint8_t*) {
  return 0;
}
int rowF32MapScalar(const float*, const int*, int, float, float, const float*, float, float*,
                    uint8_t*) {
  return 0;
}
int chunksWithDepthScalar(const uint16_t*, int, uint8_t*) { return 0; }
int nanColumnsScalar(float*, int) { return 0; }
#ifdef RLD_HAVE_HWY
HWY_EXPORT(rowU16);
HWY_EXPORT(rowU16Map);
HWY_EXPORT(rowF32);
HWY_EXPORT(rowF32Map);
HWY_EXPORT(chunksWithDepth);
HWY_EXPORT(nanColumns);
#endif

// Raw values r with d = r * scale inside [min_depth, max_depth] and r != 0: an interval, since
// d grows with r. Found with the decoder's own expression; empty when lo > hi.
void validRaw(const DepthDecoder& dec, int& lo, int& hi) {
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
  lo = a;
  hi = c;
}

// The float bounds [lo, hi] with raw >= lo <=> raw >= min_depth and raw <= hi <=> raw <= max_depth
// for every float raw (the decoder compares in double).
void floatBounds(const DepthDecoder& dec, float& lo, float& hi) {
  const float inf = std::numeric_limits<float>::infinity();
  lo = static_cast<float>(dec.min_depth);
  if (static_cast<double>(lo) < dec.min_depth) lo = std::nextafter(lo, inf);
  hi = static_cast<float>(dec.max_depth);
  if (static_cast<double>(hi) > dec.max_depth) hi = std::nextafter(hi, -inf);
  if (std::isnan(dec.min_depth) || std::isnan(dec.max_depth)) {  // nothing passes
    lo = inf;
    hi = -inf;
  }
}

// The next source row read through a column map into the cache while this one is gathered (its
// lines are read out of order and a row at a time: the hardware prefetcher starts late).
inline void prefetchRow(const uint8_t* p, size_t bytes) {
  for (size_t i = 0; i < bytes; i += 64) __builtin_prefetch(p + i);
}

// One row of depthBlocks(): a block is empty when none of its floats is a number (a point is
// three numbers or three NaN), counted by a loop the compiler vectorises.
void blocksOfRow(const float* p, int w, uint8_t* out) {
  for (int b = 0; b * kDepthBlock < w; ++b) {
    const int n = 3 * (std::min(w, (b + 1) * kDepthBlock) - b * kDepthBlock);
    const float* q = p + 3 * b * kDepthBlock;
    int numbers = 0;
    for (int i = 0; i < n; ++i) numbers += q[i] == q[i];
    out[b] = numbers > 0;
  }
}

void allocateBlocks(const cv::Size& size, cv::Mat& blocks) {
  const cv::Size s((size.width + kDepthBlock - 1) / kDepthBlock, size.height);
  if (blocks.size() != s || blocks.type() != CV_8UC1) {
    blocks.create(s, CV_8UC1);
    blocks.setTo(0);
  }
}

template <typename T>
void convertRows(const cv::Mat& depth, const DepthDecoder& decode, const Intrinsics& K, int r0,
                 int r1, cv::Mat& points, const int* col_map, const int* row_map,
                 cv::Mat* blocks, DepthPointsTables& tables) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const double inv_fx = 1.0 / K.fx;
  const double inv_fy = 1.0 / K.fy;
  const int w = points.cols;
  // the vector rows: the x factors of the columns (of their source columns when resampled) and
  // the valid raw range, once per call
  std::vector<float>& ax = tables.ax;
  const bool u16 = std::is_same<T, uint16_t>::value;
  int raw_lo = 1, raw_hi = 0;
  float f_lo = 0.f, f_hi = 0.f;
  const bool vec = !u16 || decode.scale > 0.0;
  if (vec) {
    if (u16)
      validRaw(decode, raw_lo, raw_hi);
    else
      floatBounds(decode, f_lo, f_hi);
    if (static_cast<int>(ax.size()) < w) ax.resize(w);
    for (int x = 0; x < w; ++x)
      ax[x] = static_cast<float>(((col_map ? col_map[x] : x) - K.cx) * inv_fx);
  }
  // resampled 16-bit values are read as the low half of 4 bytes: the columns before w4 have
  // their 4 bytes inside the source row
  int w4 = w;
  if (col_map && u16)
    for (w4 = 0; w4 < w && col_map[w4] + 1 < depth.cols;) ++w4;
  // resampled 16-bit depth: the source chunks (kChunk columns) of each block of kDepthBlock
  // processing columns; a block whose chunks hold only 0 has no depth (no conversion)
  std::vector<int>& spans = tables.spans;
  std::vector<uint8_t>& chunk_any = tables.chunk_any;
  const int nb = (w + kDepthBlock - 1) / kDepthBlock;
  const int nc = (depth.cols + kChunk - 1) / kChunk;
  const bool by_blocks = vec && u16 && col_map;
  if (by_blocks) {
    if (static_cast<int>(spans.size()) < 2 * nb) spans.resize(2 * nb);
    if (static_cast<int>(chunk_any.size()) < nc) chunk_any.resize(nc);
    for (int b = 0; b < nb; ++b) {
      spans[2 * b] = col_map[b * kDepthBlock] / kChunk;
      spans[2 * b + 1] = col_map[std::min(w, (b + 1) * kDepthBlock) - 1] / kChunk;
    }
  }
  for (int y = r0; y < r1; ++y) {
    const int sy = row_map ? row_map[y] : y;
    const T* src = depth.ptr<T>(sy);
    float* dst = points.ptr<float>(y);
    const float ry = static_cast<float>((sy - K.cy) * inv_fy);
    uint8_t* bl = blocks ? blocks->ptr<uint8_t>(y) : nullptr;  // marked as the row is made
    if (bl) std::memset(bl, 0, blocks->cols);
    // columns [x0, x1) of the row: the vector kernel (through the column map when resampled),
    // then the per-pixel definition
    auto convert = [&](int x0, int x1) {
      int x = x0;
      uint8_t* b = bl ? bl + x0 / kDepthBlock : nullptr;  // (x0: a block's first column)
      const int xv = std::min(x1, w4);  // (w4 <= x0: no column for the vector kernel)
      if (vec && u16 && col_map && xv > x0)
        x += RLD_DISPATCH(rowU16Map)(reinterpret_cast<const uint16_t*>(src), col_map + x0,
                                     xv - x0, decode.scale, raw_lo, raw_hi, ax.data() + x0, ry,
                                     dst + 3 * x0, b);
      else if (vec && u16 && !col_map)
        x += RLD_DISPATCH(rowU16)(reinterpret_cast<const uint16_t*>(src) + x0, x1 - x0,
                                  decode.scale, raw_lo, raw_hi, ax.data() + x0, ry, dst + 3 * x0,
                                  b);
      else if (vec && !u16 && col_map)
        x += RLD_DISPATCH(rowF32Map)(reinterpret_cast<const float*>(src), col_map + x0, x1 - x0,
                                     f_lo, f_hi, ax.data() + x0, ry, dst + 3 * x0, b);
      else if (vec && !u16)
        x += RLD_DISPATCH(rowF32)(reinterpret_cast<const float*>(src) + x0, x1 - x0, f_lo, f_hi,
                                  ax.data() + x0, ry, dst + 3 * x0, b);
      for (; x < x1; ++x) {
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
        if (bl) bl[x / kDepthBlock] = 1;
      }
    };
    const uint8_t* next =
        vec && col_map && y + 1 < r1 ? depth.ptr<uint8_t>(row_map[y + 1]) : nullptr;
    if (!by_blocks) {
      if (next) prefetchRow(next, depth.cols * sizeof(T));
      convert(0, w);
      continue;
    }
    // runs of blocks with a source value other than 0 converted, the others NaN (raw 0 is no
    // depth; most of a sparse LiDAR's row); the next source row is read into the cache a few
    // lines at a time, each while the same lines of this row are scanned (a row's prefetches at
    // once wait for each other)
    if constexpr (std::is_same<T, uint16_t>::value) {
      const int full = depth.cols / kChunk;
      for (int c0 = 0; c0 < nc; c0 += kPrefetchChunks) {
        const int c1 = std::min(nc, c0 + kPrefetchChunks);
        if (next)
          prefetchRow(next + sizeof(T) * c0 * kChunk,
                      sizeof(T) * (std::min(depth.cols, c1 * kChunk) - c0 * kChunk));
        const int vf = std::min(c1, full) - c0;  // full chunks
        int c = c0;
        if (vf > 0)
          c += RLD_DISPATCH(chunksWithDepth)(src + c0 * kChunk, vf, chunk_any.data() + c0);
        for (; c < c1; ++c) {
          unsigned any = 0;
          for (int i = c * kChunk; i < std::min(depth.cols, (c + 1) * kChunk); ++i) any |= src[i];
          chunk_any[c] = any != 0;
        }
      }
    }
    auto empty = [&](int b) {
      for (int c = spans[2 * b]; c <= spans[2 * b + 1]; ++c)
        if (chunk_any[c]) return false;
      return true;
    };
    for (int b = 0; b < nb;) {
      int e = b;
      while (e < nb && !empty(e)) ++e;
      if (e > b) {
        convert(b * kDepthBlock, std::min(w, e * kDepthBlock));
        b = e;
        if (b == nb) break;
      }
      // empty blocks from b on: NaN points
      for (e = b + 1; e < nb && empty(e);) ++e;
      const int x0 = b * kDepthBlock, x1 = std::min(w, e * kDepthBlock);
      const int x = x0 + RLD_DISPATCH(nanColumns)(dst + 3 * x0, x1 - x0);
      std::fill(dst + 3 * x, dst + 3 * x1, nan);
      b = e;
    }
  }
}

}  // namespace

bool depthToPoints(const cv::Mat& depth, const DepthDecoder& decoder, const Intrinsics& K,
                   const cv::Range& rows, cv::Mat& points, const cv::Mat& col_map,
                   const cv::Mat& row_map, cv::Mat* blocks, DepthPointsTables* tables) {
  if (depth.type() != CV_16UC1 && depth.type() != CV_32FC1) return false;
  DepthPointsTables local;  // (empty: allocates only when used)
  DepthPointsTables& t = tables ? *tables : local;
  const cv::Size size(col_map.empty() ? depth.cols : static_cast<int>(col_map.total()),
                      row_map.empty() ? depth.rows : static_cast<int>(row_map.total()));
  points.create(size, CV_32FC3);
  const int r0 = std::max(rows.start, 0);
  const int r1 = std::min(rows.end, size.height);
  const int* cm = col_map.empty() ? nullptr : col_map.ptr<int>();
  const int* rm = row_map.empty() ? nullptr : row_map.ptr<int>();
  if (blocks) allocateBlocks(size, *blocks);
  if (depth.type() == CV_16UC1)
    convertRows<uint16_t>(depth, decoder, K, r0, r1, points, cm, rm, blocks, t);
  else
    convertRows<float>(depth, decoder, K, r0, r1, points, cm, rm, blocks, t);
  return true;
}

void depthBlocks(const cv::Mat& points, const cv::Range& rows, cv::Mat& blocks) {
  CV_Assert(points.type() == CV_32FC3);
  allocateBlocks(points.size(), blocks);
  for (int y = std::max(rows.start, 0); y < std::min(rows.end, points.rows); ++y)
    blocksOfRow(points.ptr<float>(y), points.cols, blocks.ptr<uint8_t>(y));
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
#endif  // HWY_ONCE
