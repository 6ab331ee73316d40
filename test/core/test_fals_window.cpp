// The per-window algebra of FALS normals (fals_window.h) on small integer windows, where float and
// double are exact: the symmetric adjugate solve, moments of a ramp, the verdicts on windows with
// missing pixels, a pixel's oriented normal and G.
#include <cmath>

#include <gtest/gtest.h>

#include "fals_window.h"  // private: the window algebra

namespace rgbd_lane_detector {
namespace {

using namespace fals;  // NOLINT: the algebra under test

// Q = [4 1 2; 1 5 3; 2 3 6], det Q = 70, Q (1, -2, 3) = (8, 0, 14).
template <typename T>
void expectAdjugateSolve() {
  const T q[6] = {4, 1, 2, 5, 3, 6};
  T a[6];
  symmetricAdjugate(q, a);
  const T Q[3][3] = {{q[0], q[1], q[2]}, {q[1], q[3], q[4]}, {q[2], q[4], q[5]}};
  const T A[3][3] = {{a[0], a[1], a[2]}, {a[1], a[3], a[4]}, {a[2], a[4], a[5]}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_EQ(Q[i][0] * A[0][j] + Q[i][1] * A[1][j] + Q[i][2] * A[2][j], i == j ? 70 : 0);
  T m[3];
  adjugateTimes(a, T(8), T(0), T(14), m);  // det Q times the solution
  EXPECT_EQ(m[0], 70);
  EXPECT_EQ(m[1], -140);
  EXPECT_EQ(m[2], 210);
}

TEST(FalsWindow, AdjugateSolvesASymmetricSystem) {
  expectAdjugateSolve<float>();
  expectAdjugateSolve<double>();
}

TEST(FalsWindow, MomentsOfARamp) {
  // x(d) = 3 + 2 d over d = -2..2: box 15, sum d (x(d) - x(-d)) = 20, sum d^2 (x(d) + x(-d)) = 30
  const float ramp[5] = {-1.f, 1.f, 3.f, 5.f, 7.f};
  float box, m1, m2;
  moments(ramp + 2, 1, 2, box, m1, m2);
  EXPECT_EQ(box, 15.f);
  EXPECT_EQ(m1, 20.f);
  EXPECT_EQ(m2, 30.f);
  // the same values three apart, and as separate rows
  float strided[13] = {};
  for (int d = -2; d <= 2; ++d) strided[6 + 3 * d] = ramp[d + 2];
  moments(strided + 6, 3, 2, box, m1, m2);
  EXPECT_EQ(box, 15.f);
  EXPECT_EQ(m1, 20.f);
  EXPECT_EQ(m2, 30.f);
  const float* rows[5] = {ramp, ramp + 1, ramp + 2, ramp + 3, ramp + 4};
  momentsRows(rows, 0, 2, box, m1, m2);
  EXPECT_EQ(box, 15.f);
  EXPECT_EQ(m1, 20.f);
  EXPECT_EQ(m2, 30.f);
}

// The moments of unit k over the window pixels at offsets (du[i], dv[i]).
Partial partialOf(const int* du, const int* dv, int n) {
  Partial q{};
  for (int i = 0; i < n; ++i) {
    q.K0 += 1.f, q.Ku += du[i], q.Kv += dv[i];
    q.Kuu += du[i] * du[i], q.Kuv += du[i] * dv[i], q.Kvv += dv[i] * dv[i];
  }
  q.N = q.K0, q.Cu1 = q.Ku, q.Cu2 = q.Kuu, q.Cb1 = q.Kv, q.Cb2 = q.Kvv;
  return q;
}

TEST(FalsWindow, WindowsWithMissingPixelsAreSolvedInFloatOnlyWhenWellConditioned) {
  RowConst rc;
  rc.fxs = rc.fys = 1.f;
  float n[3];
  // a whole 3x3 window: Q = diag(9, 6, 6), adj(Q) = diag(36, 54, 54); n = (54 Tu, 54 Tv, 36 T0)
  const int du9[9] = {-1, 0, 1, -1, 0, 1, -1, 0, 1}, dv9[9] = {-1, -1, -1, 0, 0, 0, 1, 1, 1};
  EXPECT_EQ(solvePartial(partialOf(du9, dv9, 9), 1.f, 2.f, 3.f, 0.f, rc, n), PartialCase::kFloat);
  EXPECT_EQ(n[0], 108.f);
  EXPECT_EQ(n[1], 162.f);
  EXPECT_EQ(n[2], 36.f);
  // valid pixels in one column: no normal
  const int du3[3] = {0, 0, 0}, dv3[3] = {-1, 0, 1};
  EXPECT_EQ(solvePartial(partialOf(du3, dv3, 3), 1.f, 0.f, 0.f, 0.f, rc, n), PartialCase::kNone);
  // a thin diagonal crescent of a 5x5 window: det Q = 50 < K0 Kuu Kvv / 16 = 57.75, to double
  const int du6[6] = {-2, -1, 0, 1, 2, 2}, dv6[6] = {-2, -1, 0, 1, 2, 1};
  EXPECT_EQ(solvePartial(partialOf(du6, dv6, 6), 1.f, 0.f, 0.f, 0.f, rc, n), PartialCase::kExact);
}

TEST(FalsWindow, FinishOrientsTowardTheCameraAndGivesG) {
  RowConst rc;  // up = (0, -1, 0)
  rc.alpha = 1.f;
  rc.beta = 0.f;
  const float road_point[3] = {0.f, 1.5f, 5.f};  // below a level camera (y down)
  for (float sign : {1.f, -1.f}) {
    const float n[3] = {0.f, 2.f * sign, 0.f};
    float normal[3], g = -1.f;
    finish(n, true, road_point, 0.f, rc, normal, &g);
    EXPECT_EQ(normal[0], 0.f);
    EXPECT_EQ(normal[1], -1.f);  // toward the camera, either sign in
    EXPECT_EQ(normal[2], 0.f);
    EXPECT_EQ(g, 1.f);  // alpha |n . up|
  }
  const float n[3] = {0.f, 2.f, 0.f};
  float normal[3], g = -1.f;
  finish(n, false, road_point, 0.f, rc, normal, &g);
  EXPECT_TRUE(std::isnan(normal[1]));
  EXPECT_EQ(g, 0.f);
}

}  // namespace
}  // namespace rgbd_lane_detector
