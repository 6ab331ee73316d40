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
/// The adjugate of a window's symmetric matrix K = [K0 Ku Kv; Ku Kuu Kuv; Kv Kuv Kvv] (its six
/// terms a00 a01 a02 a11 a12 a22, as symmetricAdjugate() of fals_window.h) and its product with
/// (T0, Tu, Tv) (adjugateTimes()), in the scalar code's order of operations, on float or double
/// vectors.
struct Adjugate {
  template <class Vec>
  static void terms(Vec K0, Vec Ku, Vec Kv, Vec Kuu, Vec Kuv, Vec Kvv, Vec a[6]) {
    a[0] = hn::Sub(hn::Mul(Kuu, Kvv), hn::Mul(Kuv, Kuv));
    a[1] = hn::Sub(hn::Mul(Kuv, Kv), hn::Mul(Ku, Kvv));
    a[2] = hn::Sub(hn::Mul(Ku, Kuv), hn::Mul(Kuu, Kv));
    a[3] = hn::Sub(hn::Mul(K0, Kvv), hn::Mul(Kv, Kv));
    a[4] = hn::Sub(hn::Mul(Ku, Kv), hn::Mul(K0, Kuv));
    a[5] = hn::Sub(hn::Mul(K0, Kuu), hn::Mul(Ku, Ku));
  }
  template <class Vec>
  static void times(const Vec a[6], Vec T0, Vec Tu, Vec Tv, Vec& m0, Vec& m1, Vec& m2) {
    m0 = hn::Add(hn::Add(hn::Mul(a[0], T0), hn::Mul(a[1], Tu)), hn::Mul(a[2], Tv));
    m1 = hn::Add(hn::Add(hn::Mul(a[1], T0), hn::Mul(a[3], Tu)), hn::Mul(a[4], Tv));
    m2 = hn::Add(hn::Add(hn::Mul(a[2], T0), hn::Mul(a[4], Tu)), hn::Mul(a[5], Tv));
  }
};

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
      VT a[6];
      Adjugate::terms(K0, Ku, Kv, Kuu, Kuv, Kvv, a);
      const VT det = V::add(V::add(V::mul(K0, a[0]), V::mul(Ku, a[1])), V::mul(Kv, a[2]));
      const VM well = V::gt(det, V::mul(V::set1(kWellConditioned), V::mul(V::mul(K0, Kuu), Kvv)));
      const VM part = V::mandnot(whole, span);
      const unsigned exact = V::bits(V::mandnot(well, part));
      for (int i = 0; i < V::N; ++i)
        if (exact >> i & 1) slow[n_slow++] = x + i;
      VT p0, p1, p2;
      Adjugate::times(a, T0, Tu, Tv, p0, p1, p2);
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

#if HWY_HAVE_FLOAT64
// The exact path (FalsNormals::solveWindow) for the windows of columns [x0, x1) of one row, one
// window per double lane: the same double operations in the same order as the scalar code, so
// every target gives its bits. A pixel without a valid pixel or outside the image adds +-0 to a
// sum instead of being skipped: the sums start at +0 and are never -0, so the bits stay the same.
// Column sums (scalar solveWindow's column_) go to the 8 planes of `cols` (column x at
// cols[j * stride + x], h zero columns each side left untouched); su: source column of each
// column, padded by h finite values each side; fv[h + d]: source row offset of row y + d (0 outside
// the image, where the prepared rows are 0). n: unit normals (floats, 3 planes of stride W) and
// ok per column, or with g (and no normals wanted) G directly.
struct VD {
  using D = hn::CappedTag<double, 8>;
  using DF = hn::Rebind<float, D>;
  static constexpr int N = static_cast<int>(hn::MaxLanes(D()));
  using T = hn::Vec<D>;
  static T loadf(const float* p) { return hn::PromoteTo(D(), hn::LoadU(DF(), p)); }
};

template <int H>
void exactRow(const float* const* kv, const float* const* t, const float* const* c,
              const double* fv, int W, int x0, int x1, const double* su, const float* ax, double ay,
              double fx, double fy, double full_rows, const float* ncols, double* cols,
              std::ptrdiff_t stride, float* n_out, uint8_t* ok_out, const RowConst& rc,
              const float* zrow, float* grow, int& done) {
  using D = VD::D;
  using DF = VD::DF;
  using T = VD::T;
  constexpr int L = VD::N;
  const D d;
  const DF df;
  const int xv = x0 + (x1 - x0) / L * L;  // windows done here: [x0, xv)
  done = x0;
  if (xv == x0) return;
  // column sums of the columns the windows read
  const int c0 = std::max(0, x0 - H), c1 = std::min(W, xv + H);
  double* v[8];
  for (int j = 0; j < 8; ++j) v[j] = cols + j * stride;
  int cx = c0;
  for (; cx + L <= c1; cx += L) {
    T s[8];
    for (int j = 0; j < 8; ++j) s[j] = hn::Zero(d);
    for (int dv = -H; dv <= H; ++dv) {
      const T k = VD::loadf(kv[H + dv] + cx), tt = VD::loadf(t[H + dv] + cx),
              cc = VD::loadf(c[H + dv] + cx), f = hn::Set(d, fv[H + dv]);
      s[0] = hn::Add(s[0], k);
      const T kf = hn::Mul(k, f);
      s[1] = hn::Add(s[1], kf);
      s[2] = hn::Add(s[2], hn::Mul(kf, f));
      s[3] = hn::Add(s[3], tt);
      s[4] = hn::Add(s[4], hn::Mul(tt, f));
      s[5] = hn::Add(s[5], cc);
      const T cf = hn::Mul(cc, f);
      s[6] = hn::Add(s[6], cf);
      s[7] = hn::Add(s[7], hn::Mul(cf, f));
    }
    for (int j = 0; j < 8; ++j) hn::StoreU(s[j], d, v[j] + cx);
  }
  for (; cx < c1; ++cx) {  // the same per column
    double s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    for (int dv = -H; dv <= H; ++dv) {
      const double k = kv[H + dv][cx], tt = t[H + dv][cx], cc = c[H + dv][cx], f = fv[H + dv];
      s[0] += k;
      s[1] += k * f;
      s[2] += k * f * f;
      s[3] += tt;
      s[4] += tt * f;
      s[5] += cc;
      s[6] += cc * f;
      s[7] += cc * f * f;
    }
    for (int j = 0; j < 8; ++j) v[j][cx] = s[j];
  }
  const T zero = hn::Zero(d), three = hn::Set(d, 3.0),
          inf = hn::Set(d, std::numeric_limits<double>::infinity()), one = hn::Set(d, 1.0),
          vfx = hn::Set(d, fx), vfy = hn::Set(d, fy), vay = hn::Set(d, ay),
          vfull_rows = hn::Set(d, full_rows);
  for (int x = x0; x < xv; x += L) {
    T N = zero;
    for (int o = -H; o <= H; ++o) N = hn::Add(N, hn::LoadU(d, v[5] + x + o));
    auto ok = hn::Ge(N, three);
    T n0 = zero, n1 = zero, n2 = zero;
    if (!hn::AllFalse(d, ok)) {
      T K0 = zero, Ku = zero, Kv = zero, Kuu = zero, Kuv = zero, Kvv = zero, T0 = zero, Tu = zero,
        Tv = zero, Nu = zero, Nuu = zero, Nv = zero, Nvv = zero;
      const T sx = hn::LoadU(d, su + x);
      for (int o = -H; o <= H; ++o) {
        const T fu = hn::Sub(hn::LoadU(d, su + x + o), sx), fuu = hn::Mul(fu, fu);
        const T a0 = hn::LoadU(d, v[0] + x + o), a1 = hn::LoadU(d, v[1] + x + o),
                a3 = hn::LoadU(d, v[3] + x + o), a5 = hn::LoadU(d, v[5] + x + o);
        K0 = hn::Add(K0, a0);
        Ku = hn::Add(Ku, hn::Mul(fu, a0));
        Kuu = hn::Add(Kuu, hn::Mul(fuu, a0));
        Kv = hn::Add(Kv, a1);
        Kuv = hn::Add(Kuv, hn::Mul(fu, a1));
        Kvv = hn::Add(Kvv, hn::LoadU(d, v[2] + x + o));
        T0 = hn::Add(T0, a3);
        Tu = hn::Add(Tu, hn::Mul(fu, a3));
        Tv = hn::Add(Tv, hn::LoadU(d, v[4] + x + o));
        Nu = hn::Add(Nu, hn::Mul(fu, a5));
        Nuu = hn::Add(Nuu, hn::Mul(fuu, a5));
        Nv = hn::Add(Nv, hn::LoadU(d, v[6] + x + o));
        Nvv = hn::Add(Nvv, hn::LoadU(d, v[7] + x + o));
      }
      const T full = hn::Mul(hn::PromoteTo(d, hn::LoadU(df, ncols + x)), vfull_rows);
      const auto spread = hn::And(hn::Gt(hn::Sub(hn::Mul(N, Nuu), hn::Mul(Nu, Nu)), zero),
                                  hn::Gt(hn::Sub(hn::Mul(N, Nvv), hn::Mul(Nv, Nv)), zero));
      ok = hn::And(ok, hn::Or(hn::Not(hn::Lt(N, full)), spread));
      // symmetricAdjugate() and adjugateTimes()
      T a[6], m0, m1, m2;
      Adjugate::terms(K0, Ku, Kv, Kuu, Kuv, Kvv, a);
      Adjugate::times(a, T0, Tu, Tv, m0, m1, m2);
      n0 = hn::Mul(vfx, m1);
      n1 = hn::Mul(vfy, m2);
      n2 = hn::Sub(hn::Sub(m0, hn::Mul(hn::PromoteTo(d, hn::LoadU(df, ax + x)), n0)),
                   hn::Mul(vay, n1));
      const T len = hn::Sqrt(hn::Add(hn::Add(hn::Mul(n0, n0), hn::Mul(n1, n1)), hn::Mul(n2, n2)));
      ok = hn::And(ok, hn::And(hn::Gt(len, zero), hn::Lt(len, inf)));
      const T l = hn::IfThenElse(ok, len, one);
      n0 = hn::IfThenElseZero(ok, hn::Div(n0, l));
      n1 = hn::IfThenElseZero(ok, hn::Div(n1, l));
      n2 = hn::IfThenElseZero(ok, hn::Div(n2, l));
    }
    const auto f0 = hn::DemoteTo(df, n0), f1 = hn::DemoteTo(df, n1), f2 = hn::DemoteTo(df, n2);
    if (grow) {  // finish() for G alone, lane for lane
      // lanes without a normal hold n = 0: len2 = 0 fails the test as finish()'s ok does
      const auto fzero = hn::Zero(df), fone = hn::Set(df, 1.f);
      const auto len2 = hn::Add(hn::Add(hn::Mul(f0, f0), hn::Mul(f1, f1)), hn::Mul(f2, f2));
      const auto okg = hn::And(hn::Gt(len2, fzero), hn::Lt(len2, hn::Set(df, kInf)));
      const auto inv_len = hn::Div(fone, hn::Sqrt(hn::IfThenElse(okg, len2, fone)));
      const auto nup = hn::Mul(hn::Abs(hn::Add(hn::Add(hn::Mul(f0, hn::Set(df, rc.up[0])),
                                                       hn::Mul(f1, hn::Set(df, rc.up[1]))),
                                               hn::Mul(f2, hn::Set(df, rc.up[2])))),
                               inv_len);
      const auto normal_term = hn::IfThenElseZero(okg, nup);
      const auto z = hn::LoadU(df, zrow + x), td = hn::Set(df, rc.td),
                 inv_td = hn::Set(df, rc.inv_td);
      const auto near = hn::And(hn::Le(z, td), hn::Gt(z, hn::Set(df, -kInf)));
      const auto depth_term = rc.near_high ? hn::Mul(hn::Sub(td, z), inv_td) : hn::Mul(z, inv_td);
      hn::StoreU(hn::Add(hn::Mul(hn::Set(df, rc.alpha), normal_term),
                         hn::Mul(hn::Set(df, rc.beta),
                                 hn::IfThenElse(near, depth_term, hn::Set(df, rc.row_term)))),
                 df, grow + x);
      continue;
    }
    hn::StoreU(f0, df, n_out + x);
    hn::StoreU(f1, df, n_out + W + x);
    hn::StoreU(f2, df, n_out + 2 * W + x);
    uint8_t bits[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    hn::StoreMaskBits(d, ok, bits);
    for (int i = 0; i < L; ++i) ok_out[x + i] = bits[0] >> i & 1;
  }
  done = xv;
}
#endif  // HWY_HAVE_FLOAT64

void falsExact(int h, const float* const* kv, const float* const* t, const float* const* c,
               const double* fv, int W, int x0, int x1, const double* su, const float* ax,
               double ay, double fx, double fy, double full_rows, const float* ncols, double* cols,
               std::ptrdiff_t stride, float* n_out, uint8_t* ok_out, const RowConst& rc,
               const float* zrow, float* grow, int& done) {
  done = x0;
#if HWY_HAVE_FLOAT64
  if (h == 1)
    exactRow<1>(kv, t, c, fv, W, x0, x1, su, ax, ay, fx, fy, full_rows, ncols, cols, stride, n_out,
                ok_out, rc, zrow, grow, done);
  if (h == 2)
    exactRow<2>(kv, t, c, fv, W, x0, x1, su, ax, ay, fx, fy, full_rows, ncols, cols, stride, n_out,
                ok_out, rc, zrow, grow, done);
  if (h == 3)
    exactRow<3>(kv, t, c, fv, W, x0, x1, su, ax, ay, fx, fy, full_rows, ncols, cols, stride, n_out,
                ok_out, rc, zrow, grow, done);
#endif
}
