// Stereo depth of the offline tools: StereoSGBM with the left-right check and left padding on
// rendered pairs of known disparity, its settings from text, and the LiDAR comparison.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector_tools/stereo/stereo_check.h"
#include "rgbd_lane_detector_tools/stereo/stereo_matcher.h"

namespace rgbd_lane_detector {
namespace tools {
namespace {

constexpr int kW = 320, kH = 120;
constexpr int kBackground = 20, kForeground = 40;  // disparities (px)
const cv::Rect kBox(150, 30, 80, 60);              // foreground in the left image

cv::Mat texture(int seed) {
  cv::Mat t(kH, kW + 2 * kForeground, CV_8UC1);
  cv::RNG rng(seed);
  rng.fill(t, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(t, t, cv::Size(3, 3), 0.8);
  return t;
}

// A textured background plane at disparity 20 with a textured box at disparity 40 in front;
// the right image is rendered by the geometry (the box hides part of the background), so the
// background just left of the box is seen by the left camera only.
void renderPair(cv::Mat& left, cv::Mat& right) {
  const cv::Mat bg = texture(1), fg = texture(2);
  left.create(kH, kW, CV_8UC3);
  right.create(kH, kW, CV_8UC3);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const uchar l = kBox.contains(cv::Point(x, y)) ? fg.at<uchar>(y, x) : bg.at<uchar>(y, x);
      // right pixel x shows the left pixel x + d of whatever is nearest
      const bool box = kBox.contains(cv::Point(x + kForeground, y));
      const uchar r = box ? fg.at<uchar>(y, x + kForeground) : bg.at<uchar>(y, x + kBackground);
      left.at<cv::Vec3b>(y, x) = cv::Vec3b(l, l, l);
      right.at<cv::Vec3b>(y, x) = cv::Vec3b(r, r, r);
    }
}

int trueDisparity(int x, int y) { return kBox.contains(cv::Point(x, y)) ? kForeground : kBackground; }

// Background pixels of the left image that the right camera cannot see (hidden by the box).
bool occluded(int x, int y) {
  // the box covers right columns [x0 - 40, x1 - 40); a background point lands at x - 20
  return y >= kBox.y && y < kBox.br().y && x < kBox.x && x - kBackground >= kBox.x - kForeground;
}

struct Tally {
  int visible = 0, visible_ok = 0, visible_wrong = 0;
};

Tally tally(const cv::Mat& d, int first_column) {
  Tally t;
  const int border = 4;  // the block's half width at the image edges
  for (int y = border; y < kH - border; ++y)
    for (int x = first_column; x < kW - border; ++x) {
      const float v = d.at<float>(y, x);
      if (occluded(x, y)) continue;  // no true match
      if (std::abs(x - kBox.x) <= 3 || std::abs(x - kBox.br().x) <= 3) continue;  // box edges
      ++t.visible;
      if (v < 0.f) continue;
      if (std::fabs(v - trueDisparity(x, y)) <= 1.f)
        ++t.visible_ok;
      else
        ++t.visible_wrong;
    }
  return t;
}

TEST(StereoMatcher, RecoversKnownDisparities) {
  cv::Mat left, right;
  renderPair(left, right);
  SgbmParams p;
  p.num_disparities = 64;
  StereoMatcher matcher(p);
  cv::Mat d;
  ASSERT_EQ(matcher.disparity(left, right, d), nullptr);
  ASSERT_EQ(d.type(), CV_32FC1);
  ASSERT_EQ(d.size(), left.size());
  // columns from kBackground on: every background point there is seen by both cameras
  const Tally t = tally(d, kBackground);
  EXPECT_GT(t.visible_ok, 0.97 * t.visible) << t.visible_ok << " / " << t.visible;
  EXPECT_LT(t.visible_wrong, 0.005 * t.visible);
  // depth is Z = f B / d through the core's conversion
  cv::Mat z;
  ASSERT_EQ(matcher.depth(left, right, 700.0, 0.5, z), nullptr);
  EXPECT_NEAR(z.at<float>(60, 190), 700.0 * 0.5 / kForeground, 0.05);
  EXPECT_NEAR(z.at<float>(20, 100), 700.0 * 0.5 / kBackground, 0.1);
  EXPECT_TRUE(std::isnan(z.at<float>(60, 150 - 5)));  // occluded: no match
}

TEST(StereoMatcher, LeftRightCheckKeepsConsistentDisparitiesOnly) {
  cv::Mat left, right;
  renderPair(left, right);
  SgbmParams p;
  p.num_disparities = 64;
  p.disp12_max_diff = -1;  // OpenCV's own check off: the explicit one alone
  p.lr_check = 0.0;
  cv::Mat unchecked, checked, mirrored;
  ASSERT_EQ(StereoMatcher(p).disparity(left, right, unchecked), nullptr);
  // the right view's disparities, independently: the mirrored pair (right image as the left)
  cv::Mat left_m, right_m;
  cv::flip(right, left_m, 1);
  cv::flip(left, right_m, 1);
  ASSERT_EQ(StereoMatcher(p).disparity(left_m, right_m, mirrored), nullptr);
  cv::flip(mirrored, mirrored, 1);
  p.lr_check = 1.0;
  ASSERT_EQ(StereoMatcher(p).disparity(left, right, checked), nullptr);
  int kept = 0, rejected = 0;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const float d = unchecked.at<float>(y, x);
      if (d < 0.f) {
        ASSERT_LT(checked.at<float>(y, x), 0.f) << x << "," << y;
        continue;
      }
      // the right camera sees this pixel at x - d; its disparity there must agree
      const int xr = cvRound(x - d);
      const float dr = xr >= 0 ? mirrored.at<float>(y, xr) : -1.f;
      const bool consistent = dr >= 0.f && std::fabs(dr - d) <= 1.f;
      if (consistent) {
        ASSERT_EQ(checked.at<float>(y, x), d) << x << "," << y;
        ++kept;
      } else {
        ASSERT_LT(checked.at<float>(y, x), 0.f) << x << "," << y << " d " << d << " dr " << dr;
        ++rejected;
      }
    }
  }
  EXPECT_GT(rejected, 0);
  EXPECT_GT(kept, 20 * rejected);
  // with the check, what is left of the background strip that the box hides from the right
  // camera is at most a few pixels
  int occluded_kept = 0, occluded_total = 0;
  for (int y = kBox.y; y < kBox.br().y; ++y)
    for (int x = 0; x < kBox.x; ++x)
      if (occluded(x, y)) {
        ++occluded_total;
        occluded_kept += checked.at<float>(y, x) >= 0.f;
      }
  EXPECT_LT(occluded_kept, 0.05 * occluded_total);
}

TEST(StereoMatcher, LeftPaddingMatchesTheLeftBorder) {
  cv::Mat left, right;
  renderPair(left, right);
  SgbmParams p;
  p.num_disparities = 64;
  p.pad_left = false;
  cv::Mat plain, padded;
  StereoMatcher(p).disparity(left, right, plain);
  p.pad_left = true;
  StereoMatcher(p).disparity(left, right, padded);
  // OpenCV leaves the first num_disparities columns unmatched; with padding, background
  // pixels there that the right camera sees (x >= 20) get their disparity
  const cv::Rect border(kBackground + 4, 4, 64 - kBackground - 4, kH - 8);
  EXPECT_EQ(cv::countNonZero(plain(border) >= 0.f), 0);
  int ok = 0;
  for (int y = border.y; y < border.br().y; ++y)
    for (int x = border.x; x < border.br().x; ++x)
      ok += std::fabs(padded.at<float>(y, x) - kBackground) <= 1.f;
  EXPECT_GT(ok, 0.95 * border.area());
}

TEST(StereoMatcher, BadInput) {
  StereoMatcher m;
  cv::Mat d;
  const cv::Mat a(40, 60, CV_8UC3, cv::Scalar::all(0)), b(40, 62, CV_8UC3, cv::Scalar::all(0));
  EXPECT_NE(m.disparity(cv::Mat(), a, d), nullptr);
  EXPECT_NE(m.disparity(a, b, d), nullptr);
  EXPECT_NE(m.disparity(a, cv::Mat(40, 60, CV_8UC1, cv::Scalar(0)), d), nullptr);
  EXPECT_NE(m.disparity(cv::Mat(40, 60, CV_16UC1), cv::Mat(40, 60, CV_16UC1), d), nullptr);
}

TEST(SgbmParams, FromText) {
  SgbmParams p;
  std::string error;
  EXPECT_TRUE(setSgbmParam(p, "num_disparities", "192", error));
  EXPECT_EQ(p.num_disparities, 192);
  EXPECT_TRUE(setSgbmParam(p, "mode", "hh", error));
  EXPECT_EQ(p.mode, "hh");
  EXPECT_TRUE(setSgbmParam(p, "lr_check", "0", error));
  EXPECT_EQ(p.lr_check, 0.0);
  EXPECT_TRUE(setSgbmParam(p, "grey", "false", error));
  EXPECT_FALSE(p.grey);
  for (const auto& bad : std::vector<std::pair<std::string, std::string>>{
           {"num_disparities", "100"}, {"num_disparities", "0"}, {"block_size", "4"},
           {"block_size", "33"}, {"mode", "fast"}, {"grey", "yes"}, {"lr_check", "-1"},
           {"lr_check", "nan"}, {"uniqueness_ratio", "1x"}, {"no_such_key", "1"}}) {
    SgbmParams q;
    EXPECT_FALSE(setSgbmParam(q, bad.first, bad.second, error)) << bad.first << "=" << bad.second;
    EXPECT_NE(error.find(bad.first), std::string::npos) << error;
  }
  // the text form reads back
  SgbmParams back;
  std::istringstream text(sgbmParamsText(p));
  for (std::string kv; text >> kv;) {
    const size_t eq = kv.find('=');
    ASSERT_TRUE(setSgbmParam(back, kv.substr(0, eq), kv.substr(eq + 1), error)) << error;
  }
  EXPECT_EQ(sgbmParamsText(back), sgbmParamsText(p));
}

TEST(StereoCheck, AnalyticErrors) {
  // f B = 100: depth 10 m <-> disparity 10 px
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::Mat reference(2, 4, CV_16UC1, cv::Scalar(0));  // LiDAR depth, 1/256 m per unit
  cv::Mat estimate(2, 4, CV_32FC1, cv::Scalar(nan));
  reference.at<uint16_t>(0, 0) = 10 * 256;  // d 10: estimate d 12 (2 px): fine
  estimate.at<float>(0, 0) = 100.f / 12.f;
  reference.at<uint16_t>(0, 1) = 10 * 256;  // d 10: estimate d 14 (4 px, 40%): D1 outlier
  estimate.at<float>(0, 1) = 100.f / 14.f;
  reference.at<uint16_t>(0, 2) = 1 * 256;   // d 100: estimate d 96 (4 px, 4%): > 3 px, not D1
  estimate.at<float>(0, 2) = 100.f / 96.f;
  reference.at<uint16_t>(0, 3) = 50 * 256;  // d 2: no estimate
  estimate.at<float>(1, 0) = 3.f;           // estimate without reference
  StereoCheck c;
  ASSERT_TRUE(c.add(estimate, reference, 1.0 / 256.0, 100.0, cv::Rect(0, 0, 2, 1)));
  EXPECT_EQ(c.pixels(), 8);
  EXPECT_EQ(c.estimated(), 4);
  EXPECT_EQ(c.reference(), 4);
  EXPECT_EQ(c.matched(), 3);
  EXPECT_DOUBLE_EQ(c.density(), 0.5);
  EXPECT_DOUBLE_EQ(c.coverage(), 0.75);
  EXPECT_DOUBLE_EQ(c.outliers3px(), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(c.d1Matched(), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(c.d1All(), 2.0 / 4.0);
  // road region: the two pixels at 10 m (bin 0-10 m)
  EXPECT_EQ(c.roadPoints(), 2);
  EXPECT_EQ(c.roadPoints(0), 2);
  EXPECT_EQ(c.roadPoints(1), 0);
  const double e0 = 10.0 - 100.0 / 12.0, e1 = 10.0 - 100.0 / 14.0;
  EXPECT_NEAR(c.roadMeanError(), (e0 + e1) / 2, 1e-5);
  EXPECT_NEAR(c.roadBias(), -(e0 + e1) / 2, 1e-5);
  EXPECT_NEAR(c.roadRelativeError(0), (e0 + e1) / 20, 1e-6);
  EXPECT_TRUE(std::isnan(c.roadMeanError(2)));
  EXPECT_DOUBLE_EQ(c.roadCoverage(), 1.0);
  // float reference in metres gives the same, sizes and types are checked
  cv::Mat metres;
  reference.convertTo(metres, CV_32F, 1.0 / 256.0);
  StereoCheck m;
  ASSERT_TRUE(m.add(estimate, metres, 1.0, 100.0, cv::Rect(0, 0, 2, 1)));
  EXPECT_EQ(m.matched(), 3);  // 0 m = none
  EXPECT_DOUBLE_EQ(m.d1Matched(), c.d1Matched());
  EXPECT_FALSE(m.add(estimate, metres(cv::Rect(0, 0, 2, 2)), 1.0, 100.0, cv::Rect()));
  EXPECT_FALSE(m.add(reference, reference, 1.0, 100.0, cv::Rect()));
  EXPECT_FALSE(m.add(estimate, metres, 1.0, 0.0, cv::Rect()));
}

}  // namespace
}  // namespace tools
}  // namespace rgbd_lane_detector
