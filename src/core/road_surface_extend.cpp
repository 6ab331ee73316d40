// The road surface extended toward the camera (RoadSurface::extendToCamera()): where a column's
// nearest depth is road, the road continues down to the image's bottom rows, which LiDAR and
// stereo often leave empty. The fill of a row is a kernel compiled for every SIMD target
// (simd.h); this file is included once per target by Highway's foreach_target.h.
#ifndef RLD_ROAD_SURFACE_EXTEND_ONCE
#define RLD_ROAD_SURFACE_EXTEND_ONCE
#include "rgbd_lane_detector/road_surface.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "rgbd_lane_detector/depth_points.h"
#include "rgbd_lane_detector/geometry.h"
#include "simd.h"

namespace rgbd_lane_detector {
namespace {

/// One image row of the fill: each column at or below its first row to fill gets the point where
/// its ray meets the road plane (rayPlaneDepth() written out), unless the ray misses the plane.
struct FillRow {
  const int* from;      ///< per column: the first row to fill
  int lo, hi;           ///< this row's columns that fill lie in [lo, hi)
  const double* rx;     ///< per column: the ray's x (z = 1)
  const double* nx_rx;  ///< per column: nx rx
  double ny_ry;         ///< this row: ny ry
  double nz;
  double ry;     ///< this row: the ray's y
  double neg_d;  ///< -plane.distance
  int v;         ///< the row
  /// every column's ray of this row meets the plane: the highest (nx rx + ny ry) + nz is below
  /// -1e-9 (rounding is monotonic: no other column's sum is higher)
  bool every_ray_hits;
  float* row;    ///< the row's points (x, y, z per column)
  uint8_t* mark;  ///< the row of the filled mask
};

// Columns [c, w), the definition every vector lane follows (n . ray is (nx rx + ny ry) + nz 1;
// the point is not read: no depth here, the column's nearest depth is above). Returns the
// points filled.
inline int fillTail(const FillRow& f, int c, int w) {
  int count = 0;
  for (int x = c; x < w; ++x) {
    if (f.v < f.from[x]) continue;
    const double den = (f.nx_rx[x] + f.ny_ry) + f.nz * 1.0;
    if (!(den < -1e-9)) continue;  // the ray misses the road plane
    const double t = f.neg_d / den;
    float* p = f.row + 3 * x;
    p[0] = static_cast<float>(f.rx[x] * t);
    p[1] = static_cast<float>(f.ry * t);
    p[2] = static_cast<float>(t);
    f.mark[x] = 255;
    ++count;
  }
  return count;
}

}  // namespace
}  // namespace rgbd_lane_detector
#endif  // RLD_ROAD_SURFACE_EXTEND_ONCE

#ifdef RLD_HAVE_HWY
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "road_surface_extend.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

RLD_KERNELS_BEGIN

#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
// Lane j of the three interleaved vectors (x, y, z of N columns) holds column j / 3.
alignas(64) constexpr int32_t kColumnOfSlot[48] = {
    0,  0,  0,  1,  1,  1,  2,  2,  2,  3,  3,  3,  4,  4,  4,  5,  5,  5,  6,  6,  6,  7,  7,  7,
    8,  8,  8,  9,  9,  9,  10, 10, 10, 11, 11, 11, 12, 12, 12, 13, 13, 13, 14, 14, 14, 15, 15, 15};

// The points of the columns in @p fill stored at p (x, y, z interleaved), the others' left as
// they are: masked stores (native on AVX2 and AVX-512), which need no read of the old points.
// On a sparse LiDAR most vectors fill only some columns (those without any depth stay empty),
// and the read of the old points, far from the cache since depthToPoints() wrote them, was most
// of the fill's time.
template <class DF>
void storeFilled(DF df, hn::Mask<DF> fill, hn::Vec<DF> px, hn::Vec<DF> py, hn::Vec<DF> pz,
                 float* p) {
  const int N = static_cast<int>(hn::Lanes(df));
  static_assert(HWY_MAX_BYTES / sizeof(float) <= 16, "kColumnOfSlot covers 16 lanes");
  HWY_ALIGN float slots[3 * HWY_MAX_BYTES / sizeof(float)];
  hn::StoreInterleaved3(px, py, pz, df, slots);
  const auto m = hn::VecFromMask(df, fill);
  for (int k = 0; k < 3; ++k) {
    const auto slot_fill =
        hn::MaskFromVec(hn::TableLookupLanes(m, hn::SetTableIndices(df, kColumnOfSlot + k * N)));
    hn::BlendedStore(hn::Load(df, slots + k * N), slot_fill, df, p + k * N);
  }
}
#else
// The points of the columns in @p fill stored at p (x, y, z interleaved), the others' kept:
// the old points read and blended (no native masked store on this target).
template <class DF>
void storeFilled(DF df, hn::Mask<DF> fill, hn::Vec<DF> px, hn::Vec<DF> py, hn::Vec<DF> pz,
                 float* p) {
  hn::Vec<DF> ox, oy, oz;
  hn::LoadInterleaved3(df, p, ox, oy, oz);
  hn::StoreInterleaved3(hn::IfThenElse(fill, px, ox), hn::IfThenElse(fill, py, oy),
                        hn::IfThenElse(fill, pz, oz), df, p);
}
#endif

// fillTail() on whole float vectors of columns, lane for lane (the ray in two double halves;
// the points' floats and the mask bytes blended where a lane fills). Returns the columns done;
// *count += the points.
int fillRowKernel(const FillRow& f, int w, int* count) {
  const hn::ScalableTag<float> df;
  const hn::Half<decltype(df)> dfh;
  const hn::Rebind<double, decltype(dfh)> d;  // half as many lanes as df
  const hn::RebindToSigned<decltype(df)> di;
  const hn::Rebind<uint8_t, decltype(di)> d8;
  const int N = static_cast<int>(hn::Lanes(df)), H = static_cast<int>(hn::Lanes(d));
  const auto below = hn::Set(di, f.v + 1);
  const auto ny_ry = hn::Set(d, f.ny_ry), nz = hn::Mul(hn::Set(d, f.nz), hn::Set(d, 1.0)),
             limit = hn::Set(d, -1e-9), neg_d = hn::Set(d, f.neg_d), ry = hn::Set(d, f.ry),
             one = hn::Set(d, 1.0);
  const auto one_f = hn::Set(df, 1.f);
  const auto full_i = hn::Set(di, 255);
  const int x_end = w / N * N;
  // (the vectors from the one holding lo to the one holding hi - 1: the others fill nothing)
  const int x_stop = std::min(x_end, (f.hi + N - 1) / N * N);
  int filled = 0;
  for (int x = f.lo / N * N; x < x_stop; x += N) {
    const auto open = hn::Lt(hn::LoadU(di, f.from + x), below);  // f.v >= from
    if (hn::AllFalse(di, open)) continue;
    const auto den0 = hn::Add(hn::Add(hn::LoadU(d, f.nx_rx + x), ny_ry), nz);
    const auto den1 = hn::Add(hn::Add(hn::LoadU(d, f.nx_rx + x + H), ny_ry), nz);
    auto fill = open;
    if (!f.every_ray_hits) {
      // both conditions in float lanes (each double mask as 1 or 0)
      const auto hit0 = hn::DemoteTo(dfh, hn::IfThenElseZero(hn::Lt(den0, limit), one));
      const auto hit1 = hn::DemoteTo(dfh, hn::IfThenElseZero(hn::Lt(den1, limit), one));
      const auto hit = hn::Eq(hn::Combine(df, hit1, hit0), one_f);
      fill = hn::And(open, hn::RebindMask(di, hit));
      if (hn::AllFalse(di, fill)) continue;
    }
    const auto t0 = hn::Div(neg_d, den0), t1 = hn::Div(neg_d, den1);
    const auto px = hn::Combine(df, hn::DemoteTo(dfh, hn::Mul(hn::LoadU(d, f.rx + x + H), t1)),
                                hn::DemoteTo(dfh, hn::Mul(hn::LoadU(d, f.rx + x), t0)));
    const auto py = hn::Combine(df, hn::DemoteTo(dfh, hn::Mul(ry, t1)),
                                hn::DemoteTo(dfh, hn::Mul(ry, t0)));
    const auto pz = hn::Combine(df, hn::DemoteTo(dfh, t1), hn::DemoteTo(dfh, t0));
    float* p = f.row + 3 * x;
    if (hn::AllTrue(di, fill)) {  // (most vectors below the depth: nothing of the old to keep)
      hn::StoreInterleaved3(px, py, pz, df, p);
      hn::StoreU(hn::Set(d8, uint8_t{255}), d8, f.mark + x);  // (every lane filled)
      filled += N;
      continue;
    }
    storeFilled(df, hn::RebindMask(df, fill), px, py, pz, p);
    // (the mask's row is 0 until this row is filled: extendToCamera() clears it)
    hn::StoreU(hn::DemoteTo(d8, hn::IfThenElseZero(fill, full_i)), d8, f.mark + x);
    filled += static_cast<int>(hn::CountTrue(di, fill));
  }
  *count += filled;
  return x_end;
}

RLD_KERNELS_END
#endif  // RLD_HAVE_HWY

#if HWY_ONCE
namespace rgbd_lane_detector {
namespace {

int fillRowKernelScalar(const FillRow&, int, int*) {
  return 0;  // fillTail() does every column
}
#ifdef RLD_HAVE_HWY
HWY_EXPORT(fillRowKernel);
#endif

// No number among the n floats at p.
bool noNumber(const float* p, int n) {
  int numbers = 0;
  for (int i = 0; i < n; ++i) numbers += p[i] == p[i];
  return numbers == 0;
}

}  // namespace

int RoadSurface::extendToCamera(cv::Mat& points, const cv::Range& rows, const Intrinsics& K,
                                const PlaneEstimate& plane, double band0, double growth,
                                cv::Mat& filled, const cv::Mat& col_map, const cv::Mat& row_map) {
  filled.create(points.size(), CV_8UC1);
  for (int y = 0; y < filled.rows; ++y)  // (cv::Mat::setTo allocates)
    std::memset(filled.ptr<uint8_t>(y), 0, filled.cols);
  if (!plane.valid || points.type() != CV_32FC3) return 0;
  const int r0 = std::max(rows.start, 0);
  const int r1 = std::min(rows.end, points.rows);
  const int w = points.cols;
  const int* cm = col_map.empty() ? nullptr : col_map.ptr<int>();
  const int* rm = row_map.empty() ? nullptr : row_map.ptr<int>();
  // the nearest (lowest) row with depth of every column, rows read in memory order (a column
  // walk strides a whole row per pixel: on sparse LiDAR depth it cost 10 ms at 1600x900), each
  // at the depth blocks with columns still open only; a row without a number at all (by the
  // depth block map, else by a test the compiler vectorises) and blocks without depth are
  // passed over
  fill_from_.assign(w, -1);
  const int nb = (w + kDepthBlock - 1) / kDepthBlock;
  fill_open_.resize(nb);  // per block: its columns still open
  for (int b = 0; b < nb; ++b) fill_open_[b] = std::min(kDepthBlock, w - b * kDepthBlock);
  int open = w;
  for (int y = r1 - 1; y >= r0 && open > 0; --y) {
    const float* row = points.ptr<float>(y);
    const uint8_t* blocks = blockRow(points, y);
    if (blocks ? std::none_of(blocks, blocks + nb, [](uint8_t b) { return b != 0; })
               : open > w / 4 && noNumber(row, 3 * w))
      continue;
    for (int b = 0; b < nb; ++b) {
      if (fill_open_[b] == 0 || (blocks && !blocks[b])) continue;
      const int x1 = std::min(w, (b + 1) * kDepthBlock);
      for (int x = b * kDepthBlock; x < x1; ++x) {
        if (fill_from_[x] >= 0 || std::isnan(row[3 * x + 2])) continue;
        fill_from_[x] = y;
        --fill_open_[b];
        --open;
      }
    }
  }
  // the first row to fill: below a nearest depth on the road; none without depth, below
  // something else (a car, a wall) or with nothing missing below it
  int first = r1;
  for (int x = 0; x < w; ++x) {
    const int y = fill_from_[x];
    fill_from_[x] = r1;
    if (y < r0 || y == r1 - 1) continue;
    const cv::Vec3f& q = points.at<cv::Vec3f>(y, x);
    const double z = q[2];
    const double h = planeDistance(plane, Eigen::Vector3f(q[0], q[1], q[2]));
    if (!(std::fabs(h) <= band0 + growth * z * z)) continue;  // not road: nothing to extend
    fill_from_[x] = y + 1;
    first = std::min(first, y + 1);
  }
  // per row, the span of the columns that fill (a column fills from its first row on): the
  // kernel's vectors pass over the rest of the row (on sparse depth most of it fills nothing)
  // (by row of the points: the same size every frame)
  fill_span_.resize(2 * static_cast<size_t>(points.rows));
  int* span_lo = fill_span_.data();
  int* span_hi = span_lo + points.rows;
  std::fill(span_lo + first, span_lo + r1, w);
  std::fill(span_hi + first, span_hi + r1, 0);
  for (int x = 0; x < w; ++x) {
    if (fill_from_[x] >= r1) continue;
    span_lo[fill_from_[x]] = std::min(span_lo[fill_from_[x]], x);
    span_hi[fill_from_[x]] = x + 1;
  }
  for (int v = first + 1; v < r1; ++v) {
    span_lo[v] = std::min(span_lo[v], span_lo[v - 1]);
    span_hi[v] = std::max(span_hi[v], span_hi[v - 1]);
  }
  // each pixel's ray K.ray(u, v) from its column's and its row's part, and rayPlaneDepth()
  // written out (fillTail()): the products nx rx per column and ny ry per row, once
  const double nx = plane.normal.x(), ny = plane.normal.y(), nz = plane.normal.z();
  fill_rx_.resize(2 * w);
  double* rx = fill_rx_.data();
  double* nx_rx = rx + w;
  double highest_nx_rx = -std::numeric_limits<double>::infinity();
  for (int x = 0; x < w; ++x) {
    rx[x] = K.ray(cm ? cm[x] : x, 0.0).x();
    nx_rx[x] = nx * rx[x];
    // (a column whose product is no number never meets the plane: no row has every ray hit)
    highest_nx_rx = std::isfinite(nx_rx[x]) ? std::max(highest_nx_rx, nx_rx[x])
                                            : std::numeric_limits<double>::infinity();
  }
  FillRow f;
  f.from = fill_from_.data();
  f.rx = rx;
  f.nx_rx = nx_rx;
  f.nz = nz;
  f.neg_d = -plane.distance;
  int count = 0;
  for (int v = first; v < r1; ++v) {
    f.ry = K.ray(0.0, rm ? rm[v] : v).y();
    f.ny_ry = ny * f.ry;
    f.every_ray_hits = (highest_nx_rx + f.ny_ry) + nz * 1.0 < -1e-9;
    f.v = v;
    f.lo = span_lo[v];
    f.hi = span_hi[v];
    f.row = points.ptr<float>(v);
    f.mark = filled.ptr<uint8_t>(v);
    const int done = RLD_DISPATCH(fillRowKernel)(f, w, &count);
    count += fillTail(f, done, w);
  }
  return count;
}

}  // namespace rgbd_lane_detector
#endif  // HWY_ONCE
