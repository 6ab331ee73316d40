// Stage 3: FALS normals and G. The row kernels (fals_kernels-inl.h) are compiled for every SIMD
// target (simd.h); this file is included once per target by Highway's foreach_target.h.
#ifndef RLD_FALS_NORMALS_ONCE
#define RLD_FALS_NORMALS_ONCE
#include "rgbd_lane_detector/fals_normals.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "fals_units.h"
#include "fals_window.h"
#include "simd.h"

namespace rgbd_lane_detector {
using namespace fals;  // NOLINT: the window algebra and mask units, also in the kernels
namespace {

bool sameMap(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() != b.empty()) return false;
  if (a.empty()) return true;
  return a.total() == b.total() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

}  // namespace
}  // namespace rgbd_lane_detector
#endif  // RLD_FALS_NORMALS_ONCE

#ifdef RLD_HAVE_HWY
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "fals_normals.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

RLD_KERNELS_BEGIN
#include "fals_kernels-inl.h"
RLD_KERNELS_END
#endif  // RLD_HAVE_HWY

#if HWY_ONCE
namespace rgbd_lane_detector {
namespace {
// The scalar target: no column done by a vector (the loops of FalsNormals do them all).
void falsPrepareScalar(const float*, const float*, int x0, int, float*, float*, float*, float*,
                       uint64_t*, int& done) {
  done = x0;
}
void falsVerticalScalar(int, const float* const*, int, int x0, int, const uint64_t*, float* const*,
                        int& done) {
  done = x0;
}
void falsHorizontalScalar(int, const float* const*, const float* const*, int x0, int, const float*,
                          const float*, const RowConst&, const float*, const float*, float*, float*,
                          const uint64_t*, int*, int&, int& done) {
  done = x0;
}
void falsExactScalar(int, const float* const*, const float* const*, const float* const*,
                     const double*, int, int x0, int, const double*, const float*, double, double,
                     double, double, const float*, double*, std::ptrdiff_t, float*, uint8_t*,
                     const RowConst&, const float*, float*, int& done) {
  done = x0;
}
#ifdef RLD_HAVE_HWY
HWY_EXPORT(falsExact);
HWY_EXPORT(falsPrepare);
HWY_EXPORT(falsVertical);
HWY_EXPORT(falsHorizontal);
#endif
}  // namespace

struct FalsNormals::Output {
  cv::Mat* normals = nullptr;
  cv::Mat* G = nullptr;
  const cv::Mat* mask = nullptr;  ///< G only where nonzero (no normals then)
  RowConst base;  ///< G constants (row fields are filled per row)
};


void FalsNormals::configure(const cv::Size& size, const Intrinsics& K, int window,
                            const cv::Mat& col_map, const cv::Mat& row_map) {
  if (size == size_ && window == window_ && K == K_ && sameMap(col_map, col_map_) &&
      sameMap(row_map, row_map_) && !k_.empty())
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
    ax_[x] = static_cast<float>(K.ray(src_u_[x], 0.0).x());
  }
  for (int y = 0; y < H; ++y) {
    src_v_[y] = row_map_.empty() ? y : row_map_.at<int>(y);
    ay_[y] = static_cast<float>(K.ray(0.0, src_v_[y]).y());
  }
  // The separable path needs equally spaced source pixels (x -> a + step x).
  auto uniform = [](const std::vector<int>& m, float& step) {
    step = m.size() > 1 ? static_cast<float>(m[1] - m[0]) : 1.f;
    for (size_t i = 1; i < m.size(); ++i)
      if (m[i] - m[i - 1] != m[1] - m[0]) return false;
    return step > 0.f;
  };
  uniform_ = uniform(src_u_, step_u_) & uniform(src_v_, step_v_);

  k_.create(size, CV_32FC1);
  for (int y = 0; y < H; ++y) {
    float* k = k_.ptr<float>(y);
    for (int x = 0; x < W; ++x) {
      const Eigen::Vector3d w = K.ray(src_u_[x], src_v_[y]);
      k[x] = static_cast<float>(1.0 / (w.x() * w.x() + w.y() * w.y() + 1.0));
    }
  }
  ncols_.resize(W);
  for (int x = 0; x < W; ++x)
    ncols_[x] = static_cast<float>(std::min(W - 1, x + h) - std::max(0, x - h) + 1);

  table_.release();  // computed for the rows in use by the first run()
  table_rows_ = cv::Range(0, 0);
  prep_.create(4 * (2 * h + 1), W, CV_32FC1);
  vert_.create(kPlanes, W + 2 * h, CV_32FC1);
  vert_.setTo(0);  // the h columns each side stay 0: outside the image
  slow_.resize(W);
  column_.resize(kColumnSums * static_cast<size_t>(W));
  column_row_.assign(W, -1);
  // the vector exact path (falsExact): padded column sums and source columns, its outputs
  exact_cols_.assign(kColumnSums * static_cast<size_t>(W + 2 * h), 0.0);
  exact_su_.resize(W + 2 * h);
  for (int x = -h; x < W + h; ++x) exact_su_[x + h] = src_u_[std::min(W - 1, std::max(0, x))];
  exact_n_.resize(3 * static_cast<size_t>(W));
  exact_ok_.resize(W);
}

void FalsNormals::ensureTable(const cv::Range& rows) {
  if (!uniform_ || (rows.start >= table_rows_.start && rows.end <= table_rows_.end)) return;
  // adj(Q) of every window without missing pixels (clipped by the image), in double: moments of
  // k over offsets in processing pixels (the source step is folded into fx / step, fy / step).
  // Kept for the rows in use only (24 bytes per pixel).
  if (table_rows_.size() > 0)
    table_rows_ =
        cv::Range(std::min(rows.start, table_rows_.start), std::max(rows.end, table_rows_.end));
  else
    table_rows_ = rows;
  const int W = size_.width, H = size_.height, h = window_ / 2, n = table_rows_.size();
  table_.create(6 * n, W, CV_32FC1);
  std::vector<double> vk(3 * static_cast<size_t>(W));
  for (int y = table_rows_.start; y < table_rows_.end; ++y) {
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
      const double q[6] = {K0, Ku, Kv, Kuu, Kuv, Kvv};
      double a[6];
      symmetricAdjugate(q, a);
      for (int j = 0; j < 6; ++j)
        table_.ptr<float>(j * n + y - table_rows_.start)[x] = static_cast<float>(a[j]);
    }
  }
}

void FalsNormals::prepareRow(const cv::Mat& points, int y, const uint64_t* units, float* kv,
                             float* t, float* c, float* z, uint64_t* bad) const {
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
  forEachRun(units, W, [&](int x0, int x1) {
    int x = x0;
    RLD_DISPATCH(falsPrepare)(p, k, x0, x1, kv, t, c, z, bad, x);
    for (; x < x1; ++x) {
      const float d = z[x] = p[3 * x + 2];
      const bool valid = d > 0.f && d < kInf;
      kv[x] = valid ? k[x] : 0.f;
      t[x] = valid ? k[x] / d : 0.f;
      c[x] = valid ? 1.f : 0.f;
      if (!valid) bad[x / 512] |= uint64_t{1} << (x / 8 % 64);
    }
  });
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
  // the count first: fewer than 3 valid pixels solve nothing (most windows on a sparse LiDAR's
  // depth); then the other sums, where a column without a valid pixel adds nothing (its sums
  // are +0, and no sum here is -0: skipping it keeps every bit)
  double N = 0;
  for (int xx = std::max(0, x - h); xx <= std::min(W - 1, x + h); ++xx)
    N += column_[kColumnSums * xx + 5];
  if (N < 3.0) return false;
  double K0 = 0, Ku = 0, Kv = 0, Kuu = 0, Kuv = 0, Kvv = 0, T0 = 0, Tu = 0, Tv = 0;
  double Nu = 0, Nuu = 0, Nv = 0, Nvv = 0;
  for (int xx = std::max(0, x - h); xx <= std::min(W - 1, x + h); ++xx) {
    const double* v = &column_[kColumnSums * xx];
    if (v[5] == 0.0) continue;
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
  const double q[6] = {K0, Ku, Kv, Kuu, Kuv, Kvv};
  double a[6], m[3];
  symmetricAdjugate(q, a);
  adjugateTimes(a, T0, Tu, Tv, m);
  const double n0 = K_.fx * m[1], n1 = K_.fy * m[2];
  const double n2 = m[0] - ax_[x] * n0 - ay_[y] * n1;
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
  if (normals) normals->create(size_, CV_32FC3);
  Output out = geometricOutput(p, G);
  out.normals = normals;
  run(points, rows, out);
}

void FalsNormals::computeGeometric(const cv::Mat& points, const cv::Range& rows, const Params& p,
                                   const cv::Mat& mask, cv::Mat& G) {
  CV_Assert(points.type() == CV_32FC3 && points.size() == size_ && window_ > 0 &&
            mask.type() == CV_8UC1 && mask.size() == size_);
  Output out = geometricOutput(p, G);
  out.mask = &mask;
  run(points, rows, out);
}

FalsNormals::Output FalsNormals::geometricOutput(const Params& p, cv::Mat& G) const {
  if (G.size() != size_ || G.type() != CV_32FC1) {
    G.create(size_, CV_32FC1);
    G.setTo(0);
  }
  Output out;
  out.G = &G;
  RowConst& rc = out.base;
  rc.alpha = static_cast<float>(p.alpha);
  rc.beta = static_cast<float>(p.beta);
  rc.td = static_cast<float>(p.depth_threshold);
  rc.inv_td = static_cast<float>(1.0 / p.depth_threshold);
  rc.near_high = p.depth_term == DepthTerm::kNearHigh;
  rc.up[0] = static_cast<float>(p.up_x);
  rc.up[1] = static_cast<float>(p.up_y);
  rc.up[2] = static_cast<float>(p.up_z);
  return out;
}

void FalsNormals::run(const cv::Mat& points, const cv::Range& rows, const Output& out) {
  const int W = size_.width, H = size_.height, h = window_ / 2, span = 2 * h + 1;
  const int r0 = std::max(rows.start, 0), r1 = std::min(rows.end, H);
  if (r0 >= r1) return;
  ensureTable(cv::Range(r0, r1));

  // With a mask: per output row, the units to solve (any mask pixel) and the units whose
  // vertical sums they read (one more each side: h <= 3 columns); a prepared row covers the
  // latter of every output row whose window it is in. Without: every column (nullptr).
  const int units = (W + kUnit - 1) / kUnit, nu = (units + 63) / 64;
  const bool masked = out.mask != nullptr;
  if (masked) {
    solve_units_.resize(static_cast<size_t>(r1 - r0) * nu);
    read_units_.resize(solve_units_.size());
    prep_units_.resize(nu);
    for (int y = r0; y < r1; ++y) {
      uint64_t* solve = &solve_units_[static_cast<size_t>(y - r0) * nu];
      unitsOfRow(out.mask->ptr<uint8_t>(y), W, solve);
      dilateUnits(solve, units, &read_units_[static_cast<size_t>(y - r0) * nu]);
    }
  }
  auto solveUnits = [&](int y) -> const uint64_t* {
    return masked ? &solve_units_[static_cast<size_t>(y - r0) * nu] : nullptr;
  };
  auto readUnits = [&](int y) -> const uint64_t* {
    return masked ? &read_units_[static_cast<size_t>(y - r0) * nu] : nullptr;
  };

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
    const uint64_t* cover = nullptr;
    if (masked) {
      std::fill(prep_units_.begin(), prep_units_.end(), uint64_t{0});
      for (int y = std::max(r0, r - h); y <= std::min(r1 - 1, r + h); ++y)
        for (int j = 0; j < nu; ++j) prep_units_[j] |= readUnits(y)[j];
      cover = prep_units_.data();
    }
    prepareRow(points, r, cover, a, a + W, a + 2 * W, a + 3 * W,
               &bad_[static_cast<size_t>(i) * nw]);
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
    float* grow = out.G ? out.G->ptr<float>(y) : nullptr;
    const uint64_t* solve = solveUnits(y);
    if (masked && std::all_of(solve, solve + nu, [](uint64_t b) { return b == 0; })) {
      std::fill(grow, grow + W, 0.f);  // nothing to solve in this row
      continue;
    }
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
    // the exact path: normals already of unit length
    auto exact = [&](int x) {
      float n[3] = {0.f, 0.f, 0.f};
      const bool ok = solveWindow(x, y, kv_rows, t_rows, c_rows, n);
      finish(n, ok, prow + 3 * x, ax_[x], rc, nrow ? nrow + 3 * x : nullptr,
             grow ? grow + x : nullptr);
    };

    if (!uniform_ || referenceStages()) {
      // resampled at an uneven step (no separable sums), or the reference: every window exactly,
      // several windows per vector (the same double operations) unless the reference
      double fv[7];
      for (int d = -h; d <= h; ++d)
        fv[h + d] = y + d < 0 || y + d >= H ? 0.0 : src_v_[y + d] - src_v_[y];
      const double full_rows = std::min(H - 1, y + h) - std::max(0, y - h) + 1;
      float* gv = nrow ? nullptr : grow;  // G in the kernel when no normals are wanted
      forEachRun(solve, W, [&](int x0, int x1) {
        int x = x0;
        if (!referenceStages()) {
          RLD_DISPATCH(falsExact)
          (h, kv_rows, t_rows, c_rows, fv, W, x0, x1, exact_su_.data() + h, ax_.data(), ay_[y],
           K_.fx, K_.fy, full_rows, ncols_.data(), exact_cols_.data() + h, W + 2 * h,
           exact_n_.data(), exact_ok_.data(), rc, kv_rows[h] + 3 * W, gv, x);
          if (!gv) {
            for (int i = x0; i < x; ++i) {
              const float n[3] = {exact_n_[i], exact_n_[W + i], exact_n_[2 * W + i]};
              finish(n, exact_ok_[i], prow + 3 * i, ax_[i], rc, nrow ? nrow + 3 * i : nullptr,
                     grow ? grow + i : nullptr);
            }
          }
        }
        for (; x < x1; ++x) exact(x);
      });
      if (masked) zeroOutsideMask(out.mask->ptr<uint8_t>(y), solve, W, grow);
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
    forEachRun(readUnits(y), W, [&](int x0, int x1) {
      int x = x0;
      RLD_DISPATCH(falsVertical)(h, kv_rows, W, x0, x1, near_v, vert, x);
      for (; x < x1; ++x) {
        float unused;
        momentsRows(t_rows, x, h, vert[kW0][x], vert[kW1][x], unused);
        momentsRows(c_rows, x, h, vert[kC][x], vert[kCv1][x], vert[kCv2][x]);
        momentsRows(kv_rows, x, h, vert[kV0][x], vert[kV1][x], vert[kV2][x]);
      }
    });

    // horizontal sums, solve and outputs; ill-conditioned windows go to the exact path
    const float* table[6];
    for (int j = 0; j < 6; ++j)
      table[j] = table_.ptr<float>(j * table_rows_.size() + y - table_rows_.start);
    int n_slow = 0;
    forEachRun(solve, W, [&](int x0, int x1) {
      int x = x0;
      RLD_DISPATCH(falsHorizontal)
      (h, vert, table, x0, x1, ncols_.data(), ax_.data(), rc, prow, kv_rows[h] + 3 * W, nrow, grow,
       near_h, slow_.data(), n_slow, x);
      for (; x < x1; ++x) {
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
    });
    for (int i = 0; i < n_slow; ++i) exact(slow_[i]);
    if (masked) zeroOutsideMask(out.mask->ptr<uint8_t>(y), solve, W, grow);
  }
}

}  // namespace rgbd_lane_detector
#endif  // HWY_ONCE
