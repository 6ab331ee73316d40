// Stage 4: NCC matching. The row kernels (accumulated lookups, prefix scan of a new row, scores)
// are compiled for every SIMD target (simd.h); this file is included once per target by
// Highway's foreach_target.h. A template's terms (NccMatcher::compile) and OpenCV's reference:
// template_matching_terms.cpp.
#ifndef RLD_TEMPLATE_MATCHING_ONCE
#define RLD_TEMPLATE_MATCHING_ONCE
#include "rgbd_lane_detector/template_matching.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>

#include "simd.h"

namespace rgbd_lane_detector {
namespace {

// Zero a rectangle of a map row by row (cv::Mat::setTo allocates a scratch buffer per call).
void zero(cv::Mat& m, const cv::Rect& r) {
  if (r.width <= 0 || r.height <= 0) return;
  for (int y = r.y; y < r.br().y; ++y)
    std::memset(m.ptr<uint8_t>(y) + r.x * m.elemSize(), 0, r.width * m.elemSize());
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
  const uint32_t* e_old[NccMatcher::kMaxTemplates];  ///< shifted by -p: e_new[X] = P[X] + e_old[X]
  uint32_t* e_new[NccMatcher::kMaxTemplates];
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
  int templates;  ///< 1 to NccMatcher::kMaxTemplates
  const uint32_t* acc[NccMatcher::kMaxTemplates];  ///< correlations (sum of I over the line)
  const uint32_t* top;     ///< integral row at the window top, column x
  const uint32_t* bottom;  ///< integral row below the window
  const uint32_t* top_sq;  ///< same for the squares
  const uint32_t* bottom_sq;
  int s;     ///< template side: window columns x .. x + s
  int area;  ///< s * s
  double inv_area;
  int count[NccMatcher::kMaxTemplates];  ///< line pixels of each template
  float k[NccMatcher::kMaxTemplates];    ///< 1 / (area |T - mean T|), T in {0, 1}
  float* out[NccMatcher::kMaxTemplates];
  uint8_t* mark;  ///< optional: 255 where a score is at least level, else 0
  float level;
};

constexpr float kInfF = std::numeric_limits<float>::infinity();

// One pixel, the definition every vector lane follows operation for operation:
// diff2 = sum2 - sum^2 / area (exact in double, as OpenCV evaluates it); OpenCV's flat rule
// diff2 <= min(0.5, 10 FLT_EPSILON sum2) scores 0; otherwise with the exact integer
// N = area acc - count sum = area sum (I - mean I)(T - mean T),
// score = N / (area |I - mean I| |T - mean T|), clamped to [0, 1].
inline void scorePixel(const ScoreRow& r, int x) {
  const int32_t S =
      static_cast<int32_t>((r.bottom[x + r.s] - r.bottom[x]) - (r.top[x + r.s] - r.top[x]));
  // Q reaches 65536 * 255^2 > 2^31 for 256-pixel templates on bright images: unsigned
  const uint32_t Q = (r.bottom_sq[x + r.s] - r.bottom_sq[x]) - (r.top_sq[x + r.s] - r.top_sq[x]);
  const double sum = S, sum2 = Q;
  const double diff2 = sum2 - sum * sum * r.inv_area;
  const bool keep = diff2 > std::min(0.5, 10 * FLT_EPSILON * sum2);
  // 1 / sqrt(inf) = 0: flat windows score 0
  const float inv_sd = 1.f / std::sqrt(keep ? static_cast<float>(diff2) : kInfF);
  bool above = false;
  for (int k = 0; k < r.templates; ++k) {
    const int64_t N = static_cast<int64_t>(r.area) * static_cast<int32_t>(r.acc[k][x]) -
                      static_cast<int64_t>(r.count[k]) * S;
    const float v = static_cast<float>(N) * (inv_sd * r.k[k]);
    r.out[k][x] = v > 0.f ? std::min(v, 1.f) : 0.f;  // +0 below (never -0: same bits everywhere)
    above = above || r.out[k][x] >= r.level;
  }
  if (r.mark) r.mark[x] = above ? 255 : 0;
}

}  // namespace
}  // namespace rgbd_lane_detector
#endif  // RLD_TEMPLATE_MATCHING_ONCE

#ifdef RLD_HAVE_HWY
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "template_matching.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

RLD_KERNELS_BEGIN

// acc[x] = the sum of (plus_i[x] - minus_i[x]) over the pairs, mod 2^32 (any order: exact).
void accumulateRow(uint32_t* acc, const uint32_t* const* plus, const uint32_t* const* minus,
                   int pairs, int n) {
  const hn::ScalableTag<uint32_t> d;
  const int N = static_cast<int>(hn::Lanes(d));
  auto diff = [&](int i, int x) {
    return hn::Sub(hn::LoadU(d, plus[i] + x), hn::LoadU(d, minus[i] + x));
  };
  int x = 0;
  for (; x + 8 * N <= n; x += 8 * N) {  // eight vectors of sums in registers over all pairs
    auto a0 = hn::Zero(d), a1 = a0, a2 = a0, a3 = a0, a4 = a0, a5 = a0, a6 = a0, a7 = a0;
    for (int i = 0; i < pairs; ++i) {
      a0 = hn::Add(a0, diff(i, x));
      a1 = hn::Add(a1, diff(i, x + N));
      a2 = hn::Add(a2, diff(i, x + 2 * N));
      a3 = hn::Add(a3, diff(i, x + 3 * N));
      a4 = hn::Add(a4, diff(i, x + 4 * N));
      a5 = hn::Add(a5, diff(i, x + 5 * N));
      a6 = hn::Add(a6, diff(i, x + 6 * N));
      a7 = hn::Add(a7, diff(i, x + 7 * N));
    }
    hn::StoreU(a0, d, acc + x);
    hn::StoreU(a1, d, acc + x + N);
    hn::StoreU(a2, d, acc + x + 2 * N);
    hn::StoreU(a3, d, acc + x + 3 * N);
    hn::StoreU(a4, d, acc + x + 4 * N);
    hn::StoreU(a5, d, acc + x + 5 * N);
    hn::StoreU(a6, d, acc + x + 6 * N);
    hn::StoreU(a7, d, acc + x + 7 * N);
  }
  for (; x + N <= n; x += N) {
    auto a = hn::Zero(d);
    for (int i = 0; i < pairs; ++i) a = hn::Add(a, diff(i, x));
    hn::StoreU(a, d, acc + x);
  }
  for (; x < n; ++x) {
    uint32_t a = 0;
    for (int i = 0; i < pairs; ++i) a += plus[i][x] - minus[i][x];
    acc[x] = a;
  }
}

// Prefix sums of a new row by in-register scans, 4 or 8 columns per step (256-bit vectors at
// most: the scan crosses one 128-bit block boundary), for kTables running-sum tables. The row's
// pointers are copied out of u first: a vector store may alias anything, and the compiler would
// read every field of u again after each one. Returns P(w).
template <int kTables>
uint32_t updateRowT(const RowUpdate& u) {
  const hn::CappedTag<uint32_t, 8> d;
  const hn::Rebind<uint16_t, decltype(d)> d16;
  const hn::Rebind<uint8_t, decltype(d)> d8;
  constexpr int N = static_cast<int>(hn::MaxLanes(d));
  const uint8_t* const src = u.src;
  const uint32_t* const ii_old = u.ii_old;
  uint32_t* const ii_new = u.ii_new;
  const uint32_t* const sq_old = u.sq_old;
  uint32_t* const sq_new = u.sq_new;
  const int w = u.w;
  const uint32_t* e_old[kTables];
  uint32_t* e_new[kTables];
  for (int t = 0; t < kTables; ++t) {
    e_old[t] = u.e_old[t];
    e_new[t] = u.e_new[t];
  }
  auto carry = hn::Zero(d), carry2 = carry;
  int c = 0;
  for (; c + N <= w; c += N) {
    const auto v16 = hn::PromoteTo(d16, hn::LoadU(d8, src + c));
    auto v = hn::PromoteTo(d, v16);
    auto q = hn::PromoteTo(d, hn::Mul(v16, v16));  // 255^2 fits 16 bits
    v = hn::Add(v, hn::ShiftLeftLanes<1>(d, v));
    q = hn::Add(q, hn::ShiftLeftLanes<1>(d, q));
    v = hn::Add(v, hn::ShiftLeftLanes<2>(d, v));
    q = hn::Add(q, hn::ShiftLeftLanes<2>(d, q));
    auto tv = hn::Broadcast<3>(v), tq = hn::Broadcast<3>(q);  // per 128-bit block
    if (N == 8) {  // the low block's total into the high block
      v = hn::Add(v, hn::ConcatLowerLower(d, tv, hn::Zero(d)));
      q = hn::Add(q, hn::ConcatLowerLower(d, tq, hn::Zero(d)));
      tv = hn::Broadcast<3>(v);
      tq = hn::Broadcast<3>(q);
      tv = hn::ConcatUpperUpper(d, tv, tv);
      tq = hn::ConcatUpperUpper(d, tq, tq);
    }
    v = hn::Add(v, carry);
    q = hn::Add(q, carry2);
    const auto next = hn::Add(tv, carry), next2 = hn::Add(tq, carry2);
    const int X = c + 1;
    hn::StoreU(hn::Add(hn::LoadU(d, ii_old + X), v), d, ii_new + X);
    hn::StoreU(hn::Add(hn::LoadU(d, sq_old + X), q), d, sq_new + X);
    for (int t = 0; t < kTables; ++t)
      hn::StoreU(hn::Add(hn::LoadU(d, e_old[t] + X), v), d, e_new[t] + X);
    carry = next;
    carry2 = next2;
  }
  return updateTail(u, c, hn::GetLane(carry), hn::GetLane(carry2));
}

uint32_t updateRowKernel(const RowUpdate& u) {
  static_assert(NccMatcher::kMaxTemplates == 4, "a case per table count");
  switch (u.tables) {  // 1 to NccMatcher::kMaxTemplates
    case 1: return updateRowT<1>(u);
    case 2: return updateRowT<2>(u);
    case 3: return updateRowT<3>(u);
    default: return updateRowT<NccMatcher::kMaxTemplates>(u);
  }
}

// Scores of one row, whole vectors, the same values lane for lane as scorePixel(): S, Q and
// diff2 in double, N exact (32-bit integers when area * acc < 2^31, templates up to 45 px; else
// double, exact below 2^53), for kT templates. The row's pointers and the templates' factors are
// copied out of r first (a vector store may alias anything: the compiler would read them again
// after each store). Returns the columns done.
template <bool kWide, int kT>
int scoreRowT(const ScoreRow& r, int n) {
  const hn::ScalableTag<int32_t> d32;
  const hn::Rebind<float, decltype(d32)> df;
  const hn::Half<decltype(d32)> d32h;
  const hn::Half<decltype(df)> dfh;
  const hn::Rebind<double, decltype(d32h)> dd;
  const hn::Rebind<int8_t, decltype(d32)> d8;
  const int N = static_cast<int>(hn::Lanes(d32));
  const auto inv_area = hn::Set(dd, r.inv_area), eps = hn::Set(dd, 10 * FLT_EPSILON),
             half = hn::Set(dd, 0.5), inf_d = hn::Set(dd, std::numeric_limits<double>::infinity()),
             two32 = hn::Set(dd, 4294967296.0), zero_d = hn::Zero(dd);
  const auto f_one = hn::Set(df, 1.f), f_zero = hn::Zero(df), level = hn::Set(df, r.level);
  int8_t* const mark = reinterpret_cast<int8_t*>(r.mark);
  const uint32_t* const top = r.top;
  const uint32_t* const bottom = r.bottom;
  const uint32_t* const top_sq = r.top_sq;
  const uint32_t* const bottom_sq = r.bottom_sq;
  const int s = r.s, area = r.area;
  const uint32_t* acc[kT];
  float* out[kT];
  int count[kT];
  float k_t[kT];
  for (int k = 0; k < kT; ++k) {
    acc[k] = r.acc[k];
    out[k] = r.out[k];
    count[k] = r.count[k];
    k_t[k] = r.k[k];
  }
  auto ld = [&](const uint32_t* p) {
    return hn::BitCast(d32, hn::LoadU(hn::RebindToUnsigned<decltype(d32)>(), p));
  };
  auto lower = [&](hn::Vec<decltype(d32)> v) { return hn::PromoteTo(dd, hn::LowerHalf(d32h, v)); };
  auto upper = [&](hn::Vec<decltype(d32)> v) { return hn::PromoteTo(dd, hn::UpperHalf(d32h, v)); };
  int x = 0;
  for (; x + N <= n; x += N) {
    const auto S = hn::Sub(hn::Sub(ld(bottom + s + x), ld(bottom + x)),
                           hn::Sub(ld(top + s + x), ld(top + x)));
    if (hn::AllTrue(d32, hn::Eq(S, hn::Zero(d32)))) {
      for (int k = 0; k < kT; ++k)
        hn::StoreU(f_zero, df, out[k] + x);  // windows of zeros are flat
      if (mark) hn::StoreU(hn::Zero(d8), d8, mark + x);
      continue;
    }
    const auto Q = hn::Sub(hn::Sub(ld(bottom_sq + s + x), ld(bottom_sq + x)),
                           hn::Sub(ld(top_sq + s + x), ld(top_sq + x)));
    hn::Vec<decltype(dfh)> d_f[2];
    hn::Vec<decltype(dd)> sum_d[2];
    for (int h = 0; h < 2; ++h) {
      // Q is unsigned (up to 65536 * 255^2): lanes at or above 2^31 promote negative, add 2^32
      const auto sum = h ? upper(S) : lower(S), q = h ? upper(Q) : lower(Q);
      const auto sum2 = hn::Add(q, hn::IfThenElseZero(hn::Lt(q, zero_d), two32));
      sum_d[h] = sum;
      const auto diff2 = hn::Sub(sum2, hn::Mul(hn::Mul(sum, sum), inv_area));
      const auto keep = hn::Gt(diff2, hn::Min(half, hn::Mul(eps, sum2)));
      d_f[h] = hn::DemoteTo(dfh, hn::IfThenElse(keep, diff2, inf_d));
    }
    const auto inv_sd = hn::Div(f_one, hn::Sqrt(hn::Combine(df, d_f[1], d_f[0])));
    auto above = hn::FirstN(df, 0);
    for (int k = 0; k < kT; ++k) {
      hn::Vec<decltype(df)> num;
      if (kWide) {
        const auto A = ld(acc[k] + x);
        const auto area_d = hn::Set(dd, area), count_d = hn::Set(dd, count[k]);
        const auto n0 = hn::Sub(hn::Mul(area_d, lower(A)), hn::Mul(count_d, sum_d[0]));
        const auto n1 = hn::Sub(hn::Mul(area_d, upper(A)), hn::Mul(count_d, sum_d[1]));
        num = hn::Combine(df, hn::DemoteTo(dfh, n1), hn::DemoteTo(dfh, n0));
      } else {
        num = hn::ConvertTo(df, hn::Sub(hn::Mul(hn::Set(d32, area), ld(acc[k] + x)),
                                        hn::Mul(hn::Set(d32, count[k]), S)));
      }
      const auto v = hn::Mul(num, hn::Mul(inv_sd, hn::Set(df, k_t[k])));
      const auto score = hn::IfThenElseZero(hn::Gt(v, f_zero), hn::Min(v, f_one));
      hn::StoreU(score, df, out[k] + x);
      above = hn::Or(above, hn::Ge(score, level));
    }
    if (mark)  // (all-ones lanes, -1, narrow to the byte 255)
      hn::StoreU(hn::DemoteTo(d8, hn::BitCast(d32, hn::VecFromMask(df, above))), d8, mark + x);
  }
  return x;
}

template <bool kWide>
int scoreRowW(const ScoreRow& r, int n) {
  switch (r.templates) {  // 1 to NccMatcher::kMaxTemplates
    case 1: return scoreRowT<kWide, 1>(r, n);
    case 2: return scoreRowT<kWide, 2>(r, n);
    case 3: return scoreRowT<kWide, 3>(r, n);
    default: return scoreRowT<kWide, NccMatcher::kMaxTemplates>(r, n);
  }
}

int scoreRowKernel(const ScoreRow& r, int n) {
  return r.s <= 45 ? scoreRowW<false>(r, n) : scoreRowW<true>(r, n);
}

RLD_KERNELS_END
#endif  // RLD_HAVE_HWY

#if HWY_ONCE
namespace rgbd_lane_detector {
namespace {

// The scalar target: the per-pixel definitions.
void accumulateRowScalar(uint32_t* acc, const uint32_t* const* plus, const uint32_t* const* minus,
                         int pairs, int n) {
  std::fill(acc, acc + n, 0u);
  for (int i = 0; i < pairs; ++i)
    for (int x = 0; x < n; ++x) acc[x] += plus[i][x] - minus[i][x];
}
uint32_t updateRowKernelScalar(const RowUpdate& u) {
  return updateTail(u, 0, 0, 0);
}
int scoreRowKernelScalar(const ScoreRow&, int) {
  return 0;  // scorePixel() does every column
}
#ifdef RLD_HAVE_HWY
HWY_EXPORT(accumulateRow);
HWY_EXPORT(updateRowKernel);
HWY_EXPORT(scoreRowKernel);
#endif

uint32_t updateRow(const RowUpdate& u) {
  return RLD_DISPATCH(updateRowKernel)(u);
}

void scoreRow(const ScoreRow& r, int n) {
  for (int x = RLD_DISPATCH(scoreRowKernel)(r, n); x < n; ++x) scorePixel(r, x);
}

void accumulate(uint32_t* acc, const uint32_t* const* plus, const uint32_t* const* minus, int pairs,
                int n) {
  RLD_DISPATCH(accumulateRow)(acc, plus, minus, pairs, n);
}

}  // namespace
void NccMatcher::produceRow(const cv::Mat& image, const cv::Rect& region, int y) {
  const int w = width_, m = margin_;
  RowUpdate u;
  u.src = image.ptr<uint8_t>(region.y + y) + region.x;
  u.w = w;
  u.ii_old = integral_.ptr<uint32_t>(y % ring_);
  u.ii_new = integral_.ptr<uint32_t>((y + 1) % ring_);
  u.sq_old = integral_sq_.ptr<uint32_t>(y % ring_);
  u.sq_new = integral_sq_.ptr<uint32_t>((y + 1) % ring_);
  u.tables = tables_;
  const uint32_t* older[kMaxTemplates];
  for (int k = 0; k < u.tables; ++k) {
    older[k] = stair_[k].ptr<uint32_t>((y - table_q_[k] + ring_) % ring_) + m;
    u.e_old[k] = older[k] - table_p_[k];
    u.e_new[k] = stair_[k].ptr<uint32_t>(y % ring_) + m;
  }
  const uint32_t total = updateRow(u);
  u.ii_new[0] = u.ii_old[0];
  u.sq_new[0] = u.sq_old[0];
  // running sums at column 0 and in the margins, where P is 0 left of the region and the row
  // total right of it: E(y, X) = P(X) + E(y - q, X - p), E outside [-m, w + m] counting 0
  for (int k = 0; k < u.tables; ++k) {
    const int p = table_p_[k];
    auto step = [&](int X) {
      const uint32_t P = X <= 0 ? 0u : total;
      u.e_new[k][X] = P + (X - p >= -m && X - p <= w + m ? older[k][X - p] : 0u);
    };
    for (int X = -m; X <= 0; ++X) step(X);
    for (int X = w + 1; X <= w + m; ++X) step(X);
  }
}

bool NccMatcher::match(const cv::Mat& image, const cv::Rect& region_in, const LineTemplate& left,
                       const LineTemplate& right, cv::Mat& response_left, cv::Mat& response_right) {
  const LineTemplate* templates[2] = {&left, &right};
  cv::Mat* responses[2] = {&response_left, &response_right};
  return match(image, region_in, templates, responses, 2);
}

bool NccMatcher::match(const cv::Mat& image, const cv::Rect& region_in,
                       const LineTemplate* const* templates, cv::Mat* const* responses,
                       int count, Mark* mark) {
  CV_Assert(image.type() == CV_8UC1 && count >= 1 && count <= kMaxTemplates);
  const int s = templates[0]->size;
  for (int k = 1; k < count; ++k) CV_Assert(templates[k]->size == s);
  const cv::Rect region = region_in & cv::Rect(0, 0, image.cols, image.rows);
  if (mark) mark->marked = false;
  if (referenceStages()) {
    for (int k = 0; k < count; ++k)
      matchTemplateReference(image, region_in, *templates[k], *responses[k]);
    return region.width >= s && region.height >= s;
  }
  for (int k = 0; k < count; ++k) responses[k]->create(image.size(), CV_32FC1);
  if (region.width < s || region.height < s) {
    for (int k = 0; k < count; ++k) zero(*responses[k], cv::Rect(0, 0, image.cols, image.rows));
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
  for (int k = 0; k < count; ++k) {
    cv::Mat& R = *responses[k];
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
  // the mark: over the region's rows, 0 where no score is written (0 is below the level)
  cv::Mat* const mask = mark && mark->level > 0.f ? mark->mask : nullptr;
  if (mask) {
    if (mask->size() != image.size() || mask->type() != CV_8UC1)
      mask->create(image.size(), CV_8UC1);
    zero(*mask, cv::Rect(0, region.y, image.cols, y0 - region.y));
    zero(*mask, cv::Rect(0, y0 + oh, image.cols, rb - y0 - oh));
    zero(*mask, cv::Rect(0, y0, x0, oh));
    zero(*mask, cv::Rect(x0 + ow, y0, image.cols - x0 - ow, oh));
    mark->marked = true;
  }

  // the templates' terms; one running-sum table per distinct slope
  templates_ = count;
  tables_ = 0;
  margin_ = 0;
  int max_q = 1;
  for (int k = 0; k < count; ++k) {
    Compiled& c = compiled_[k];
    compile(*templates[k], c);
    c.stair = 0;
    while (c.stair < tables_ && (table_p_[c.stair] != c.p || table_q_[c.stair] != c.q)) ++c.stair;
    if (c.stair == tables_) {
      table_p_[tables_] = c.p;
      table_q_[tables_++] = c.q;
    }
    margin_ = std::max(margin_, std::abs(c.p));
    max_q = std::max(max_q, c.q);
  }
  width_ = w;
  ring_ = s + max_q + 1;
  const int cols = w + 1 + 2 * margin_;
  // Buffers only grow: a template slope that changes between frames (ring rows, margins) must
  // not reallocate in steady state.
  auto ensure = [](cv::Mat& m, int rows, int c) {
    if (m.rows < rows || m.cols < c)
      m.create(std::max(rows, m.rows), std::max(c, m.cols), CV_32SC1);
  };
  ensure(integral_, ring_, w + 1);
  ensure(integral_sq_, ring_, w + 1);
  for (int t = 0; t < tables_; ++t) ensure(stair_[t], ring_, cols);
  for (int k = 0; k < count; ++k) acc_[k].resize(ow);
  constexpr int kMaxPairs = 4 + 4 * kMaxSlopeDenominator;  // compile()'s most
  plus_ptr_.reserve(kMaxPairs);
  minus_ptr_.reserve(kMaxPairs);
  runs_.reserve(ow + 1);  // at most one run per two blocks
  // integral row 0 and the running sums before the region are zero
  zero(integral_, cv::Rect(0, 0, w + 1, 1));
  zero(integral_sq_, cv::Rect(0, 0, w + 1, 1));
  for (int t = 0; t < tables_; ++t)
    for (int y = -table_q_[t]; y < 0; ++y) zero(stair_[t], cv::Rect(0, y + ring_, cols, 1));

  const int area = s * s;
  const double inv_area = 1.0 / area;
  ScoreRow sr;
  sr.templates = count;
  sr.s = s;
  sr.area = area;
  sr.inv_area = inv_area;
  sr.mark = nullptr;
  sr.level = mask ? mark->level : 1.f;
  for (int k = 0; k < count; ++k) {
    // sum (T - mean T)^2 for a binary template, in units where T is 1 on the line; an empty or
    // full template has no defined correlation and scores 0
    const double n_t = compiled_[k].count;
    const double var = n_t - n_t * n_t * inv_area;
    sr.k[k] = var > 0.0 ? static_cast<float>(1.0 / (area * std::sqrt(var))) : 0.f;
    sr.count[k] = static_cast<int>(compiled_[k].count);
    sr.acc[k] = acc_[k].data();
  }

  for (int y = 0; y < s - 1; ++y) produceRow(image, region, y);
  for (int y = 0; y < oh; ++y) {
    produceRow(image, region, y + s - 1);
    const int y_slot = y % ring_;
    auto row = [&](bool stair, int table, int dy) -> const uint32_t* {
      int slot = y_slot + dy;  // (y + dy) mod ring_, dy in [-q, s]: no division per term
      while (slot >= ring_) slot -= ring_;
      if (slot < 0) slot += ring_;
      return stair ? stair_[table].ptr<uint32_t>(slot) + margin_ : integral_.ptr<uint32_t>(slot);
    };
    // A window without a pixel above 0 (most of a road in the half-binary image) scores 0 what
    // ever its correlation (scorePixel(): a flat window): blocks of such windows, found by the
    // integral of their union, are not accumulated (their sums keep any earlier value)
    const uint32_t* top = integral_.ptr<uint32_t>(y % ring_);
    const uint32_t* bottom = integral_.ptr<uint32_t>((y + s) % ring_);
    auto empty = [&](int x0, int x1) {  // windows x0 .. x1 - 1: columns x0 .. x1 - 2 + s
      const int e = x1 - 1 + s;
      return (bottom[e] - bottom[x0]) - (top[e] - top[x0]) == 0u;
    };
    constexpr int kBlock = 16;
    runs_.clear();  // the runs of blocks with pixels, the same for every template
    for (int b = 0; b < ow;) {
      int e = b;
      while (e < ow && !empty(e, std::min(ow, e + kBlock))) e = std::min(ow, e + kBlock);
      if (e > b) {
        runs_.push_back(b);
        runs_.push_back(e);
      }
      while (e < ow && empty(e, std::min(ow, e + kBlock))) e = std::min(ow, e + kBlock);
      b = e;
    }
    for (int k = 0; k < count; ++k) {
      const Compiled& c = compiled_[k];
      const int pairs = static_cast<int>(c.plus.size());
      if (pairs > kMaxPairs) {
        plus_ptr_.resize(pairs);
        minus_ptr_.resize(pairs);
        for (int i = 0; i < pairs; ++i) {
          plus_ptr_[i] = row(c.plus[i].stair, c.stair, c.plus[i].dy) + c.plus[i].dx;
          minus_ptr_[i] = row(c.minus[i].stair, c.stair, c.minus[i].dy) + c.minus[i].dx;
        }
        accumulate(acc_[k].data(), plus_ptr_.data(), minus_ptr_.data(), pairs, ow);
        continue;
      }
      const uint32_t* plus_row[kMaxPairs];
      const uint32_t* minus_row[kMaxPairs];
      for (int i = 0; i < pairs; ++i) {
        plus_row[i] = row(c.plus[i].stair, c.stair, c.plus[i].dy) + c.plus[i].dx;
        minus_row[i] = row(c.minus[i].stair, c.stair, c.minus[i].dy) + c.minus[i].dx;
      }
      for (size_t j = 0; j < runs_.size(); j += 2) {
        const int b = runs_[j], e = runs_[j + 1];
        const uint32_t* plus[kMaxPairs];
        const uint32_t* minus[kMaxPairs];
        for (int i = 0; i < pairs; ++i) {
          plus[i] = plus_row[i] + b;
          minus[i] = minus_row[i] + b;
        }
        accumulate(acc_[k].data() + b, plus, minus, pairs, e - b);
      }
    }
    sr.top = top;
    sr.bottom = bottom;
    sr.top_sq = integral_sq_.ptr<uint32_t>(y % ring_);
    sr.bottom_sq = integral_sq_.ptr<uint32_t>((y + s) % ring_);
    for (int k = 0; k < count; ++k) sr.out[k] = responses[k]->ptr<float>(y0 + y) + x0;
    if (mask) sr.mark = mask->ptr<uint8_t>(y0 + y) + x0;
    scoreRow(sr, ow);
  }
  return true;
}

}  // namespace rgbd_lane_detector
#endif  // HWY_ONCE
