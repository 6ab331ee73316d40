// FALS normals: accuracy on planes, agreement with OpenCV contrib, orientation, invalid depth.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <opencv2/opencv_modules.hpp>
#ifdef HAVE_OPENCV_RGBD
#include <opencv2/rgbd.hpp>
#endif

#include "rgbd_lane_detector/depth_points.h"
#include "rgbd_lane_detector/fals_normals.h"

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
      pts.at<cv::Vec3f>(v, u) = (t > 0 && t <= max_z)
                                    ? cv::Vec3f(static_cast<float>(r.x() * t),
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

#ifdef HAVE_OPENCV_RGBD
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

}  // namespace
}  // namespace rgbd_lane_detector
