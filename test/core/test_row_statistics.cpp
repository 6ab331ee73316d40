// The classifier's row statistics: medians equal to std::nth_element's element on every path
// (insertion-sort sizes, counting sizes, non-finite values, grey values), and the step most rows
// agree on.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "row_statistics.h"

namespace rgbd_lane_detector {
namespace {

float nthElement(std::vector<float> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

TEST(RowStatistics, MedianOfSmallSetsByHand) {
  std::vector<float> v;
  EXPECT_TRUE(std::isnan(median(v)));
  v = {3.f, 1.f, 2.f};
  EXPECT_EQ(median(v), 2.f);
  v = {4.f, 1.f, 3.f, 2.f};
  EXPECT_EQ(median(v), 3.f);  // the upper of the two middle elements (index n / 2)
}

TEST(RowStatistics, MedianIsTheElementNthElementPutsInTheMiddle) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> level(0, 20);  // many ties
  for (int n = 1; n <= 90; ++n) {
    std::vector<float> v(n);
    for (float& x : v) x = 0.25f * static_cast<float>(level(rng)) - 2.0f;
    const float expected = nthElement(v);
    EXPECT_EQ(median(v), expected) << n;
    if (n > 20) {  // a non-finite value takes the nth_element path: still the same element
      v[3] = INFINITY;
      EXPECT_EQ(median(v), nthElement(v)) << n;
    }
  }
}

TEST(RowStatistics, GreyMedianIsTheMedianOfGreyValues) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> grey(0, 255);
  for (int n : {1, 2, 5, 16, 17, 30, 64, 65, 121, 200}) {
    std::vector<float> v(n);
    for (float& x : v) x = static_cast<float>(grey(rng));
    std::vector<float> w = v;
    EXPECT_EQ(greyMedian(v), median(w)) << n;
  }
  std::vector<float> flat(40, 80.f);
  flat[0] = 255.f;
  EXPECT_EQ(greyMedian(flat), 80.f);
}

// Grey values spread over the whole range (a row's dark and bright pixels): the median found in
// its bin of 16 grey levels, at both ends of a bin and of the range, is nth_element's element.
TEST(RowStatistics, GreyMedianAtTheEndsOfItsCountingBins) {
  std::mt19937 rng(17);
  std::uniform_int_distribution<int> grey(0, 255);
  for (int middle : {0, 15, 16, 17, 31, 32, 127, 128, 239, 240, 254, 255}) {
    for (int n : {17, 18, 33, 64, 65, 96, 121, 321}) {
      // about half the values below the middle one, the rest above (or equal)
      std::vector<float> v(n);
      for (int i = 0; i < n; ++i) {
        const int g = grey(rng);
        v[i] = static_cast<float>(i < n / 2 ? std::min(g, middle) : std::max(g, middle));
      }
      std::vector<uint8_t> bytes(v.begin(), v.end());
      const float expected = nthElement(v);
      EXPECT_EQ(greyMedian(bytes.data(), n / 3, bytes.data() + n / 3, n - n / 3), expected)
          << middle << " " << n;
      EXPECT_EQ(greyMedian(v), expected) << middle << " " << n;
    }
  }
}

// The median of two runs of grey bytes (a profile's two sides, read in place) is greyMedian() of
// the same values as floats, on both of its paths (up to 16 values and counted), with ties.
TEST(RowStatistics, GreyMedianOfTwoByteRunsIsGreyMedianOfTheirValues) {
  std::mt19937 rng(13);
  std::uniform_int_distribution<int> grey(60, 140);
  for (int na : {0, 1, 3, 8, 9, 40, 96}) {
    for (int nb : {0, 2, 3, 8, 17, 96}) {
      std::vector<uint8_t> a(na + 1), b(nb + 1);
      for (auto& x : a) x = static_cast<uint8_t>(grey(rng));
      for (auto& x : b) x = static_cast<uint8_t>(grey(rng));
      std::vector<float> v;
      for (int i = 0; i < na; ++i) v.push_back(a[i]);
      for (int i = 0; i < nb; ++i) v.push_back(b[i]);
      const float got = greyMedian(a.data(), na, b.data(), nb);
      if (v.empty()) {
        EXPECT_TRUE(std::isnan(got));
        continue;
      }
      EXPECT_EQ(got, greyMedian(v)) << na << " " << nb;
    }
  }
}

TEST(RowStatistics, StepInMostRowsNeedsTheShareAndTheRows) {
  // 7 of 10 rows show a 12 cm kerb: 70 % reach 10 cm, the step is their median
  std::vector<float> steps = {0.12f, 0.13f, 0.11f, 0.12f, 0.0f, 0.12f, 0.01f, 0.14f, 0.12f, -0.01f};
  float step = 0.f;
  EXPECT_TRUE(stepInMostRows(steps, 0.1f, 3, 0.7, step));
  EXPECT_EQ(step, 0.12f);
  // 6 of 10: no consistent step
  steps = {0.12f, 0.13f, 0.11f, 0.12f, 0.0f, 0.12f, 0.01f, 0.02f, 0.12f, -0.01f};
  EXPECT_TRUE(stepInMostRows(steps, 0.1f, 3, 0.7, step));
  EXPECT_TRUE(std::isnan(step));
  // fewer rows than needed: not measured
  steps = {0.12f, 0.12f};
  EXPECT_FALSE(stepInMostRows(steps, 0.1f, 3, 0.7, step));
  EXPECT_TRUE(std::isnan(step));
}

}  // namespace
}  // namespace rgbd_lane_detector
