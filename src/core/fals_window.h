// The per-window algebra of FALS normals (fals_normals.cpp and its vector kernels,
// fals_kernels-inl.h; falsNormalAt()): moments of a window's rows and columns, the symmetric 3x3
// solve by the adjugate, the solve of a window's Q from its moments (whole windows from a table of
// adj(Q), windows with missing pixels from their own), and a pixel's oriented normal and G. The
// scalar definition every vector lane follows: same operations, same order (-ffp-contract=off).
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>

namespace rgbd_lane_detector {
namespace fals {

/**
 * @brief adj(Q) of the symmetric 3x3 Q = [q0 q1 q2; q1 q3 q4; q2 q4 q5] (its upper triangle row
 * by row), the same six entries of the symmetric adj(Q): Q adj(Q) = det(Q) I.
 */
template <typename T>
inline void symmetricAdjugate(const T q[6], T a[6]) {
  a[0] = q[3] * q[5] - q[4] * q[4];
  a[1] = q[4] * q[2] - q[1] * q[5];
  a[2] = q[1] * q[4] - q[3] * q[2];
  a[3] = q[0] * q[5] - q[2] * q[2];
  a[4] = q[1] * q[2] - q[0] * q[4];
  a[5] = q[0] * q[3] - q[1] * q[1];
}

/// m = adj(Q) s for the six entries of symmetricAdjugate() (Q^-1 s times det Q), each row summed
/// left to right.
template <typename T>
inline void adjugateTimes(const T a[6], T s0, T s1, T s2, T m[3]) {
  m[0] = (a[0] * s0 + a[1] * s1) + a[2] * s2;
  m[1] = (a[1] * s0 + a[3] * s1) + a[4] * s2;
  m[2] = (a[2] * s0 + a[4] * s1) + a[5] * s2;
}

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// Planes of one row of vertical sums over the window's rows (offset dv from the centre row):
// box and first moment in dv of t = k / z (valid pixels), box of the valid flag c; where pixels
// are missing also box, first and second moment of kv = k c and the moments of c.
enum Plane { kW0, kW1, kC, kV0, kV1, kV2, kCv1, kCv2, kPlanes };

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

// Q m = s up to the positive factor det Q, from the precomputed adj(Q) of a window without missing
// pixels: m' = adj(Q) s, then n' = B^-T m' = (fxs m1, fys m2, m0 - ax n'x - ay n'y).
// Same operation order as the vector code.
inline void solveTable(const float a[6], float T0, float Tu, float Tv, float ax, const RowConst& rc,
                       float n[3]) {
  float m[3];
  adjugateTimes(a, T0, Tu, Tv, m);
  n[0] = rc.fxs * m[1];
  n[1] = rc.fys * m[2];
  n[2] = (m[0] - ax * n[0]) - rc.ay * n[1];
}

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
  const float Q[6] = {q.K0, q.Ku, q.Kv, q.Kuu, q.Kuv, q.Kvv};
  float a[6];
  symmetricAdjugate(Q, a);
  const float det = (q.K0 * a[0] + q.Ku * a[1]) + q.Kv * a[2];
  const bool well = det > kWellConditioned * ((q.K0 * q.Kuu) * q.Kvv);
  solveTable(a, T0, Tu, Tv, ax, rc, n);
  return !span ? PartialCase::kNone : (well ? PartialCase::kFloat : PartialCase::kExact);
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

}  // namespace fals
}  // namespace rgbd_lane_detector
