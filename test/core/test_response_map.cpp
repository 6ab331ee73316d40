// Geometric map G (Eq. 2, both depth terms) and fused response R (Eq. 3), hand-computed.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/pixel_kernels.h"
#include "rgbd_lane_detector/response_map.h"
#include "simd.h"  // private: targets

namespace rgbd_lane_detector {
namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();

TEST(GeometricMap, EveryBranchOfEquation2) {
  Params p;  // alpha 0.4, beta 0.1, T_D 20
  p.depth_term = DepthTerm::kNearHigh;
  // D <= T_D: alpha |n.O_y| + beta (T_D - D) / T_D
  EXPECT_NEAR(geometricValue(5.f, -0.9f, 300, 380, p), 0.4 * 0.9 + 0.1 * 15.0 / 20.0, 1e-6);
  EXPECT_NEAR(geometricValue(20.f, 0.9f, 300, 380, p), 0.4 * 0.9, 1e-6);  // D == T_D
  // D > T_D: alpha |n.O_y| + beta v / H
  EXPECT_NEAR(geometricValue(25.f, -0.9f, 300, 380, p), 0.4 * 0.9 + 0.1 * 300.0 / 380.0, 1e-6);
  // unknown depth and normal: only the row term
  EXPECT_NEAR(geometricValue(kNaN, kNaN, 190, 380, p), 0.1 * 0.5, 1e-6);
  // paper's printed variant D / T_D
  p.depth_term = DepthTerm::kFarHigh;
  EXPECT_NEAR(geometricValue(5.f, -0.9f, 300, 380, p), 0.4 * 0.9 + 0.1 * 5.0 / 20.0, 1e-6);
  EXPECT_NEAR(geometricValue(25.f, -0.9f, 300, 380, p), 0.4 * 0.9 + 0.1 * 300.0 / 380.0, 1e-6);
  // a vertical surface (wall, truck side) gets no normal term
  p.depth_term = DepthTerm::kNearHigh;
  EXPECT_NEAR(geometricValue(10.f, 0.f, 300, 380, p), 0.1 * 0.5, 1e-6);
}

TEST(ResponseMap, EveryBranchOfEquation3) {
  EXPECT_FLOAT_EQ(fusedValue(0.4f, 0.3f, 0.5f), 0.4f);   // M < tau_G: R = M
  EXPECT_FLOAT_EQ(fusedValue(0.5f, 0.3f, 0.5f), 0.8f);   // M >= tau_G: R = M + G
  EXPECT_FLOAT_EQ(fusedValue(0.9f, 0.45f, 0.5f), 1.35f);
  EXPECT_FLOAT_EQ(fusedValue(0.0f, 0.45f, 0.0f), 0.45f);
}

TEST(ResponseMap, MapsOverRowsWithUpAxisAndInPlaceFusion) {
  Params p;
  p.up_x = 0;
  p.up_y = -1;
  p.up_z = 0;
  cv::Mat points(4, 3, CV_32FC3, cv::Scalar(0, 1.5, 10));
  cv::Mat normals(4, 3, CV_32FC3, cv::Scalar(0, -0.8, -0.6));
  points.at<cv::Vec3f>(2, 1) = cv::Vec3f(kNaN, kNaN, kNaN);
  normals.at<cv::Vec3f>(2, 1) = cv::Vec3f(kNaN, kNaN, kNaN);
  cv::Mat G;
  geometricMap(points, normals, p, cv::Range(1, 3), G);
  ASSERT_EQ(G.type(), CV_32FC1);
  EXPECT_NEAR(G.at<float>(1, 0), 0.4 * 0.8 + 0.1 * 0.5, 1e-6);
  EXPECT_NEAR(G.at<float>(2, 1), 0.1 * 2.0 / 4.0, 1e-6);  // unknown: row term only
  EXPECT_EQ(G.at<float>(0, 0), 0.f);                         // outside the rows
  EXPECT_EQ(G.at<float>(3, 2), 0.f);

  cv::Mat M(4, 3, CV_32FC1, cv::Scalar(0.7f));
  M.at<float>(1, 2) = 0.2f;
  fuseResponse(M, G, 0.5f, cv::Range(1, 3), M);  // in place
  EXPECT_NEAR(M.at<float>(1, 0), 0.7 + 0.4 * 0.8 + 0.05, 1e-6);
  EXPECT_FLOAT_EQ(M.at<float>(1, 2), 0.2f);
  EXPECT_FLOAT_EQ(M.at<float>(0, 0), 0.7f);  // outside the rows: unchanged
}

// Where G enters R: any map at tau_G or above (ties included), over the given rows, on every
// target, for one to four maps; a width that leaves a scalar tail on every vector target.
TEST(ResponseMap, FusionMaskIsAnyMapAtTauOrAbove) {
  const cv::Size size(37, 9);
  const float tau = 0.5f;
  cv::RNG rng(8);
  cv::Mat maps[kMaxFusedMaps];
  for (cv::Mat& m : maps) {
    m.create(size, CV_32FC1);
    for (int y = 0; y < size.height; ++y)
      for (int x = 0; x < size.width; ++x) {
        const int r = rng.uniform(0, 10);
        // exactly tau, just below it, above it, zero
        m.at<float>(y, x) = r == 0 ? tau : r == 1 ? std::nextafter(tau, 0.f) : r == 2 ? 0.9f : 0.f;
      }
  }
  const cv::Range rows(1, 8);
  for (simd::Target target : simd::availableTargets()) {
    simd::forceTarget(target);
    for (int count = 1; count <= kMaxFusedMaps; ++count) {
      SCOPED_TRACE(testing::Message() << simd::targetName(target) << ", " << count << " maps");
      cv::Mat mask;
      switch (count) {
        case 1:
          fusionMask({&maps[0]}, tau, rows, mask);
          break;
        case 2:
          fusionMask({&maps[0], &maps[1]}, tau, rows, mask);
          break;
        case 3:
          fusionMask({&maps[0], &maps[1], &maps[2]}, tau, rows, mask);
          break;
        default:
          fusionMask({&maps[0], &maps[1], &maps[2], &maps[3]}, tau, rows, mask);
      }
      ASSERT_EQ(mask.type(), CV_8UC1);
      int wrong = 0, set = 0;
      for (int y = 0; y < size.height; ++y)
        for (int x = 0; x < size.width; ++x) {
          bool any = false;
          for (int i = 0; i < count; ++i) any = any || maps[i].at<float>(y, x) >= tau;
          const bool inside = y >= rows.start && y < rows.end;
          const int want = inside && any ? 255 : 0;
          wrong += mask.at<uint8_t>(y, x) != want;
          set += want != 0;
        }
      EXPECT_EQ(wrong, 0);
      EXPECT_GT(set, 0);
    }
  }
  simd::forceTarget(simd::kBest);
}

// The one-pass forms the detector runs: gatedFusionMask() gives the maps and the mask of
// applyPlaneGate() on each pair then fusionMask(), and fuseResponseMasked() the maps of
// fuseResponse(), bit for bit, on every target, for 2, 3 and 4 maps (three: both sides' and one
// acquiring side's; the odd map is gated alone, as applyPlaneGate() with it as its own pair).
TEST(ResponseMap, OnePassGateMaskAndFusionAreTheSeparatePasses) {
  const cv::Size size(45, 11);
  const float tau = 0.3f, tau_g = 0.5f, max_off = 0.2f;
  cv::RNG rng(12);
  cv::Mat maps[kMaxFusedMaps], G(size, CV_32FC1), points(size, CV_32FC3);
  for (cv::Mat& m : maps) {
    m.create(size, CV_32FC1);
    for (int y = 0; y < size.height; ++y)
      for (int x = 0; x < size.width; ++x) {
        const int r = rng.uniform(0, 12);
        m.at<float>(y, x) = r == 0 ? tau : r == 1 ? tau_g : r == 2 ? 0.9f : r == 3 ? 0.4f : 0.f;
      }
  }
  rng.fill(G, cv::RNG::UNIFORM, 0.0, 0.6);
  PlaneEstimate plane;
  plane.valid = true;
  plane.normal = Eigen::Vector3d(0.0, -0.995, 0.0998).normalized();
  plane.distance = 1.5;
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const float z = static_cast<float>(rng.uniform(2.0, 30.0));
      const float off = static_cast<float>(rng.uniform(-0.5, 0.5));  // off the plane by up to 0.5 m
      cv::Vec3f& p = points.at<cv::Vec3f>(y, x);
      p = cv::Vec3f(static_cast<float>(rng.uniform(-5.0, 5.0)), 0.f, z);
      // y on the plane (n . p + d = 0), then moved off it
      p[1] = static_cast<float>(-(plane.normal.x() * p[0] + plane.normal.z() * z + plane.distance) /
                                plane.normal.y()) + off;
      if (rng.uniform(0, 8) == 0) p = cv::Vec3f(kNaN, kNaN, kNaN);
    }
  const cv::Range rows(1, 10);
  for (simd::Target target : simd::availableTargets()) {
    simd::forceTarget(target);
    for (int count : {2, 3, 4}) {
      SCOPED_TRACE(testing::Message() << simd::targetName(target) << ", " << count << " maps");
      cv::Mat a[kMaxFusedMaps], b[kMaxFusedMaps];
      cv::Mat* pa[kMaxFusedMaps];
      for (int i = 0; i < count; ++i) {
        a[i] = maps[i].clone();
        b[i] = maps[i].clone();
        pa[i] = &a[i];
      }
      cv::Mat mask_a, mask_b;
      gatedFusionMask(points, plane, max_off, tau, pa, count, tau_g, rows, mask_a);
      for (int i = 0; i < count; i += 2)
        applyPlaneGate(points, rows, plane, max_off, tau, b[i], b[std::min(i + 1, count - 1)]);
      if (count == 2)
        fusionMask({&b[0], &b[1]}, tau_g, rows, mask_b);
      else if (count == 3)
        fusionMask({&b[0], &b[1], &b[2]}, tau_g, rows, mask_b);
      else
        fusionMask({&b[0], &b[1], &b[2], &b[3]}, tau_g, rows, mask_b);
      EXPECT_EQ(cv::countNonZero(mask_a != mask_b), 0);
      int gated = 0;
      for (int i = 0; i < count; ++i) {
        EXPECT_EQ(cv::countNonZero(a[i] != b[i]), 0) << i;
        gated += cv::countNonZero(b[i] != maps[i]);
      }
      EXPECT_GT(gated, 0);
      fuseResponseMasked(pa, count, G, tau_g, rows, mask_a);
      for (int i = 0; i < count; ++i) {
        fuseResponse(b[i], G, tau_g, rows, b[i]);
        EXPECT_EQ(std::memcmp(a[i].data, b[i].data, a[i].total() * sizeof(float)), 0) << i;
      }
    }
  }
  simd::forceTarget(simd::kBest);
}

// findSeed's maximum: cv::minMaxLoc's value and first position (row-major) on ties.
TEST(ResponseMap, MaxLocationIsMinMaxLocs) {
  cv::RNG rng(4);
  cv::Mat big(50, 77, CV_32FC1);
  for (int trial = 0; trial < 40; ++trial) {
    rng.fill(big, cv::RNG::UNIFORM, 0.0, trial % 2 ? 1.0 : 3.0);
    if (trial % 4 == 1) big.setTo(0.f);                     // all equal: first element
    if (trial % 4 == 2) big.setTo(1.25f, big > 2.5f);       // many ties
    if (trial % 4 == 3) big.at<float>(49, 76) = 9.f;        // maximum in the last element
    const cv::Rect area(trial % 7, trial % 5, 77 - trial % 7 - trial % 3, 45);  // odd widths
    double ref_v, v;
    cv::Point ref_p, p;
    cv::minMaxLoc(big(area), nullptr, &ref_v, nullptr, &ref_p);
    maxLocation(big(area), v, p);
    EXPECT_EQ(v, ref_v) << trial;
    EXPECT_EQ(p, ref_p) << trial;
  }
}

// A row's maximum and its first column, on every target, for rows shorter than a vector and
// with ties across the vectors and the rest.
TEST(ResponseMap, RowMaximumIsTheFirstMaximum) {
  cv::RNG rng(6);
  std::vector<float> row(70);
  for (simd::Target target : simd::availableTargets()) {
    simd::forceTarget(target);
    for (int trial = 0; trial < 200; ++trial) {
      const int n = 1 + trial % 70;
      for (float& v : row) v = static_cast<float>(rng.uniform(0, 4)) * 0.25f;  // ties
      float value = -1.f;
      int column = -1;
      rowMaximum(row.data(), n, value, column);
      const int first = static_cast<int>(std::max_element(row.begin(), row.begin() + n) -
                                         row.begin());
      EXPECT_EQ(value, row[first]) << simd::targetName(target) << " " << trial;
      EXPECT_EQ(column, first) << simd::targetName(target) << " " << trial;
    }
  }
  simd::forceTarget(simd::kBest);
}

}  // namespace
}  // namespace rgbd_lane_detector
