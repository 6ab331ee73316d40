// Disparity to depth (Z = f T / d): analytic values, every invalid case, the valid window,
// strides, in-place use, no allocation when sized, and bad input.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/disparity_depth.h"

namespace rgbd_lane_detector {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

DisparityModel model(double f = 700.0, double T = 0.12) {
  DisparityModel m;
  m.focal = f;
  m.baseline = T;
  return m;
}

cv::Mat row(std::initializer_list<float> values) {
  cv::Mat m(1, static_cast<int>(values.size()), CV_32FC1);
  int i = 0;
  for (float v : values) m.at<float>(0, i++) = v;
  return m;
}

TEST(DisparityDepth, DepthIsFocalTimesBaselineOverDisparity) {
  const cv::Mat d = row({1.f, 8.f, 16.5f, 84.f, 127.9375f, 0.0625f});
  cv::Mat z;
  ASSERT_EQ(disparityToDepth(d, model(), z), nullptr);
  ASSERT_EQ(z.type(), CV_32FC1);
  ASSERT_EQ(z.size(), d.size());
  for (int x = 0; x < d.cols; ++x)
    EXPECT_NEAR(z.at<float>(0, x), 700.0 * 0.12 / d.at<float>(0, x),
                1e-6 * 700.0 * 0.12 / d.at<float>(0, x))
        << "column " << x;
  EXPECT_FLOAT_EQ(z.at<float>(0, 3), 1.0f);  // 84 / 84
}

TEST(DisparityDepth, InvalidDisparitiesAreNaN) {
  DisparityModel m = model();
  m.min_disparity = 0.0;  // stereo_image_proc: unmatched pixels are min_disparity - 1 = -1
  m.max_disparity = 127.0;
  m.delta_d = 1.0 / 16;
  // NaN, +inf, -inf, 0, the unmatched marker -1, above the range, within delta_d of zero
  const cv::Mat d = row({kNaN, kInf, -kInf, 0.f, -1.f, 127.5f, 0.05f, 2.f, 127.f, 0.0625f});
  cv::Mat z;
  ASSERT_EQ(disparityToDepth(d, m, z), nullptr);
  for (int x = 0; x < 7; ++x) EXPECT_TRUE(std::isnan(z.at<float>(0, x))) << "column " << x;
  EXPECT_FLOAT_EQ(z.at<float>(0, 7), 42.f);
  EXPECT_FLOAT_EQ(z.at<float>(0, 8), static_cast<float>(84.0 / 127.0));
  EXPECT_FLOAT_EQ(z.at<float>(0, 9), 84.f * 16.f);  // one step of the resolution is valid
}

TEST(DisparityDepth, ZeroDisparityIsNaNWithoutAnyBound) {
  cv::Mat z;
  ASSERT_EQ(disparityToDepth(row({0.f, -0.f, -3.f, 3.f}), model(), z), nullptr);
  EXPECT_TRUE(std::isnan(z.at<float>(0, 0)));
  EXPECT_TRUE(std::isnan(z.at<float>(0, 1)));
  EXPECT_TRUE(std::isnan(z.at<float>(0, 2)));  // negative depth
  EXPECT_FLOAT_EQ(z.at<float>(0, 3), 28.f);
}

TEST(DisparityDepth, MinDisparityBoundsExactly) {
  // stereo_msgs: only disparities *less than* min_disparity are invalid; bounds that floats
  // cannot hold exactly (0.1) are applied exactly.
  DisparityModel m = model();
  m.min_disparity = 10.0;
  cv::Mat z;
  ASSERT_EQ(disparityToDepth(row({10.f, std::nextafter(10.f, 0.f), 9.f, 64.f}), m, z), nullptr);
  EXPECT_FLOAT_EQ(z.at<float>(0, 0), 8.4f);
  EXPECT_TRUE(std::isnan(z.at<float>(0, 1)));
  EXPECT_TRUE(std::isnan(z.at<float>(0, 2)));
  EXPECT_FLOAT_EQ(z.at<float>(0, 3), 84.f / 64.f);

  m.min_disparity = 0.1;
  const float above = 0.1f;                           // 0.100000001...
  const float below = std::nextafter(0.1f, 0.f);      // 0.099999994...
  ASSERT_EQ(disparityToDepth(row({above, below}), m, z), nullptr);
  EXPECT_FALSE(std::isnan(z.at<float>(0, 0)));
  EXPECT_TRUE(std::isnan(z.at<float>(0, 1)));
}

TEST(DisparityDepth, MaxDisparityOnlyBoundsARange) {
  DisparityModel m = model();
  m.min_disparity = 0.0;
  m.max_disparity = 0.0;  // a driver that fills neither field: no upper bound
  cv::Mat z;
  ASSERT_EQ(disparityToDepth(row({500.f}), m, z), nullptr);
  EXPECT_FLOAT_EQ(z.at<float>(0, 0), 84.f / 500.f);
  m.max_disparity = 400.0;
  ASSERT_EQ(disparityToDepth(row({500.f, 400.f}), m, z), nullptr);
  EXPECT_TRUE(std::isnan(z.at<float>(0, 0)));
  EXPECT_FLOAT_EQ(z.at<float>(0, 1), 84.f / 400.f);
}

TEST(DisparityDepth, NegativeDisparityConvention) {
  // d = x_r - x_l < 0 with T < 0 (ZED-style): Z = f T / d is still positive; the range
  // [f T / Z_min, f T / Z_max] = [-280, -4.2] for 0.3-20 m.
  DisparityModel m = model(700.0, -0.12);
  m.min_disparity = 700.0 * -0.12 / 0.3;
  m.max_disparity = 700.0 * -0.12 / 20.0;
  cv::Mat z;
  ASSERT_EQ(disparityToDepth(row({-42.f, -279.f, -300.f, -4.f, 42.f}), m, z), nullptr);
  EXPECT_FLOAT_EQ(z.at<float>(0, 0), 2.f);
  EXPECT_FLOAT_EQ(z.at<float>(0, 1), 84.f / 279.f);
  EXPECT_TRUE(std::isnan(z.at<float>(0, 2)));  // nearer than the search range
  EXPECT_TRUE(std::isnan(z.at<float>(0, 3)));  // beyond it
  EXPECT_TRUE(std::isnan(z.at<float>(0, 4)));  // wrong sign: behind the camera
}

// A rig whose baseline's sign does not match its disparities' (stereo_image_proc's d = x_l - x_r
// with T < 0) gives no depth anywhere: counted, so that the nodelet can say why; the count agrees
// with the conversion's depths.
TEST(DisparityDepth, CountsValidPixelsAndThoseOfTheWrongSign) {
  cv::Mat z;
  DisparityCounts n;
  const cv::Mat d = row({42.f, 84.f, 0.f, kNaN, -1.f, 3.f});
  const auto count = [&](const DisparityModel& m) {
    n = countDisparities(d, m);
    return disparityToDepth(d, m, z);
  };
  ASSERT_EQ(count(model(700.0, 0.12)), nullptr);
  EXPECT_EQ(cv::countNonZero(z == z), n.valid);
  EXPECT_EQ(n.valid, 3);  // 42, 84, 3
  EXPECT_EQ(n.wrong_sign, 1);  // -1: behind the camera
  ASSERT_EQ(count(model(700.0, -0.12)), nullptr);
  EXPECT_EQ(cv::countNonZero(z == z), n.valid);
  EXPECT_EQ(n.valid, 1);  // -1
  EXPECT_EQ(n.wrong_sign, 3);
  DisparityModel m = model(700.0, -0.12);
  m.min_disparity = 1.0;  // stereo_image_proc's range, T of the wrong sign: nothing valid
  m.max_disparity = 128.0;
  ASSERT_EQ(count(m), nullptr);
  EXPECT_EQ(n.valid, 0);
  EXPECT_EQ(n.wrong_sign, 3);
  m.valid_window = cv::Rect(4, 0, 2, 1);  // the window's pixels alone: -1 out of range, 3
  ASSERT_EQ(count(m), nullptr);
  EXPECT_EQ(n.valid, 0);
  EXPECT_EQ(n.wrong_sign, 1);
}

TEST(DisparityDepth, ValidWindow) {
  cv::Mat d(4, 6, CV_32FC1, cv::Scalar(21.f));  // Z = 4 m everywhere
  DisparityModel m = model();
  m.valid_window = cv::Rect(2, 1, 3, 2);
  cv::Mat z;
  ASSERT_EQ(disparityToDepth(d, m, z), nullptr);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) {
      const bool inside = x >= 2 && x < 5 && y >= 1 && y < 3;
      if (inside)
        EXPECT_FLOAT_EQ(z.at<float>(y, x), 4.f) << x << "," << y;
      else
        EXPECT_TRUE(std::isnan(z.at<float>(y, x))) << x << "," << y;
    }
  // partly outside the image: clipped
  m.valid_window = cv::Rect(4, -3, 10, 5);
  ASSERT_EQ(disparityToDepth(d, m, z), nullptr);
  EXPECT_EQ(cv::countNonZero(z == z), 2 * 2);  // columns 4-5 of rows 0-1 (NaN != NaN)
  EXPECT_FLOAT_EQ(z.at<float>(1, 5), 4.f);
  // entirely outside: nothing valid
  m.valid_window = cv::Rect(10, 10, 3, 3);
  ASSERT_EQ(disparityToDepth(d, m, z), nullptr);
  EXPECT_EQ(cv::countNonZero(z == z), 0);
  // empty: the whole image
  m.valid_window = cv::Rect();
  ASSERT_EQ(disparityToDepth(d, m, z), nullptr);
  EXPECT_EQ(cv::countNonZero(z == z), 24);
}

TEST(DisparityDepth, RowsByStepWithoutAllocation) {
  // input and output are regions of larger images (step > cols * 4)
  cv::Mat big_d(10, 20, CV_32FC1, cv::Scalar(-1.f));
  cv::Mat d = big_d(cv::Rect(3, 2, 7, 5));
  for (int y = 0; y < d.rows; ++y)
    for (int x = 0; x < d.cols; ++x) d.at<float>(y, x) = 1.f + y * 7 + x;
  cv::Mat big_z(12, 30, CV_32FC1, cv::Scalar(-5.f));
  cv::Mat z = big_z(cv::Rect(11, 4, 7, 5));
  const uchar* before = z.data;
  ASSERT_EQ(disparityToDepth(d, model(), z), nullptr);
  EXPECT_EQ(z.data, before);  // sized: written in place, no allocation
  for (int y = 0; y < d.rows; ++y)
    for (int x = 0; x < d.cols; ++x)
      EXPECT_FLOAT_EQ(z.at<float>(y, x), 84.f / (1.f + y * 7 + x));
  // nothing outside the region was touched
  EXPECT_EQ(cv::countNonZero(big_z != -5.f), 7 * 5);
}

TEST(DisparityDepth, InPlace) {
  cv::Mat d = row({42.f, 0.f, 84.f});
  const uchar* data = d.data;
  ASSERT_EQ(disparityToDepth(d, model(), d), nullptr);
  EXPECT_EQ(d.data, data);
  EXPECT_FLOAT_EQ(d.at<float>(0, 0), 2.f);
  EXPECT_TRUE(std::isnan(d.at<float>(0, 1)));
  EXPECT_FLOAT_EQ(d.at<float>(0, 2), 1.f);
}

TEST(DisparityDepth, BadInputLeavesOutputUntouched) {
  cv::Mat z(1, 1, CV_32FC1, cv::Scalar(7.f));
  EXPECT_NE(disparityToDepth(cv::Mat(), model(), z), nullptr);
  EXPECT_NE(disparityToDepth(cv::Mat(2, 2, CV_16SC1, cv::Scalar(16)), model(), z), nullptr);
  EXPECT_NE(disparityToDepth(cv::Mat(2, 2, CV_32FC2, cv::Scalar(1.f)), model(), z), nullptr);
  const cv::Mat d = row({42.f});
  for (const DisparityModel& m :
       {model(0.0, 0.12), model(-700.0, 0.12), model(kNaN, 0.12), model(700.0, 0.0),
        model(700.0, kInf), model(1e30, 1e30)}) {
    ASSERT_NE(m.problem(), nullptr);
    EXPECT_NE(disparityToDepth(d, m, z), nullptr);
  }
  DisparityModel m = model();
  m.delta_d = -1.0;
  EXPECT_NE(disparityToDepth(d, m, z), nullptr);
  m = model();
  m.min_disparity = kNaN;
  EXPECT_NE(disparityToDepth(d, m, z), nullptr);
  EXPECT_EQ(z.size(), cv::Size(1, 1));
  EXPECT_FLOAT_EQ(z.at<float>(0, 0), 7.f);
  EXPECT_EQ(model().problem(), nullptr);
}

}  // namespace
}  // namespace rgbd_lane_detector
