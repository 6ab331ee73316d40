// FALS vector kernels, written once with Google Highway and included by fals_normals.cpp in its
// per-target section (once per SIMD target, inside rgbd_lane_detector::HWY_NAMESPACE). Every lane
// repeats the scalar code's operations in the same order (no FMA contraction: the core is built
// with -ffp-contract=off), so all targets give the same bits. Uses RowConst, finish(), the Plane
// indices and kWellConditioned of fals_window.h.

/// The float vectors of the target (at most 16 lanes: masks fit an unsigned) as the few
/// operations the kernels use.
struct V {
  using D = hn::CappedTag<float, 16>;
  static constexpr int N = static_cast<int>(hn::MaxLanes(D()));
  using T = hn::Vec<D>;
  using M = hn::Mask<D>;
  static T load(const float* p) { return hn::LoadU(D(), p); }
  static void store(float* p, T v) { hn::StoreU(v, D(), p); }
  static T set1(float f) { return hn::Set(D(), f); }
  static T zero() { return hn::Zero(D()); }
  static T add(T a, T b) { return hn::Add(a, b); }
  static T sub(T a, T b) { return hn::Sub(a, b); }
  static T mul(T a, T b) { return hn::Mul(a, b); }
  static T div(T a, T b) { return hn::Div(a, b); }
  static T sqrt(T a) { return hn::Sqrt(a); }
  static T abs(T a) { return hn::Abs(a); }
  static M gt(T a, T b) { return hn::Gt(a, b); }
  static M ge(T a, T b) { return hn::Ge(a, b); }
  static M lt(T a, T b) { return hn::Lt(a, b); }
  static M le(T a, T b) { return hn::Le(a, b); }
  static M eq(T a, T b) { return hn::Eq(a, b); }
  static M mand(M a, M b) { return hn::And(a, b); }
  static M mor(M a, M b) { return hn::Or(a, b); }
  static M mandnot(M a, M b) { return hn::AndNot(a, b); }  // b and not a
  static M ones() { return hn::FirstN(D(), N); }
  static T select(M m, T a, T b) { return hn::IfThenElse(m, a, b); }  // m ? a : b
  static T keep(M m, T a) { return hn::IfThenElseZero(m, a); }
  static bool none(M m) { return hn::AllFalse(D(), m); }
  static unsigned bits(M m) {  // bit i: lane i
    uint8_t b[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    hn::StoreMaskBits(D(), m, b);
    return static_cast<unsigned>(b[0]) | static_cast<unsigned>(b[1]) << 8;
  }
  // z of N interleaved points (x, y, z) starting at p
  static T loadZ(const float* p) {
    T x, y, z;
    hn::LoadInterleaved3(D(), p, x, y, z);
    return z;
  }
};

using VT = V::T;
using VM = V::M;
constexpr unsigned kAllLanes = V::N >= 32 ? ~0u : (1u << V::N) - 1u;

// moments() for V::N adjacent x: the value at offset d is at p + d * stride.
template <int H, bool kSecond = false>
inline void momentsV(const float* p, std::ptrdiff_t stride, VT& box, VT& m1, VT* m2 = nullptr) {
  box = V::load(p);
  m1 = V::zero();
  VT second = V::zero();
  for (int d = 1; d <= H; ++d) {
    const VT a0 = V::load(p + d * stride), b0 = V::load(p - d * stride);
    const VT a = V::add(a0, b0);
    box = V::add(box, a);
    m1 = V::add(m1, V::mul(V::set1(static_cast<float>(d)), V::sub(a0, b0)));
    if (kSecond) second = V::add(second, V::mul(V::set1(static_cast<float>(d * d)), a));
  }
  if (kSecond) *m2 = second;
}

// The same over separate rows: the value at offset d is at rows[H + d] + off.
template <int H, bool kSecond = false>
inline void momentsRowsV(const float* const* rows, std::ptrdiff_t off, VT& box, VT& m1,
                         VT* m2 = nullptr) {
  box = V::load(rows[H] + off);
  m1 = V::zero();
  VT second = V::zero();
  for (int d = 1; d <= H; ++d) {
    const VT a0 = V::load(rows[H + d] + off), b0 = V::load(rows[H - d] + off);
    const VT a = V::add(a0, b0);
    box = V::add(box, a);
    m1 = V::add(m1, V::mul(V::set1(static_cast<float>(d)), V::sub(a0, b0)));
    if (kSecond) second = V::add(second, V::mul(V::set1(static_cast<float>(d * d)), a));
  }
  if (kSecond) *m2 = second;
}

// Any of the 8-pixel blocks covering columns [from, to) marked in the bit set.
inline bool anyBlockIn(const uint64_t* bits, int from, int to) {
  for (int b = from / 8; b <= (to - 1) / 8; ++b)
    if (bits[b / 64] >> (b % 64) & 1) return true;
  return false;
}

// Any of the 8-pixel blocks covering columns x .. x + V::N - 1 marked in the bit set.
inline bool anyBlock(const uint64_t* bits, int x) {
  return anyBlockIn(bits, x, x + V::N);
}

// Prepared row (kv, t, c and z itself) over the columns [x0, n) of the row's arrays; bit b of
// bad: block b has invalid pixels.
void prepare(const float* p, const float* k, int x0, int n, float* kv, float* t, float* c,
             float* zs, uint64_t* bad, int& done) {
  const VT zero = V::zero(), inf = V::set1(kInf), one = V::set1(1.f);
  int x = x0;
  for (; x + V::N <= n; x += V::N) {
    const VT z = V::loadZ(p + 3 * x), kk = V::load(k + x);
    V::store(zs + x, z);
    const VM valid = V::mand(V::gt(z, zero), V::lt(z, inf));
    V::store(kv + x, V::keep(valid, kk));
    V::store(t + x, V::keep(valid, V::div(kk, V::select(valid, z, one))));
    V::store(c + x, V::keep(valid, one));
    for (unsigned invalid = ~V::bits(valid) & kAllLanes; invalid; invalid &= invalid - 1) {
      const int b = (x + __builtin_ctz(invalid)) / 8;  // the block of an invalid pixel
      bad[b / 64] |= uint64_t{1} << (b % 64);
    }
  }
  done = x;
}

// Vertical sums of the columns [x0, x1), V::N at a time: rows[H + d] holds the prepared row at
// offset d (planes kv, t, c at 0, W, 2 W). The kv and c moments are only needed near missing
// pixels (bits of holes).
template <int H>
void vertical(const float* const* rows, int W, int x0, int x1, const uint64_t* holes,
              float* const* out, int& done) {
  int x = x0;
  for (; x + V::N <= x1; x += V::N) {
    VT w0, w1, n, n1, n2;
    momentsRowsV<H>(rows, W + x, w0, w1);
    V::store(out[kW0] + x, w0);
    V::store(out[kW1] + x, w1);
    // the count is read by horizontal() only on vectors near missing pixels (their windows reach
    // into the vectors each side) and by its scalar tail (left of it: the last vector)
    if (!anyBlock(holes, x)) {
      if (x + 2 * V::N <= W && !anyBlockIn(holes, std::max(0, x - V::N), std::min(W, x + 2 * V::N)))
        continue;
      momentsRowsV<H>(rows, 2 * W + x, n, n1);
      V::store(out[kC] + x, n);
      continue;
    }
    VT v0, v1, v2;
    momentsRowsV<H, true>(rows, 2 * W + x, n, n1, &n2);
    momentsRowsV<H, true>(rows, x, v0, v1, &v2);
    V::store(out[kC] + x, n);
    V::store(out[kCv1] + x, n1);
    V::store(out[kCv2] + x, n2);
    V::store(out[kV0] + x, v0);
    V::store(out[kV1] + x, v1);
    V::store(out[kV2] + x, v2);
  }
  done = x;
}

// Horizontal sums, solve and G of the columns [x0, n), V::N pixels per step. Bits of holes: missing
// pixels within reach of the block's windows. Windows without missing pixels use the precomputed
// adj(Q) (table planes at table[j] + x), the others solvePartial(), whose ill-conditioned columns
// are appended to `slow` for the exact double path (their G is written there). Normals (rarely
// wanted) are finished by the scalar code from the same n'.
template <int H>
void horizontal(const float* const* vert, const float* const* table, int x0, int n,
                const float* ncols, const float* ax, const RowConst& rc, const float* prow,
                const float* zrow, float* nrow, float* grow, const uint64_t* holes, int* slow,
                int& n_slow, int& done) {
  const VT zero = V::zero(), one = V::set1(1.f), three = V::set1(3.f);
  const VT inf = V::set1(kInf), ninf = V::set1(-kInf);
  const VT fxs = V::set1(rc.fxs), fys = V::set1(rc.fys), ay = V::set1(rc.ay),
           full_rows = V::set1(rc.full_rows);
  const VT u0 = V::set1(rc.up[0]), u1 = V::set1(rc.up[1]), u2 = V::set1(rc.up[2]);
  const VT alpha = V::set1(rc.alpha), beta = V::set1(rc.beta), td = V::set1(rc.td),
           inv_td = V::set1(rc.inv_td), row_term = V::set1(rc.row_term);
  int x = x0;
  for (; x + V::N <= n; x += V::N) {
    VT T0, Tu, Tv, N = zero, unused;
    momentsV<H>(vert[kW0] + x, 1, T0, Tu);
    momentsV<H>(vert[kW1] + x, 1, Tv, unused);
    // without missing pixels in the rows every window is whole (and has at least 4 pixels)
    VM whole = V::ones();
    const bool holed = anyBlock(holes, x);
    if (holed) {
      momentsV<H>(vert[kC] + x, 1, N, unused);
      whole = V::eq(N, V::mul(V::load(ncols + x), full_rows));
    }
    VM ok = whole;
    VT a[6];
    for (int j = 0; j < 6; ++j) a[j] = V::load(table[j] + x);
    VT m0 = V::add(V::add(V::mul(a[0], T0), V::mul(a[1], Tu)), V::mul(a[2], Tv));
    VT m1 = V::add(V::add(V::mul(a[1], T0), V::mul(a[3], Tu)), V::mul(a[4], Tv));
    VT m2 = V::add(V::add(V::mul(a[2], T0), V::mul(a[4], Tu)), V::mul(a[5], Tv));
    if (holed && !V::none(V::mandnot(whole, V::ge(N, three)))) {
      // windows with 3 or more valid pixels, some missing: solvePartial(), lane for lane
      VT K0, Ku, Kuu, Kv, Kuv, Kvv, Cu1, Cu2, Cb1, Cb2;
      momentsV<H, true>(vert[kV0] + x, 1, K0, Ku, &Kuu);
      momentsV<H>(vert[kV1] + x, 1, Kv, Kuv);
      momentsV<H>(vert[kV2] + x, 1, Kvv, unused);
      momentsV<H, true>(vert[kC] + x, 1, N, Cu1, &Cu2);
      momentsV<H>(vert[kCv1] + x, 1, Cb1, unused);
      momentsV<H>(vert[kCv2] + x, 1, Cb2, unused);
      const VM span =
          V::mand(V::ge(N, three), V::mand(V::gt(V::sub(V::mul(N, Cu2), V::mul(Cu1, Cu1)), zero),
                                           V::gt(V::sub(V::mul(N, Cb2), V::mul(Cb1, Cb1)), zero)));
      const VT a00 = V::sub(V::mul(Kuu, Kvv), V::mul(Kuv, Kuv));
      const VT a01 = V::sub(V::mul(Kuv, Kv), V::mul(Ku, Kvv));
      const VT a02 = V::sub(V::mul(Ku, Kuv), V::mul(Kuu, Kv));
      const VT a11 = V::sub(V::mul(K0, Kvv), V::mul(Kv, Kv));
      const VT a12 = V::sub(V::mul(Ku, Kv), V::mul(K0, Kuv));
      const VT a22 = V::sub(V::mul(K0, Kuu), V::mul(Ku, Ku));
      const VT det = V::add(V::add(V::mul(K0, a00), V::mul(Ku, a01)), V::mul(Kv, a02));
      const VM well = V::gt(det, V::mul(V::set1(kWellConditioned), V::mul(V::mul(K0, Kuu), Kvv)));
      const VM part = V::mandnot(whole, span);
      const unsigned exact = V::bits(V::mandnot(well, part));
      for (int i = 0; i < V::N; ++i)
        if (exact >> i & 1) slow[n_slow++] = x + i;
      const VT p0 = V::add(V::add(V::mul(a00, T0), V::mul(a01, Tu)), V::mul(a02, Tv));
      const VT p1 = V::add(V::add(V::mul(a01, T0), V::mul(a11, Tu)), V::mul(a12, Tv));
      const VT p2 = V::add(V::add(V::mul(a02, T0), V::mul(a12, Tu)), V::mul(a22, Tv));
      m0 = V::select(whole, m0, p0);
      m1 = V::select(whole, m1, p1);
      m2 = V::select(whole, m2, p2);
      ok = V::mor(whole, V::mand(part, well));
    }
    const VT n0 = V::mul(fxs, m1), n1 = V::mul(fys, m2);
    const VT n2 = V::sub(V::sub(m0, V::mul(V::load(ax + x), n0)), V::mul(ay, n1));
    if (nrow) {
      alignas(64) float b0[V::N], b1[V::N], b2[V::N];
      V::store(b0, n0);
      V::store(b1, n1);
      V::store(b2, n2);
      const unsigned okb = V::bits(ok);
      for (int i = 0; i < V::N; ++i) {
        const float nn[3] = {b0[i], b1[i], b2[i]};
        finish(nn, okb >> i & 1, prow + 3 * (x + i), ax[x + i], rc, nrow + 3 * (x + i),
               grow ? grow + x + i : nullptr);
      }
      continue;
    }
    const VT len2 = V::add(V::add(V::mul(n0, n0), V::mul(n1, n1)), V::mul(n2, n2));
    ok = V::mand(ok, V::mand(V::gt(len2, zero), V::lt(len2, inf)));
    const VT inv_len = V::div(one, V::sqrt(V::select(ok, len2, one)));
    const VT nup =
        V::mul(V::abs(V::add(V::add(V::mul(n0, u0), V::mul(n1, u1)), V::mul(n2, u2))), inv_len);
    const VT normal_term = V::keep(ok, nup);
    const VT z = V::load(zrow + x);
    const VM near = V::mand(V::le(z, td), V::gt(z, ninf));
    const VT depth_term = rc.near_high ? V::mul(V::sub(td, z), inv_td) : V::mul(z, inv_td);
    V::store(grow + x, V::add(V::mul(alpha, normal_term),
                              V::mul(beta, V::select(near, depth_term, row_term))));
  }
  done = x;
}

// Exported entry points (template arguments are not dispatched): the window half-size h is 1, 2
// or 3; another h does nothing (done = x0). Columns are absolute: a range [x0, x1) of the row.
void falsPrepare(const float* p, const float* k, int x0, int x1, float* kv, float* t, float* c,
                 float* zs, uint64_t* bad, int& done) {
  prepare(p, k, x0, x1, kv, t, c, zs, bad, done);
}

void falsVertical(int h, const float* const* rows, int W, int x0, int x1, const uint64_t* holes,
                  float* const* out, int& done) {
  done = x0;
  if (h == 1) vertical<1>(rows, W, x0, x1, holes, out, done);
  if (h == 2) vertical<2>(rows, W, x0, x1, holes, out, done);
  if (h == 3) vertical<3>(rows, W, x0, x1, holes, out, done);
}

void falsHorizontal(int h, const float* const* vert, const float* const* table, int x0, int x1,
                    const float* ncols, const float* ax, const RowConst& rc, const float* prow,
                    const float* zrow, float* nrow, float* grow, const uint64_t* holes, int* slow,
                    int& n_slow, int& done) {
  done = x0;
  if (h == 1)
    horizontal<1>(vert, table, x0, x1, ncols, ax, rc, prow, zrow, nrow, grow, holes, slow, n_slow,
                  done);
  if (h == 2)
    horizontal<2>(vert, table, x0, x1, ncols, ax, rc, prow, zrow, nrow, grow, holes, slow, n_slow,
                  done);
  if (h == 3)
    horizontal<3>(vert, table, x0, x1, ncols, ax, rc, prow, zrow, nrow, grow, holes, slow, n_slow,
                  done);
}
