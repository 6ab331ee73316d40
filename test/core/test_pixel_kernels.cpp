// The detector's per-pixel passes: nearest-neighbour resampling through index maps, the plane
// gate of the response maps.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/pixel_kernels.h"

namespace rgbd_lane_detector {
namespace {

TEST(RemapNearest, TakesTheMappedSourcePixelOfEveryChannel) {
  cv::Mat src(4, 5, CV_8UC3);
  for (int y = 0; y < src.rows; ++y)
    for (int x = 0; x < src.cols; ++x) src.at<cv::Vec3b>(y, x) = cv::Vec3b(10 * y + x, x, y);
  const cv::Mat col_map = (cv::Mat_<int>(1, 3) << 0, 2, 4);
  const cv::Mat row_map = (cv::Mat_<int>(1, 2) << 1, 3);
  cv::Mat dst;
  remapNearest(src, col_map, row_map, dst);
  ASSERT_EQ(dst.size(), cv::Size(3, 2));
  ASSERT_EQ(dst.type(), CV_8UC3);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      EXPECT_EQ(dst.at<cv::Vec3b>(y, x), src.at<cv::Vec3b>(row_map.at<int>(y), col_map.at<int>(x)));
  uchar* data = dst.data;
  remapNearest(src, col_map, row_map, dst);  // sized: no new buffer
  EXPECT_EQ(dst.data, data);
}

TEST(PlaneGate, RemovesStrongMatchesOffThePlaneOnly) {
  // a level road 1.5 m below the camera: y = 1.5 on it
  PlaneEstimate plane;
  plane.valid = true;
  plane.normal = Eigen::Vector3d(0, -1, 0);
  plane.distance = 1.5;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::Mat points(1, 40, CV_32FC3, cv::Scalar(0.f, 1.5f, 10.f));  // on the road
  points.at<cv::Vec3f>(0, 3) = cv::Vec3f(0.f, 0.5f, 10.f);          // 1 m above it
  points.at<cv::Vec3f>(0, 20) = cv::Vec3f(0.f, 0.5f, 10.f);         // 1 m above, weak match
  points.at<cv::Vec3f>(0, 30) = cv::Vec3f(nan, nan, nan);           // no depth
  cv::Mat left(1, 40, CV_32FC1, cv::Scalar(0.9f)), right(1, 40, CV_32FC1, cv::Scalar(0.f));
  left.at<float>(0, 20) = 0.1f;
  right.at<float>(0, 20) = 0.1f;
  applyPlaneGate(points, cv::Range(0, 1), plane, 0.3f, 0.5f, left, right);
  for (int x = 0; x < 40; ++x) {
    const float expected = x == 3 ? 0.f : (x == 20 ? 0.1f : 0.9f);
    EXPECT_EQ(left.at<float>(0, x), expected) << x;
  }
  EXPECT_EQ(right.at<float>(0, 20), 0.1f);  // below tau: not looked at
}

}  // namespace
}  // namespace rgbd_lane_detector
