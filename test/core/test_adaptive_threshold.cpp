// Per-row adaptive half-binary threshold.
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/adaptive_threshold.h"

namespace rgbd_lane_detector {
namespace {

TEST(AdaptiveThreshold, RowMedian) {
  std::vector<int> hist;
  const uint8_t row[] = {9, 1, 7, 3, 5};
  EXPECT_EQ(rowMedian(row, 5, hist), 5);
  const uint8_t even[] = {10, 20, 30, 40};
  EXPECT_EQ(rowMedian(even, 4, hist), 20);  // lower median
  // every 4th pixel: 0, 100, 200
  uint8_t strided[12] = {0, 255, 255, 255, 100, 255, 255, 255, 200, 255, 255, 255};
  EXPECT_EQ(rowMedian(strided, 12, hist, 4), 100);
}

// With a stride, rowMedian() reads four samples at a time, then the rest one by one: strides 2
// and 3, odd and even counts of samples (1 to 16), read in fours only or with a tail of 1 to 3,
// the last sample in the row's last column or before it. The samples are 10, 20, ..., 10 n, the
// median among them (the lower one for an even count) in the last sample; the pixels between
// the samples and the stride's pixels after the row must not count: one more sample of 0 moves
// the lower median of an odd count down, one of 255 that of an even count up.
TEST(AdaptiveThreshold, RowMedianWithAStrideReadsEverySampleToTheRowsEnd) {
  std::vector<int> hist;
  for (int stride : {2, 3}) {
    for (int width = 1; width <= 16 * stride; ++width) {
      const int n = (width + stride - 1) / stride;  // samples 0, stride, ... below width
      const int median = 10 * ((n + 1) / 2);
      for (uint8_t other : {uint8_t(0), uint8_t(255)}) {
        SCOPED_TRACE(testing::Message() << "stride " << stride << ", width " << width
                                        << ", others " << int(other));
        std::vector<uint8_t> row(width + stride, other);
        for (int k = 0, v = 1; v <= n; ++v)
          if (10 * v != median) row[stride * k++] = static_cast<uint8_t>(10 * v);
        row[stride * (n - 1)] = static_cast<uint8_t>(median);
        EXPECT_EQ(rowMedian(row.data(), width, hist, stride), median);
        ASSERT_EQ(hist.size(), 256u);
        EXPECT_EQ(std::accumulate(hist.begin(), hist.end(), 0), n);
        EXPECT_EQ(hist[other], 0);
      }
    }
  }
}

TEST(AdaptiveThreshold, EachRowAtItsMedianPlusOffset) {
  // a dark row (shadow, overpass) and a bright row (fog), each with one bright marker pixel
  cv::Mat img(3, 8, CV_8UC1);
  const uint8_t dark[] = {20, 22, 25, 21, 60, 23, 24, 20};
  const uint8_t fog[] = {150, 155, 152, 151, 210, 149, 153, 150};
  std::copy(dark, dark + 8, img.ptr<uint8_t>(0));
  std::copy(fog, fog + 8, img.ptr<uint8_t>(1));
  img.row(2).setTo(77);
  std::vector<int> hist;
  const cv::Mat grey = img.clone();
  cv::Mat out;
  applyRowThreshold(grey, out, cv::Range(0, 2), 30, hist);  // into another image
  applyRowThreshold(img, img, cv::Range(0, 2), 30, hist);   // in place
  for (const cv::Mat* m : {&out, &img}) {
    for (int x = 0; x < 8; ++x) {
      EXPECT_EQ(m->at<uint8_t>(0, x), x == 4 ? 60 : 0);   // a fixed tau_c = 100 would lose it
      EXPECT_EQ(m->at<uint8_t>(1, x), x == 4 ? 210 : 0);  // a fixed tau_c = 100 keeps all fog
    }
  }
  for (int x = 0; x < 8; ++x) {
    EXPECT_EQ(img.at<uint8_t>(2, x), 77);  // outside the rows: untouched
    EXPECT_EQ(out.at<uint8_t>(2, x), 0);   // a new output starts zeroed
  }
  EXPECT_EQ(grey.at<uint8_t>(0, 0), 20);  // the input of the copy is kept
}

TEST(AdaptiveThreshold, DarkRowsTakeThePaintsRelativeContrast) {
  // rows of 40 px (the median reads every 4th pixel): a dark foggy row (median 41): offset
  // 0.25 x 41 = 10, paint at 56 kept where the fixed +30 loses it, 50 not; a row at the dark
  // limit's other side (median 90) keeps the fixed offset: tau 120; a very dark row (median 12)
  // keeps at least kMinRowOffset against noise: tau 20
  cv::Mat img(3, 40, CV_8UC1);
  for (int x = 0; x < 40; ++x) {
    img.at<uint8_t>(0, x) = static_cast<uint8_t>(40 + x % 3);
    img.at<uint8_t>(1, x) = static_cast<uint8_t>(89 + x % 3);
    img.at<uint8_t>(2, x) = static_cast<uint8_t>(11 + x % 3);
  }
  img.at<uint8_t>(0, 21) = 56;
  img.at<uint8_t>(0, 22) = 50;
  img.at<uint8_t>(1, 21) = 120;
  img.at<uint8_t>(1, 22) = 119;
  img.at<uint8_t>(2, 21) = 21;
  img.at<uint8_t>(2, 22) = 19;
  std::vector<int> hist;
  cv::Mat out;
  applyRowThreshold(img, out, cv::Range(0, 3), 30, hist, 0.25);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 40; ++x)
      EXPECT_EQ(out.at<uint8_t>(y, x), x == 21 ? img.at<uint8_t>(y, 21) : 0) << y << " " << x;
  applyRowThreshold(img, out, cv::Range(0, 1), 30, hist);  // fixed offset: tau 71
  EXPECT_EQ(out.at<uint8_t>(0, 21), 0);
}

}  // namespace
}  // namespace rgbd_lane_detector
