// Half-binary image: equal to OpenCV grey conversion followed by THRESH_TOZERO.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector/half_binary.h"

namespace rgbd_lane_detector {
namespace {

cv::Mat reference(const cv::Mat& bgr, int tau_c) {
  cv::Mat grey, out;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  cv::threshold(grey, out, tau_c - 1, 0, cv::THRESH_TOZERO);  // keep grey >= tau_c
  return out;
}

TEST(HalfBinary, MatchesOpenCvForEveryFormat) {
  cv::RNG rng(7);
  cv::Mat bgr(37, 53, CV_8UC3);
  rng.fill(bgr, cv::RNG::UNIFORM, 0, 256);
  const int tau_c = 100;
  const cv::Mat expected = reference(bgr, tau_c);
  const cv::Range all(0, bgr.rows);

  cv::Mat rgb, bgra, rgba, out;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  cv::cvtColor(bgr, bgra, cv::COLOR_BGR2BGRA);
  cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
  for (const auto& [img, fmt] : {std::make_pair(bgr, PixelFormat::kBgr8),
                                 std::make_pair(rgb, PixelFormat::kRgb8),
                                 std::make_pair(bgra, PixelFormat::kBgra8),
                                 std::make_pair(rgba, PixelFormat::kRgba8)}) {
    halfBinary(img, fmt, tau_c, all, out);
    ASSERT_EQ(out.type(), CV_8UC1);
    EXPECT_EQ(cv::countNonZero(out != expected), 0) << "format " << static_cast<int>(fmt);
  }
  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  halfBinary(grey, PixelFormat::kMono8, tau_c, all, out);
  EXPECT_EQ(cv::countNonZero(out != expected), 0);
}

TEST(HalfBinary, ThresholdBoundaryAndRowRange) {
  cv::Mat grey(4, 3, CV_8UC1);
  grey.row(0).setTo(99);
  grey.row(1).setTo(100);
  grey.row(2).setTo(255);
  grey.row(3).setTo(0);
  cv::Mat out(4, 3, CV_8UC1, cv::Scalar(7));
  halfBinary(grey, PixelFormat::kMono8, 100, cv::Range(0, 3), out);
  EXPECT_EQ(out.at<uint8_t>(0, 0), 0);    // below tau_c: zero
  EXPECT_EQ(out.at<uint8_t>(1, 1), 100);  // at tau_c: kept
  EXPECT_EQ(out.at<uint8_t>(2, 2), 255);
  EXPECT_EQ(out.at<uint8_t>(3, 0), 7);    // outside the row range: untouched
}

TEST(HalfBinary, GreyWeightsAreBt601) {
  EXPECT_EQ(greyValue(255, 0, 0), 76);
  EXPECT_EQ(greyValue(0, 255, 0), 150);
  EXPECT_EQ(greyValue(0, 0, 255), 29);
  EXPECT_EQ(greyValue(255, 255, 255), 255);
}

}  // namespace
}  // namespace rgbd_lane_detector
