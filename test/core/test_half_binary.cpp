// Half-binary image: equal to OpenCV grey conversion followed by THRESH_TOZERO.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "guarded_mat.h"
#include "rgbd_lane_detector/half_binary.h"
#include "rgbd_lane_detector/pixel_kernels.h"
#include "simd.h"  // private: targets

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

// Through index maps (the detector's processing scale): the half-binary image of the resampled
// colour, on every target, for 1, 3 and 4 channels (both channel orders); the maps reach the last
// source column (the 3-channel gather must not read past a row) and rows outside the range stay
// 0. A row wider than the columns gathered between two prefetches (256) is gathered in parts.
TEST(HalfBinary, ThroughIndexMapsIsTheResampledImage) {
  for (const cv::Size& size : {cv::Size(67, 41), cv::Size(497, 23)}) {
    const int w = size.width * 39 / 67, h = size.height * 25 / 41;
    cv::RNG rng(3);
    cv::Mat bgr(size, CV_8UC3);
    rng.fill(bgr, cv::RNG::UNIFORM, 0, 256);
    cv::Mat bgra, grey;
    cv::cvtColor(bgr, bgra, cv::COLOR_BGR2BGRA);
    cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
    cv::Mat col_map(1, w, CV_32SC1), row_map(1, h, CV_32SC1);
    for (int x = 0; x < w; ++x)
      col_map.at<int>(x) = std::min(size.width - 1, static_cast<int>((x + 0.5) * size.width / w));
    for (int y = 0; y < h; ++y)
      row_map.at<int>(y) =
          std::min(size.height - 1, static_cast<int>((y + 0.5) * size.height / h));
    col_map.at<int>(w - 1) = size.width - 1;
    const cv::Range rows(3, h - 3);
    for (simd::Target target : simd::availableTargets()) {
      simd::forceTarget(target);
      for (const auto& [img, fmt] : {std::make_pair(bgr, PixelFormat::kBgr8),
                                     std::make_pair(bgr, PixelFormat::kRgb8),
                                     std::make_pair(bgra, PixelFormat::kBgra8),
                                     std::make_pair(bgra, PixelFormat::kRgba8),
                                     std::make_pair(grey, PixelFormat::kMono8)}) {
        SCOPED_TRACE(testing::Message() << simd::targetName(target) << ", format "
                                        << static_cast<int>(fmt) << ", width " << w);
        for (int tau_c : {0, 100}) {
          cv::Mat small, expected, out;
          remapNearest(img, col_map, row_map, small);
          halfBinary(small, fmt, tau_c, rows, expected);
          halfBinary(img, fmt, tau_c, rows, out, col_map, row_map);
          ASSERT_EQ(out.size(), cv::Size(w, h));
          EXPECT_EQ(cv::countNonZero(out != expected), 0);
        }
      }
    }
  }
  simd::forceTarget(simd::kBest);
}

// The source rows end where an inaccessible page begins (a read past a row's end faults, where an
// ordinary cv::Mat's padding takes it unseen): every format, without a column map and through
// one whose last columns read the last source column (a 3-channel pixel is gathered as 4 bytes:
// one past the row there), wider than the columns gathered between two prefetches (the second
// part 48 columns: on every target, vectors reach the map's last column), the source's last row
// read by every other output row; on every target, the thresholded grey of the source pixel.
TEST(HalfBinary, NoReadPastTheSourceRowsEnd) {
  cv::RNG rng(17);
  const int rows = 3, cols = 451, tau_c = 100;
  cv::Mat bgr(rows, cols, CV_8UC3);
  rng.fill(bgr, cv::RNG::UNIFORM, 0, 256);
  const cv::Mat expected = reference(bgr, tau_c);
  cv::Mat rgb, bgra, rgba, grey;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  cv::cvtColor(bgr, bgra, cv::COLOR_BGR2BGRA);
  cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  const int w = 304;
  cv::Mat col_map(1, w, CV_32SC1), row_map = (cv::Mat_<int>(1, 5) << 2, 0, 2, 1, 2);
  for (int x = 0; x < w; ++x) col_map.at<int>(x) = std::min(cols - 1, x * 3 / 2);
  for (int x = w - 12; x < w; ++x) col_map.at<int>(x) = cols - 1 - (x % 3 == 1);
  ASSERT_EQ(col_map.at<int>(w - 1), cols - 1);
  for (const auto& [img, fmt] : {std::make_pair(bgr, PixelFormat::kBgr8),
                                 std::make_pair(rgb, PixelFormat::kRgb8),
                                 std::make_pair(bgra, PixelFormat::kBgra8),
                                 std::make_pair(rgba, PixelFormat::kRgba8),
                                 std::make_pair(grey, PixelFormat::kMono8)}) {
    const test::GuardedMat guarded(img);
    ASSERT_EQ(guarded.end(), guarded.guard());
    for (simd::Target target : simd::availableTargets()) {
      simd::forceTarget(target);
      SCOPED_TRACE(testing::Message() << simd::targetName(target) << ", format "
                                      << static_cast<int>(fmt));
      cv::Mat out, mapped;
      halfBinary(guarded.mat(), fmt, tau_c, cv::Range(0, rows), out);
      EXPECT_EQ(cv::countNonZero(out != expected), 0);
      halfBinary(guarded.mat(), fmt, tau_c, cv::Range(0, 5), mapped, col_map, row_map);
      ASSERT_EQ(mapped.size(), cv::Size(w, 5));
      for (int y = 0; y < 5; ++y)
        for (int x = 0; x < w; ++x)
          EXPECT_EQ(mapped.at<uint8_t>(y, x),
                    expected.at<uint8_t>(row_map.at<int>(y), col_map.at<int>(x)))
              << y << " " << x;
    }
  }
  simd::forceTarget(simd::kBest);
}

}  // namespace
}  // namespace rgbd_lane_detector
