// Stage 7: sliding-box tracing. The box sums (the stage's hot loop) are compiled for every SIMD
// target (simd.h); this file is included once per target by Highway's foreach_target.h.
#ifndef RLD_SLIDING_BOX_ONCE
#define RLD_SLIDING_BOX_ONCE
#include "rgbd_lane_detector/sliding_box.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "rgbd_lane_detector/geometry.h"
#include "simd.h"
#endif

#ifdef RLD_HAVE_HWY
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "sliding_box.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

RLD_KERNELS_BEGIN

// Pixels of r[0, w) above threshold among the whole vectors: their count and the sum of their
// columns (from 0); returns the columns done.
int boxRow(const float* r, int w, float threshold, int& count, int64_t& sum_x) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const int N = static_cast<int>(hn::Lanes(df));
  const auto thr = hn::Set(df, threshold);
  auto cols = hn::Iota(di, 0);
  auto sums = hn::Zero(di);  // column sums per lane: below 2^31 for any image row
  int x = 0;
  for (; x + N <= w; x += N) {
    const auto above = hn::Gt(hn::LoadU(df, r + x), thr);
    count += static_cast<int>(hn::CountTrue(df, above));
    sums = hn::Add(sums, hn::IfThenElseZero(hn::RebindMask(di, above), cols));
    cols = hn::Add(cols, hn::Set(di, N));
  }
  sum_x += hn::GetLane(hn::SumOfLanes(di, sums));
  return x;
}

RLD_KERNELS_END
#endif  // RLD_HAVE_HWY

#if HWY_ONCE
namespace rgbd_lane_detector {
namespace {

// The scalar target: no column done by a vector (boxCentroid() does them all).
int boxRowScalar(const float*, int, float, int&, int64_t&) {
  return 0;
}
#ifdef RLD_HAVE_HWY
HWY_EXPORT(boxRow);
#endif

// The trace runs in columns from the image's centre column, x - ox with ox = (width - 1) / 2, so
// that a mirrored road (x -> width - 1 - x) is traced with every float operation negated: the
// same rounding, the mirrored boxes. Conversions go through double, where they are exact.
struct Columns {
  double ox;
  double absolute(float x) const { return static_cast<double>(x) + ox; }
  float centred(double x) const { return static_cast<float>(x - ox); }
};

// Pixels above threshold in a rectangle (clipped to bounds): their count and column and row sums.
void boxSums(const cv::Mat& R, const cv::Rect& rect, float threshold, const cv::Rect& bounds,
             int64_t& n, int64_t& sx, int64_t& sy) {
  const cv::Rect box = rect & bounds;
  n = sx = sy = 0;
  for (int y = box.y; y < box.y + box.height; ++y) {
    const float* r = R.ptr<float>(y) + box.x;
    int count = 0;
    int64_t sum_x = 0;
    int x = RLD_DISPATCH(boxRow)(r, box.width, threshold, count, sum_x);
    for (; x < box.width; ++x) {
      if (r[x] > threshold) {
        sum_x += x;
        ++count;
      }
    }
    sx += sum_x + static_cast<int64_t>(box.x) * count;
    sy += static_cast<int64_t>(y) * count;
    n += count;
  }
}

// Centroid of the pixels above threshold in the box of side s centred at c (centred columns,
// clipped to bounds); returns their number (weighted). The sums are exact integers, so every
// target gives the same centroid. An odd s (a template with a centre pixel): the columns whose
// centres are within s / 2 of c.x; where the box's ends fall on pixel centres (c.x halfway
// between two pixels) the two end columns count half, so that a mirrored centre has the mirrored
// box. An even s keeps the s columns from floor(c.x - s / 2 + 0.5), the box of c.x - 0.5 (as the
// matcher writes an even template's score half a pixel right of its centre, nothing after it is
// symmetric; the symmetric box measured worse on the real corpus with it).
int64_t boxCentroid(const cv::Mat& R, const cv::Point2f& c, int s, float threshold,
                    const cv::Rect& bounds, const Columns& cols, cv::Point2f& centroid) {
  const double a = cols.absolute(c.x);
  int x0 = static_cast<int>(std::floor(a - 0.5 * s + 0.5)), x1 = x0 + s - 1;
  if (s % 2 == 1) {
    x0 = static_cast<int>(std::ceil(a - 0.5 * s));
    x1 = static_cast<int>(std::floor(a + 0.5 * s));
  }
  const int y0 = static_cast<int>(std::floor(c.y - 0.5f * s + 0.5f));
  int64_t n = 0, sx = 0, sy = 0;
  boxSums(R, cv::Rect(x0, y0, x1 - x0 + 1, s), threshold, bounds, n, sx, sy);
  if (x1 - x0 == s) {  // half end columns: every sum doubled, the ends' taken once
    int64_t n0, sx0, sy0, n1, sx1, sy1;
    boxSums(R, cv::Rect(x0, y0, 1, s), threshold, bounds, n0, sx0, sy0);
    boxSums(R, cv::Rect(x1, y0, 1, s), threshold, bounds, n1, sx1, sy1);
    n = 2 * n - n0 - n1;
    sx = 2 * sx - sx0 - sx1;
    sy = 2 * sy - sy0 - sy1;
  }
  // x - ox = (2 sx - (width - 1) n) / 2n: an exact integer numerator, negated by a mirror
  if (n > 0)
    centroid = cv::Point2f(
        static_cast<float>(static_cast<double>(2 * sx - static_cast<int64_t>(2.0 * cols.ox) * n) /
                           (2.0 * static_cast<double>(n))),
        static_cast<float>(static_cast<double>(sy) / static_cast<double>(n)));
  return n;
}

float sampleR(const cv::Mat& R, const cv::Point2f& p, const Columns& cols) {
  const int x = std::min(std::max(roundColumn(cols.absolute(p.x), R.cols), 0), R.cols - 1);
  const int y = std::min(std::max(static_cast<int>(std::lround(p.y)), 0), R.rows - 1);
  return R.at<float>(y, x);
}

// Trace one direction; appends the recorded centroids (in tracing order).
void traceDirection(const cv::Mat& R, const cv::Point2f& start, cv::Point2f d,
                    const TraceParams& tp, const cv::Rect& bounds, const Columns& cols,
                    std::vector<cv::Point2f>& out, std::vector<float>& scores) {
  cv::Point2f pos = start;
  cv::Point2f last = start;  // last recorded centroid
  const cv::Point2f d0 = d;
  const float cos_max_turn = static_cast<float>(std::cos(tp.max_turn));
  const float jump = static_cast<float>(std::max(tp.jump, 1));
  int gaps = 0;
  for (int step = 0; step < tp.max_steps; ++step) {
    const cv::Point2f next = pos + jump * d;
    const double next_x = cols.absolute(next.x);
    if (next_x < bounds.x || next.y < bounds.y || next_x >= bounds.x + bounds.width ||
        next.y >= bounds.y + bounds.height)
      break;
    cv::Point2f c;
    if (boxCentroid(R, next, tp.box_size, tp.threshold, bounds, cols, c) == 0) {
      if (++gaps > tp.gap_steps) break;
      pos = next;
      continue;
    }
    gaps = 0;
    // Re-centre across the marker, keep the progress along it (Eq. 4 without moving back).
    const cv::Point2f n(-d.y, d.x);
    const float lateral = (c - next).dot(n);
    pos = next + lateral * n;
    const cv::Point2f delta = c - last;
    if (delta.dot(d) >= 0.5f * jump) {
      out.push_back(c);
      scores.push_back(sampleR(R, c, cols));
      if (tp.follow_curve) {
        const float len = std::sqrt(delta.dot(delta));
        if (len >= jump) {
          cv::Point2f nd = 0.5f * d + 0.5f * (delta / len);
          const float nl = std::sqrt(nd.dot(nd));
          // a marker bends gently in the image; a trace turning further than max_turn from
          // its start has left the marker (a vehicle's edge, a shadow boundary)
          if (nl > 1e-6f && (nd / nl).dot(d0) >= cos_max_turn) d = nd / nl;
        }
      }
      last = c;
    }
  }
}

}  // namespace

void traceMarker(const cv::Mat& R, const cv::Point2f& seed, double angle, const TraceParams& params,
                 const cv::Rect& bounds_in, std::vector<cv::Point2f>& centroids,
                 std::vector<float>& scores) {
  centroids.clear();
  scores.clear();
  if (R.empty() || R.type() != CV_32FC1) return;
  const cv::Rect bounds = bounds_in & cv::Rect(0, 0, R.cols, R.rows);
  if (bounds.empty() ||
      !bounds.contains(cv::Point(static_cast<int>(seed.x), static_cast<int>(seed.y))))
    return;
  const Columns cols{0.5 * (R.cols - 1)};
  cv::Point2f start;
  if (boxCentroid(R, cv::Point2f(cols.centred(seed.x), seed.y), params.box_size,
                  params.threshold, bounds, cols, start) == 0)
    return;

  const cv::Point2f down(static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle)));
  // near part: trace down, then reverse so that the list runs near to far
  traceDirection(R, start, down, params, bounds, cols, centroids, scores);
  std::reverse(centroids.begin(), centroids.end());
  std::reverse(scores.begin(), scores.end());
  centroids.push_back(start);
  scores.push_back(sampleR(R, start, cols));
  traceDirection(R, start, -down, params, bounds, cols, centroids, scores);
  for (auto& c : centroids) c.x = static_cast<float>(cols.absolute(c.x));
}

}  // namespace rgbd_lane_detector
#endif  // HWY_ONCE
