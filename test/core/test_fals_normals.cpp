// FALS normals: accuracy on planes, agreement with OpenCV contrib, orientation, invalid depth.
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#include <opencv2/opencv_modules.hpp>
// OpenCV built with contrib, and its headers here (not in the aarch64 sysroot of make test-arm64)
#if defined(HAVE_OPENCV_RGBD) && __has_include(<opencv2/rgbd.hpp>)
#define RLD_TEST_RGBD 1
#include <opencv2/rgbd.hpp>
#endif

#include <Eigen/Dense>

#include "rgbd_lane_detector/depth_points.h"
#include "rgbd_lane_detector/fals_normals.h"
#include "rgbd_lane_detector/response_map.h"
#include "simd.h"  // private: targets

namespace rgbd_lane_detector {
namespace {

const Intrinsics kK{525.0, 525.0, 319.5, 239.5};

// Organised points of the plane n . p + d = 0 (NaN where the ray misses or z > max_z).
cv::Mat planePoints(const Eigen::Vector3d& n, double d, cv::Size size, double max_z = 50.0) {
  cv::Mat pts(size, CV_32FC3);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) {
      const Eigen::Vector3d r((u - kK.cx) / kK.fx, (v - kK.cy) / kK.fy, 1.0);
      const double t = -d / n.dot(r);
      pts.at<cv::Vec3f>(v, u) =
          (t > 0 && t <= max_z) ? cv::Vec3f(static_cast<float>(r.x() * t),
                                            static_cast<float>(r.y() * t), static_cast<float>(t))
                                : cv::Vec3f(nan, nan, nan);
    }
  return pts;
}

double angleTo(const cv::Vec3f& a, const Eigen::Vector3d& b) {
  const double c = a[0] * b.x() + a[1] * b.y() + a[2] * b.z();
  if (std::isnan(c)) return M_PI;  // a missing normal counts as wrong
  return std::acos(std::min(1.0, std::max(-1.0, c)));
}

struct Stats {
  double mean = 0;
  int n = 0;
};

Stats meanError(const cv::Mat& normals, const cv::Mat& pts, const Eigen::Vector3d& truth,
                int border) {
  Stats s;
  for (int v = border; v < normals.rows - border; ++v)
    for (int u = border; u < normals.cols - border; ++u) {
      const cv::Vec3f n = normals.at<cv::Vec3f>(v, u);
      if (std::isnan(pts.at<cv::Vec3f>(v, u)[2]) || std::isnan(n[0])) continue;
      s.mean += angleTo(n, truth);
      ++s.n;
    }
  if (s.n) s.mean /= s.n;
  return s;
}

TEST(FalsNormals, TiltedPlaneIsAccurateAndFacesTheCamera) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.2, -0.9, -0.3).normalized();
  const double d = 2.0;  // camera on the side n points to
  const cv::Size size(640, 480);
  const cv::Mat pts = planePoints(n, d, size);
  for (int window : {3, 5, 7}) {
    FalsNormals fals;
    fals.configure(size, kK, window);
    cv::Mat normals;
    fals.compute(pts, cv::Range(0, size.height), normals);
    const Stats s = meanError(normals, pts, n, 0);
    ASSERT_GT(s.n, 100000);
    EXPECT_LT(s.mean, 0.006) << "window " << window;
    // toward the camera: n . p < 0 at every valid pixel
    int wrong = 0;
    for (int v = 0; v < size.height; ++v)
      for (int u = 0; u < size.width; ++u) {
        const cv::Vec3f q = normals.at<cv::Vec3f>(v, u), p = pts.at<cv::Vec3f>(v, u);
        if (!std::isnan(q[0]) && !std::isnan(p[2]) && q.dot(p) >= 0) ++wrong;
      }
    EXPECT_EQ(wrong, 0);
  }
}

TEST(FalsNormals, RoadSeenFromACarIsAccurate) {
  // camera 1.5 m above the road, pitched down 5 degrees: the grazing case of the method
  const double pitch = 5.0 * M_PI / 180.0;
  const Eigen::Vector3d n(0.0, -std::cos(pitch), -std::sin(pitch));
  const cv::Size size(640, 480);
  const cv::Mat pts = planePoints(n, 1.5, size, 40.0);
  FalsNormals fals;
  fals.configure(size, kK, 5);
  cv::Mat normals;
  fals.compute(pts, cv::Range(0, size.height), normals);
  const Stats s = meanError(normals, pts, n, 3);
  ASSERT_GT(s.n, 50000);
  EXPECT_LT(s.mean, 0.006);
}

TEST(FalsNormals, HolesUseOnlyValidPixelsAndStayExact) {
  const Eigen::Vector3d n = Eigen::Vector3d(-0.1, -0.8, -0.4).normalized();
  const cv::Size size(160, 120);
  cv::Mat pts = planePoints(n, 1.0, size);
  cv::RNG rng(11);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int i = 0; i < 4000; ++i)  // ~20% random holes
    pts.at<cv::Vec3f>(rng.uniform(0, size.height), rng.uniform(0, size.width)) =
        cv::Vec3f(nan, nan, nan);
  FalsNormals fals;
  fals.configure(size, kK, 5);
  cv::Mat normals;
  fals.compute(pts, cv::Range(0, size.height), normals);
  int checked = 0;
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) {
      const cv::Vec3f q = normals.at<cv::Vec3f>(v, u);
      if (std::isnan(q[0])) continue;
      EXPECT_LT(angleTo(q, n), 0.01) << u << "," << v;
      ++checked;
    }
  EXPECT_GT(checked, size.area() / 2);
}

TEST(FalsNormals, CollinearOrMissingWindowsGiveNaN) {
  const cv::Size size(40, 30);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::Mat pts(size, CV_32FC3, cv::Scalar(nan, nan, nan));
  // a single valid row of points (one LiDAR line): rays in a window are collinear
  const Eigen::Vector3d n(0, -1, 0);
  const cv::Mat plane = planePoints(n, 1.0, size);
  plane.row(20).copyTo(pts.row(20));
  FalsNormals fals;
  fals.configure(size, kK, 5);
  cv::Mat normals;
  fals.compute(pts, cv::Range(0, size.height), normals);
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) EXPECT_TRUE(std::isnan(normals.at<cv::Vec3f>(v, u)[0]));
}

TEST(FalsNormals, RowRangeAndReconfiguration) {
  const Eigen::Vector3d n = Eigen::Vector3d(0, -1, -0.2).normalized();
  const cv::Size size(64, 48);
  auto render = [&](const Intrinsics& K) {
    cv::Mat pts(size, CV_32FC3);
    for (int v = 0; v < size.height; ++v)
      for (int u = 0; u < size.width; ++u) {
        const Eigen::Vector3d r((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
        const double t = -1.5 / n.dot(r);
        pts.at<cv::Vec3f>(v, u) = cv::Vec3f(r.x() * t, r.y() * t, t);
      }
    return pts;
  };
  const Intrinsics K1{300, 300, 31.5, 23.5}, K2{200, 250, 20.0, 10.0};
  FalsNormals fals;
  fals.configure(size, K1, 5);
  cv::Mat normals(size, CV_32FC3, cv::Scalar(9, 9, 9));
  fals.compute(render(K1), cv::Range(30, 40), normals);
  EXPECT_EQ(normals.at<cv::Vec3f>(10, 10)[0], 9.f);  // outside the range: untouched
  EXPECT_LT(angleTo(normals.at<cv::Vec3f>(35, 32), n), 0.006);
  // new intrinsics: the precomputed M^-1 must follow them
  fals.configure(size, K2, 5);
  fals.compute(render(K2), cv::Range(0, 48), normals);
  EXPECT_LT(angleTo(normals.at<cv::Vec3f>(35, 32), n), 0.006);
  EXPECT_LT(angleTo(normals.at<cv::Vec3f>(20, 50), n), 0.006);
}

#ifdef RLD_TEST_RGBD
TEST(FalsNormals, AgreesWithOpenCvContribFals) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.85, -0.25).normalized();
  const cv::Size size(640, 480);
  const cv::Mat pts = planePoints(n, 3.0, size, 1e9);
  // OpenCV needs a dense input; planePoints with this plane covers the image
  ASSERT_EQ(cv::countNonZero(pts.reshape(1) != pts.reshape(1)), 0);
  const cv::Mat K = (cv::Mat_<float>(3, 3) << kK.fx, 0, kK.cx, 0, kK.fy, kK.cy, 0, 0, 1);
  cv::rgbd::RgbdNormals ref(size.height, size.width, CV_32F, K, 5,
                            cv::rgbd::RgbdNormals::RGBD_NORMALS_METHOD_FALS);
  cv::Mat ref_normals;
  ref(pts, ref_normals);
  FalsNormals fals;
  fals.configure(size, kK, 5);
  cv::Mat normals;
  fals.compute(pts, cv::Range(0, size.height), normals);
  double sum = 0;
  int count = 0;
  for (int v = 3; v < size.height - 3; ++v)
    for (int u = 3; u < size.width - 3; ++u) {
      const cv::Vec3f a = normals.at<cv::Vec3f>(v, u), b = ref_normals.at<cv::Vec3f>(v, u);
      if (std::isnan(b[0])) continue;
      const double c = std::fabs(a.dot(b)) / (cv::norm(a) * cv::norm(b));
      sum += std::acos(std::min(1.0, c));
      ++count;
    }
  ASSERT_GT(count, size.area() / 2);
  EXPECT_LT(sum / count, 0.006);
}
#endif

// FALS as written, in double: per pixel, M and b over the window's valid pixels (unit rays of the
// source pixels, ranges |p|), n = M^-1 b oriented toward the camera; NaN below 3 valid pixels or
// when missing pixels leave the valid ones in one row or one column.
cv::Mat referenceFals(const cv::Mat& pts, const Intrinsics& K, int window,
                      const std::vector<int>& src_u, const std::vector<int>& src_v) {
  const int h = window / 2;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::Mat out(pts.size(), CV_32FC3, cv::Scalar(nan, nan, nan));
  auto ray = [&](int x, int y) {
    return Eigen::Vector3d((src_u[x] - K.cx) / K.fx, (src_v[y] - K.cy) / K.fy, 1.0).normalized();
  };
  for (int y = 0; y < pts.rows; ++y)
    for (int x = 0; x < pts.cols; ++x) {
      Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
      Eigen::Vector3d b = Eigen::Vector3d::Zero();
      int n = 0, full = 0, x0 = pts.cols, x1 = -1, y0 = pts.rows, y1 = -1;
      for (int yy = std::max(0, y - h); yy <= std::min(pts.rows - 1, y + h); ++yy)
        for (int xx = std::max(0, x - h); xx <= std::min(pts.cols - 1, x + h); ++xx) {
          ++full;
          const cv::Vec3f p = pts.at<cv::Vec3f>(yy, xx);
          if (!(p[2] > 0.f) || !std::isfinite(p[2])) continue;
          const Eigen::Vector3d v = ray(xx, yy);
          M += v * v.transpose();
          b += v / std::sqrt(double(p[0]) * p[0] + double(p[1]) * p[1] + double(p[2]) * p[2]);
          ++n;
          x0 = std::min(x0, xx);
          x1 = std::max(x1, xx);
          y0 = std::min(y0, yy);
          y1 = std::max(y1, yy);
        }
      if (n < 3 || (n < full && (x1 == x0 || y1 == y0))) continue;
      Eigen::Vector3d nn = M.ldlt().solve(b).normalized();
      const cv::Vec3f p = pts.at<cv::Vec3f>(y, x);
      const Eigen::Vector3d ref = p[2] > 0.f ? Eigen::Vector3d(p[0], p[1], p[2]) : ray(x, y);
      if (nn.dot(ref) > 0) nn = -nn;
      out.at<cv::Vec3f>(y, x) = cv::Vec3f(nn.x(), nn.y(), nn.z());
    }
  return out;
}

// A wavy surface (not a plane: every window's least-squares fit matters) with hole blobs,
// isolated holes, a single valid row and column among holes, and a step edge.
cv::Mat wavyPoints(const Intrinsics& K, cv::Size size, const std::vector<int>& src_u,
                   const std::vector<int>& src_v) {
  cv::Mat pts(size, CV_32FC3);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::RNG rng(5);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const double rx = (src_u[x] - K.cx) / K.fx, ry = (src_v[y] - K.cy) / K.fy;
      double z = 4.0 + 0.3 * std::sin(0.11 * x) * std::cos(0.07 * y) + 0.02 * y;
      if (x > size.width / 2) z += 0.5;  // step edge
      const bool hole = rng.uniform(0.0, 1.0) < 0.02 || std::hypot(x - 40, y - 30) < 6 ||
                        (y >= 50 && y < 60 && y != 55 && x >= 70 && x < 80) ||
                        (y >= 50 && y < 60 && x == 90);
      pts.at<cv::Vec3f>(y, x) =
          hole ? cv::Vec3f(nan, nan, nan)
               : cv::Vec3f(static_cast<float>(rx) * static_cast<float>(z),
                           static_cast<float>(ry) * static_cast<float>(z), static_cast<float>(z));
    }
  return pts;
}

// The same, each pixel its own source pixel.
cv::Mat wavyPoints(const Intrinsics& K, cv::Size size) {
  std::vector<int> su(size.width), sv(size.height);
  for (int x = 0; x < size.width; ++x) su[x] = x;
  for (int y = 0; y < size.height; ++y) sv[y] = y;
  return wavyPoints(K, size, su, sv);
}

// Same NaN pattern, and angles within tol_rad. Float points alone limit a 5x5 fit at 4 m to about
// 1e-5 rad; the float box sums add a few 1e-5 at clipped (border) windows.
void expectMatchesReference(const cv::Mat& normals, const cv::Mat& ref, double tol_rad) {
  int both = 0, mismatched_nan = 0;
  double worst = 0;
  for (int y = 0; y < ref.rows; ++y)
    for (int x = 0; x < ref.cols; ++x) {
      const cv::Vec3f a = normals.at<cv::Vec3f>(y, x), b = ref.at<cv::Vec3f>(y, x);
      if (std::isnan(a[0]) != std::isnan(b[0])) {
        ++mismatched_nan;
        continue;
      }
      if (std::isnan(b[0])) continue;
      const Eigen::Vector3d da(a[0], a[1], a[2]), db(b[0], b[1], b[2]);
      const double e = std::atan2(da.cross(db).norm(), da.dot(db));
      worst = std::max(worst, e);
      ++both;
    }
  EXPECT_EQ(mismatched_nan, 0);
  EXPECT_GT(both, ref.total() / 2);
  EXPECT_LT(worst, tol_rad);
}

TEST(FalsNormals, EqualsTheDefinitionInDoublePrecision) {
  const Intrinsics K{266.37, 266.37, 320.0, 190.0};
  const cv::Size size(131, 97);  // odd width: vector bodies and scalar tails
  std::vector<int> su(size.width), sv(size.height);
  for (int x = 0; x < size.width; ++x) su[x] = 250 + x;
  for (int y = 0; y < size.height; ++y) sv[y] = 200 + y;
  // the same geometry as a crop: pixel (x, y) has source (250 + x, 200 + y)
  const Intrinsics Kc{K.fx, K.fy, K.cx - 250, K.cy - 200};
  const cv::Mat pts = wavyPoints(K, size, su, sv);
  for (int window : {3, 5, 7}) {
    SCOPED_TRACE(testing::Message() << "window " << window);
    FalsNormals fals;
    fals.configure(size, Kc, window);
    cv::Mat normals;
    fals.compute(pts, cv::Range(0, size.height), normals);
    expectMatchesReference(normals, referenceFals(pts, K, window, su, sv), 2e-4);
  }
}

TEST(FalsNormals, EqualsTheDefinitionWhenResampled) {
  // nearest resampling by 2 (even steps, the separable path) and by 1.6 (uneven steps)
  const Intrinsics K{532.74, 532.74, 640.0, 380.0};
  for (double ratio : {2.0, 1.6}) {
    SCOPED_TRACE(testing::Message() << "ratio " << ratio);
    const cv::Size size(120, 80);
    cv::Mat col_map(1, size.width, CV_32SC1), row_map(1, size.height, CV_32SC1);
    std::vector<int> su(size.width), sv(size.height);
    for (int x = 0; x < size.width; ++x) su[x] = col_map.at<int>(x) = 500 + int((x + 0.5) * ratio);
    for (int y = 0; y < size.height; ++y) sv[y] = row_map.at<int>(y) = 400 + int((y + 0.5) * ratio);
    const cv::Mat pts = wavyPoints(K, size, su, sv);
    FalsNormals fals;
    fals.configure(size, K, 5, col_map, row_map);
    cv::Mat normals;
    fals.compute(pts, cv::Range(0, size.height), normals);
    expectMatchesReference(normals, referenceFals(pts, K, 5, su, sv), 2e-4);
  }
}

TEST(FalsNormals, GeometricMapEqualsTheMapOfTheNormals) {
  const Intrinsics K{266.37, 266.37, 60.0, 40.0};
  const cv::Size size(125, 83);
  const cv::Mat pts = wavyPoints(K, size);
  FalsNormals fals;
  fals.configure(size, K, 5);
  cv::Mat normals, G_ref, G, kept;
  fals.compute(pts, cv::Range(0, size.height), normals);
  for (DepthTerm term : {DepthTerm::kNearHigh, DepthTerm::kFarHigh}) {
    Params p;
    p.depth_term = term;
    p.depth_threshold = 4.2;  // both branches of Eq. 2 occur
    p.up_x = 0.1;
    p.up_y = -0.99;
    p.up_z = 0.1;
    p = sanitize(p);
    geometricMap(pts, normals, p, cv::Range(3, 80), G_ref);
    fals.computeGeometric(pts, cv::Range(3, 80), p, G, &kept);
    EXPECT_LT(cv::norm(G, G_ref, cv::NORM_INF), 1e-5);
    cv::Mat G2;
    fals.computeGeometric(pts, cv::Range(3, 80), p, G2);  // without normals: same G
    EXPECT_LT(cv::norm(G2, G_ref, cv::NORM_INF), 1e-5);
    for (int y = 3; y < 80; ++y)
      for (int x = 0; x < size.width; ++x) {
        const cv::Vec3f a = kept.at<cv::Vec3f>(y, x), b = normals.at<cv::Vec3f>(y, x);
        ASSERT_EQ(std::isnan(a[0]), std::isnan(b[0]));
        if (!std::isnan(b[0])) {
          ASSERT_EQ(a, b);
        }
      }
  }
}

// G only where R needs it (a mask): the same bits as the whole map on the mask and 0 elsewhere,
// on every target, for masks of single pixels, runs that end at the last column (the width is
// not a whole number of 16-column units), a full and an empty mask, next to holes.
TEST(FalsNormals, MaskedGeometricMapIsTheWholeMapOnTheMask) {
  const Intrinsics K{266.37, 266.37, 160.0, 40.0};
  const cv::Size size(333, 97);
  const cv::Mat pts = wavyPoints(K, size);  // holes, a step edge, a crescent of pixels
  std::vector<std::pair<const char*, cv::Mat>> masks;
  cv::Mat sparse = cv::Mat::zeros(size, CV_8UC1);
  cv::RNG rng(3);
  for (int i = 0; i < 300; ++i)
    sparse.at<uint8_t>(rng.uniform(0, size.height), rng.uniform(0, size.width)) = 255;
  masks.emplace_back("single pixels", sparse);
  cv::Mat edges = cv::Mat::zeros(size, CV_8UC1);
  for (int y = 0; y < size.height; y += 3) {
    edges.at<uint8_t>(y, 0) = 255;
    edges.at<uint8_t>(y, size.width - 1) = 255;
    for (int x = 310; x < 330; ++x) edges.at<uint8_t>(y + 1 < size.height ? y + 1 : y, x) = 1;
  }
  cv::line(edges, cv::Point(20, 0), cv::Point(140, 96), cv::Scalar(255), 3);  // a marker
  cv::circle(edges, cv::Point(40, 30), 9, cv::Scalar(255), -1);               // over a hole
  masks.emplace_back("edges, a line and a disc", edges);
  masks.emplace_back("full", cv::Mat(size, CV_8UC1, cv::Scalar(255)));
  masks.emplace_back("empty", cv::Mat::zeros(size, CV_8UC1));
  Params p;
  p.depth_threshold = 4.2;  // both branches of Eq. 2
  const cv::Range rows(3, 90);
  cv::Mat other = pts * 1.3;  // an earlier frame's cloud: what the buffers hold before
  // every target, and the reference (every window solved in double) on the best one
  std::vector<std::pair<simd::Target, bool>> runs;
  for (simd::Target target : simd::availableTargets()) runs.emplace_back(target, false);
  runs.emplace_back(simd::kBest, true);
  for (const auto& run : runs) {
    simd::forceTarget(run.first);
    setReferenceStages(run.second);
    for (int window : {3, 5, 7}) {
      FalsNormals whole_fals;
      whole_fals.configure(size, K, window);
      cv::Mat whole;
      whole_fals.computeGeometric(pts, rows, p, whole);
      for (const auto& m : masks) {
        SCOPED_TRACE(testing::Message()
                     << simd::targetName(simd::currentTarget()) << (run.second ? " reference" : "")
                     << ", window " << window << ", mask " << m.first);
        FalsNormals fals;
        fals.configure(size, K, window);
        cv::Mat G;
        fals.computeGeometric(other, rows, p, G);
        G.setTo(7.f);  // stale values must be overwritten
        fals.computeGeometric(pts, rows, p, m.second, G);
        int differ = 0, on_mask = 0;
        for (int y = 0; y < size.height; ++y)
          for (int x = 0; x < size.width; ++x) {
            const float g = G.at<float>(y, x);
            if (y < rows.start || y >= rows.end) {
              differ += g != 7.f;  // rows outside the range are not touched
            } else if (m.second.at<uint8_t>(y, x)) {
              ++on_mask;
              differ += std::memcmp(&g, &whole.at<float>(y, x), sizeof(float)) != 0;
            } else {
              differ += g != 0.f;
            }
          }
        EXPECT_EQ(differ, 0);
        if (std::string(m.first) != "empty") {
          EXPECT_GT(on_mask, 200);
        }
      }
    }
  }
  setReferenceStages(false);
  simd::forceTarget(simd::kBest);
}

// Resampled at an uneven step (the column map steps 1, 2, 1, 2 ... as at scale 0.6) every window
// is solved by the exact path, several per vector: the same bits as the scalar solve (the
// reference) on every target, for normals, G, G with normals and G on a mask, with holes, a
// width that is no whole number of vectors, and the image borders.
TEST(FalsNormals, UnevenResamplingGivesTheReferenceBitsOnEveryTarget) {
  const Intrinsics K{532.74, 532.74, 640.0, 380.0};
  const cv::Size size(203, 61);
  cv::Mat col_map(1, size.width, CV_32SC1), row_map(1, size.height, CV_32SC1);
  std::vector<int> su(size.width), sv(size.height);
  for (int x = 0; x < size.width; ++x) su[x] = col_map.at<int>(x) = 400 + int((x + 0.5) / 0.6);
  for (int y = 0; y < size.height; ++y) sv[y] = row_map.at<int>(y) = 350 + int((y + 0.5) / 0.6);
  const cv::Mat pts = wavyPoints(K, size, su, sv);  // holes, a step edge, a crescent of pixels
  cv::Mat mask = cv::Mat::zeros(size, CV_8UC1);
  cv::line(mask, cv::Point(0, 0), cv::Point(202, 60), cv::Scalar(255), 5);
  cv::circle(mask, cv::Point(180, 20), 12, cv::Scalar(255), -1);
  Params p;
  p.depth_threshold = 4.2;  // both branches of Eq. 2
  const cv::Range rows(0, size.height);
  struct Out {
    cv::Mat normals, G, G_normals, kept, G_mask;
  };
  auto run = [&](int window) {
    Out o;
    FalsNormals fals;
    fals.configure(size, K, window, col_map, row_map);
    fals.compute(pts, rows, o.normals);
    fals.computeGeometric(pts, rows, p, o.G);
    fals.computeGeometric(pts, rows, p, o.G_normals, &o.kept);
    fals.computeGeometric(pts, rows, p, mask, o.G_mask);
    return o;
  };
  auto same = [](const cv::Mat& a, const cv::Mat& b) {
    return a.size() == b.size() && a.type() == b.type() &&
           std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
  };
  for (int window : {3, 5, 7}) {
    setReferenceStages(true);
    const Out ref = run(window);
    setReferenceStages(false);
    int solved = 0;
    for (int y = 0; y < size.height; ++y)
      for (int x = 0; x < size.width; ++x)
        solved += !std::isnan(ref.normals.at<cv::Vec3f>(y, x)[0]);
    EXPECT_GT(solved, static_cast<int>(size.area()) / 2);
    for (simd::Target target : simd::availableTargets()) {
      simd::forceTarget(target);
      SCOPED_TRACE(testing::Message() << simd::targetName(target) << ", window " << window);
      const Out o = run(window);
      EXPECT_TRUE(same(o.normals, ref.normals));
      EXPECT_TRUE(same(o.G, ref.G));
      EXPECT_TRUE(same(o.G_normals, ref.G_normals));
      EXPECT_TRUE(same(o.kept, ref.kept));
      EXPECT_TRUE(same(o.G_mask, ref.G_mask));
    }
  }
  simd::forceTarget(simd::kBest);
}

}  // namespace
}  // namespace rgbd_lane_detector

namespace rgbd_lane_detector {
namespace {

TEST(FalsNormalAt, AgreesWithTheNormalImage) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.1, -0.25, -0.9).normalized();  // faces the camera
  const cv::Size size(160, 120);
  cv::Mat pts = planePoints(n, 3.0, size);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int x = 40; x < 44; ++x) pts.at<cv::Vec3f>(60, x) = cv::Vec3f(nan, nan, nan);  // a hole
  FalsNormals fals;
  fals.configure(size, kK, 5);
  cv::Mat normals;
  fals.compute(pts, cv::Range(0, size.height), normals);
  int checked = 0;
  for (int y = 50; y < 70; y += 3)
    for (int x = 30; x < 60; x += 3) {
      float q[3];
      const cv::Vec3f ref = normals.at<cv::Vec3f>(y, x);
      const bool ok = falsNormalAt(pts, x, y, 5, kK, cv::Mat(), cv::Mat(), q);
      ASSERT_EQ(ok, !std::isnan(ref[0])) << x << "," << y;
      if (!ok) continue;
      EXPECT_LT(angleTo(cv::Vec3f(q[0], q[1], q[2]), n), 1e-3);
      EXPECT_GT(q[0] * ref[0] + q[1] * ref[1] + q[2] * ref[2], 0.999f);
      ++checked;
    }
  EXPECT_GT(checked, 50);
  float q[3];
  EXPECT_FALSE(falsNormalAt(pts, -1, 5, 5, kK, cv::Mat(), cv::Mat(), q));
  cv::Mat empty(size, CV_32FC3, cv::Scalar(nan, nan, nan));
  EXPECT_FALSE(falsNormalAt(empty, 50, 50, 5, kK, cv::Mat(), cv::Mat(), q));
}

}  // namespace
}  // namespace rgbd_lane_detector
