// NCC matching: equal to cv::matchTemplate(TM_CCOEFF_NORMED) within 1e-4.
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector/half_binary.h"
#include "rgbd_lane_detector/response_map.h"
#include "rgbd_lane_detector/template_matching.h"
#include "simd.h"
#include "synthetic_scene.h"

namespace rgbd_lane_detector {
namespace {

double maxDiff(const cv::Mat& a, const cv::Mat& b) { return cv::norm(a, b, cv::NORM_INF); }

void expectMatchesReference(const cv::Mat& image, const cv::Rect& region, double left_angle,
                            double right_angle, int size = 32, int width = 10) {
  LineTemplate l, r;
  makeLineTemplate(size, width, left_angle, l);
  makeLineTemplate(size, width, right_angle, r);
  NccMatcher matcher;
  cv::Mat ml, mr, rl, rr;
  ASSERT_TRUE(matcher.match(image, region, l, r, ml, mr));
  matchTemplateReference(image, region, l, rl);
  matchTemplateReference(image, region, r, rr);
  EXPECT_LT(maxDiff(ml, rl), 1e-4) << "left angle " << left_angle;
  EXPECT_LT(maxDiff(mr, rr), 1e-4) << "right angle " << right_angle;
  double lo, hi;
  cv::minMaxLoc(ml, &lo, &hi);
  EXPECT_GE(lo, 0.0);
  EXPECT_LE(hi, 1.0);
}

TEST(LineTemplate, OneRunPerRowMatchesTheImage) {
  for (double a : {0.3, M_PI / 4, 1.2, M_PI / 2, 2.0, 3 * M_PI / 4, 2.8}) {
    LineTemplate t;
    makeLineTemplate(32, 10, a, t);
    ASSERT_EQ(t.image.size(), cv::Size(32, 32));
    int count = 0;
    for (int r = 0; r < 32; ++r)
      for (int c = 0; c < 32; ++c) {
        const bool on = c >= t.run_begin[r] && c < t.run_end[r];
        EXPECT_EQ(t.image.at<uint8_t>(r, c), on ? 255 : 0);
        count += on;
      }
    EXPECT_EQ(count, t.count);
    EXPECT_EQ(cv::countNonZero(t.image), t.count);
  }
  // the default right template "\" runs from the top-left to the bottom-right corner
  LineTemplate right;
  makeLineTemplate(32, 10, M_PI / 4, right);
  EXPECT_EQ(right.image.at<uint8_t>(0, 0), 255);
  EXPECT_EQ(right.image.at<uint8_t>(31, 31), 255);
  EXPECT_EQ(right.image.at<uint8_t>(0, 31), 0);
  LineTemplate left;
  makeLineTemplate(32, 10, 3 * M_PI / 4, left);
  EXPECT_EQ(left.image.at<uint8_t>(31, 0), 255);
  EXPECT_EQ(left.image.at<uint8_t>(0, 31), 255);
  EXPECT_EQ(left.image.at<uint8_t>(0, 0), 0);
}

TEST(NccMatcher, EqualsMatchTemplateOnRandomImages) {
  cv::RNG rng(42);
  cv::Mat img(120, 160, CV_8UC1);
  rng.fill(img, cv::RNG::UNIFORM, 0, 256);
  expectMatchesReference(img, cv::Rect(0, 0, 160, 120), 3 * M_PI / 4, M_PI / 4);
  expectMatchesReference(img, cv::Rect(5, 40, 150, 70), 2.1, 0.9);
  expectMatchesReference(img, cv::Rect(0, 0, 160, 120), 2.5, 0.5, 17, 3);
}

TEST(NccMatcher, EqualsMatchTemplateOnARoad) {
  test::RoadScene scene;
  scene.right_dashed = true;
  cv::Mat bgr, depth, hb;
  scene.render(bgr, depth);
  halfBinary(bgr, PixelFormat::kBgr8, 100, cv::Range(0, bgr.rows), hb);
  const cv::Rect roi(0, 156, 640, 224);
  expectMatchesReference(hb, roi, 3 * M_PI / 4, M_PI / 4);
  expectMatchesReference(hb, roi, 2.4, 0.65);
  // the road markers give the highest scores: half-binary leaves only paint above tau_c
  LineTemplate l, r;
  makeLineTemplate(32, 10, 3 * M_PI / 4, l);
  makeLineTemplate(32, 10, M_PI / 4, r);
  NccMatcher m;
  cv::Mat ml, mr;
  ASSERT_TRUE(m.match(hb, roi, l, r, ml, mr));
  double hi;
  cv::Point at;
  cv::minMaxLoc(ml, nullptr, &hi, nullptr, &at);
  EXPECT_GT(hi, 0.5);
  EXPECT_LT(at.x, 320);  // the left marker is left of the centre
  cv::minMaxLoc(mr, nullptr, &hi, nullptr, &at);
  EXPECT_GT(hi, 0.5);
  EXPECT_GT(at.x, 320);
}

TEST(NccMatcher, FlatWindowsScoreZeroAndOutsideRegionIsZero) {
  cv::Mat img(64, 64, CV_8UC1, cv::Scalar(0));
  img(cv::Rect(0, 0, 64, 20)).setTo(180);  // flat bright band
  LineTemplate l, r;
  makeLineTemplate(16, 4, 3 * M_PI / 4, l);
  makeLineTemplate(16, 4, M_PI / 4, r);
  NccMatcher m;
  cv::Mat ml, mr, ref;
  ASSERT_TRUE(m.match(img, cv::Rect(0, 0, 64, 64), l, r, ml, mr));
  EXPECT_EQ(ml.at<float>(8, 30), 0.f);   // window inside the flat band
  EXPECT_EQ(ml.at<float>(50, 30), 0.f);  // window of zeros
  matchTemplateReference(img, cv::Rect(0, 0, 64, 64), l, ref);
  EXPECT_LT(maxDiff(ml, ref), 1e-4);
  EXPECT_EQ(ml.at<float>(0, 0), 0.f);    // border: no full window
}

TEST(NccMatcher, RegionSmallerThanTemplateFailsCleanly) {
  cv::Mat img(20, 20, CV_8UC1, cv::Scalar(100));
  LineTemplate l, r;
  makeLineTemplate(32, 10, 3 * M_PI / 4, l);
  makeLineTemplate(32, 10, M_PI / 4, r);
  NccMatcher m;
  cv::Mat ml, mr;
  EXPECT_FALSE(m.match(img, cv::Rect(0, 0, 20, 20), l, r, ml, mr));
  ASSERT_EQ(ml.size(), img.size());
  EXPECT_EQ(cv::countNonZero(ml), 0);
  EXPECT_FALSE(m.match(img, cv::Rect(-50, -50, 10, 10), l, r, ml, mr));
}

// The matcher sums a template along its slope p/q: check the rasterisation keeps that period,
// stays near the requested angle, and that the matcher equals matchTemplate for every slope
// denominator, size parity and row width (vector bodies and scalar tails).
TEST(LineTemplate, SlopeIsPeriodicAndCloseToTheRequestedAngle) {
  for (int deg = 10; deg <= 170; ++deg) {
    const double a = deg * M_PI / 180.0;
    LineTemplate t;
    makeLineTemplate(32, 10, a, t);
    ASSERT_GE(t.slope_q, 1);
    ASSERT_LE(t.slope_q, kMaxSlopeDenominator);
    const double from_h = std::min(deg, 180 - deg);
    if (from_h <= 80) {
      EXPECT_LT(std::fabs(t.drawn_angle - a), 2.0 * M_PI / 180.0) << deg;
    }
    for (int r = 0; r + t.slope_q < 32; ++r) {
      const int b0 = t.run_begin[r], b1 = t.run_begin[r + t.slope_q];
      if (b0 > 0 && b0 < 32 && b1 > 0 && b1 < 32) {
        EXPECT_EQ(b1, b0 + t.slope_p) << deg;
      }
    }
  }
}

TEST(NccMatcher, EqualsMatchTemplateForEverySlope) {
  cv::RNG rng(7);
  cv::Mat img(150, 211, CV_8UC1);
  rng.fill(img, cv::RNG::UNIFORM, 0, 256);
  // sparse image (half-binary like): mostly zeros, flat and empty windows
  cv::Mat sparse = img.clone();
  sparse.setTo(0, img < 200);
  for (int q = 1; q <= kMaxSlopeDenominator; ++q) {
    for (int p : {-2 * q - 1, -q, -1, 1, q + 1, 3 * q}) {
      const double angle = std::atan2(static_cast<double>(q), static_cast<double>(p));
      for (int size : {17, 32}) {
        SCOPED_TRACE(testing::Message() << "slope " << p << "/" << q << " size " << size);
        expectMatchesReference(img, cv::Rect(3, 11, 203, 130), angle, M_PI - angle, size,
                               size / 3);
        expectMatchesReference(sparse, cv::Rect(0, 0, 211, 150), angle, angle, size, 5);
      }
    }
  }
}


// A window's sum of squares passes 2^31 on bright images from 182-pixel templates on (the
// largest, 256, reaches 65536 * 255^2): every target must read it unsigned and score as
// matchTemplate does, not call the window flat.
TEST(NccMatcher, LargeTemplatesOnBrightImagesEqualMatchTemplateOnEveryTarget) {
  const int size = 200;
  cv::RNG rng(11);
  cv::Mat img(300, 330, CV_8UC1);
  rng.fill(img, cv::RNG::UNIFORM, 228, 241);  // bright asphalt in sunlight: 228..240
  LineTemplate l, r;
  makeLineTemplate(size, 40, 3 * M_PI / 4, l);
  makeLineTemplate(size, 40, M_PI / 4, r);
  // the left template's line drawn through (160, 140), brighter than the road around it
  cv::Mat line(img.size(), CV_8UC1, cv::Scalar(0));
  const cv::Point2d dir(std::cos(l.drawn_angle), std::sin(l.drawn_angle));  // v down
  cv::line(line, cv::Point2d(160, 140) - 300 * dir, cv::Point2d(160, 140) + 300 * dir,
           cv::Scalar(255), 40);
  cv::max(img, line, img);
  const cv::Rect all(0, 0, img.cols, img.rows);
  cv::Mat ref;
  matchTemplateReference(img, all, l, ref);
  double hi;
  cv::Point at;
  cv::minMaxLoc(ref, nullptr, &hi, nullptr, &at);
  ASSERT_GT(hi, 0.85);  // the scene is what it says: the line matches well, on the line
  const cv::Point2d off = cv::Point2d(at) - cv::Point2d(160, 140);
  EXPECT_LT(std::fabs(off.x * dir.y - off.y * dir.x), 3.0) << at;  // distance to the line
  for (const simd::Target target : simd::availableTargets()) {
    SCOPED_TRACE(simd::targetName(target));
    simd::forceTarget(target);
    expectMatchesReference(img, all, 3 * M_PI / 4, M_PI / 4, size, 40);
  }
  simd::forceTarget(simd::kBest);
}
// Sparse images (a half-binary road: zeros but for a few lines and specks): windows without a
// pixel are not accumulated, and their correlations left from a dense image matched before
// change nothing: the same bits as a fresh matcher on every target, and matchTemplate's scores.
TEST(NccMatcher, SparseImagesAfterADenseOneEqualAFreshMatcher) {
  cv::RNG rng(21);
  cv::Mat dense(120, 203, CV_8UC1), sparse(120, 203, CV_8UC1, cv::Scalar(0));
  rng.fill(dense, cv::RNG::UNIFORM, 0, 256);
  cv::line(sparse, cv::Point(20, 119), cv::Point(90, 30), cv::Scalar(220), 6);
  for (int i = 0; i < 25; ++i)
    sparse.at<uint8_t>(rng.uniform(0, 120), rng.uniform(0, 203)) =
        static_cast<uint8_t>(rng.uniform(1, 256));
  LineTemplate l, r;
  makeLineTemplate(32, 10, 3 * M_PI / 4 + 0.1, l);  // slope q > 1: stair lookups
  makeLineTemplate(32, 10, M_PI / 4, r);
  const cv::Rect region(3, 10, 197, 105);
  for (simd::Target target : simd::availableTargets()) {
    simd::forceTarget(target);
    SCOPED_TRACE(simd::targetName(target));
    NccMatcher used, fresh;
    cv::Mat ul, ur, fl, fr, rl, rr;
    ASSERT_TRUE(used.match(dense, region, l, r, ul, ur));
    ASSERT_TRUE(used.match(sparse, region, l, r, ul, ur));
    ASSERT_TRUE(fresh.match(sparse, region, l, r, fl, fr));
    EXPECT_EQ(std::memcmp(ul.data, fl.data, ul.total() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(ur.data, fr.data, ur.total() * sizeof(float)), 0);
    matchTemplateReference(sparse, region, l, rl);
    matchTemplateReference(sparse, region, r, rr);
    EXPECT_LT(maxDiff(fl, rl), 1e-4);
    EXPECT_LT(maxDiff(fr, rr), 1e-4);
    EXPECT_GT(cv::countNonZero(fl > 0.5f), 0);  // the line is found
  }
  simd::forceTarget(simd::kBest);
}

// The detector matches its two templates and, while a side acquires, both acquisition templates
// in one pass: every map the same bits as its template matched alone (on every target), and
// matchTemplate's scores; a pass of four and passes of two on one matcher in turn change nothing,
// nor does a pass of three (the kernels are compiled per count of templates and tables).
TEST(NccMatcher, OnePassOfFourTemplatesEqualsEachTemplateAlone) {
  cv::RNG rng(5);
  cv::Mat img(140, 230, CV_8UC1, cv::Scalar(0));  // a half-binary road: lines, specks, a patch
  cv::line(img, cv::Point(30, 139), cv::Point(100, 20), cv::Scalar(210), 7);
  cv::line(img, cv::Point(200, 139), cv::Point(150, 10), cv::Scalar(180), 5);
  for (int i = 0; i < 40; ++i)
    img.at<uint8_t>(rng.uniform(0, 140), rng.uniform(0, 230)) =
        static_cast<uint8_t>(rng.uniform(1, 256));
  cv::Mat patch = img(cv::Rect(120, 60, 50, 40));
  rng.fill(patch, cv::RNG::UNIFORM, 0, 256);
  LineTemplate t[4];
  makeLineTemplate(32, 10, 3 * M_PI / 4 + 0.12, t[0]);  // an adapted left side: slope q > 1
  makeLineTemplate(32, 10, M_PI / 4, t[1]);
  makeLineTemplate(32, 10, defaultLeftAngle(70.0), t[2]);  // acquisition templates
  makeLineTemplate(32, 10, defaultRightAngle(70.0), t[3]);
  LineTemplate same;  // a fourth template of the right template's slope: one shared table
  makeLineTemplate(32, 6, M_PI / 4, same);
  ASSERT_GT(t[0].slope_q, 1);
  ASSERT_NE(t[2].slope_q, t[1].slope_q);
  const cv::Rect region(2, 5, 225, 130);
  for (simd::Target target : simd::availableTargets()) {
    simd::forceTarget(target);
    SCOPED_TRACE(simd::targetName(target));
    const LineTemplate* fourths[2] = {&t[3], &same};
    for (const LineTemplate* fourth : fourths) {
      const LineTemplate* all[4] = {&t[0], &t[1], &t[2], fourth};
      NccMatcher both;  // passes of two, four, two, four as the detector while sides acquire
      cv::Mat m[4];
      cv::Mat* maps[4] = {&m[0], &m[1], &m[2], &m[3]};
      ASSERT_TRUE(both.match(img, region, all, maps, 2));
      ASSERT_TRUE(both.match(img, region, all, maps, 4));
      ASSERT_TRUE(both.match(img, region, all, maps, 2));
      ASSERT_TRUE(both.match(img, region, all, maps, 4));
      cv::Mat m3[3];  // and a pass of three (one side acquiring), on another matcher
      cv::Mat* maps3[3] = {&m3[0], &m3[1], &m3[2]};
      NccMatcher three;
      ASSERT_TRUE(three.match(img, region, all, maps3, 3));
      for (int k = 0; k < 4; ++k) {
        NccMatcher alone;
        cv::Mat a, ref;
        cv::Mat* one[1] = {&a};
        ASSERT_TRUE(alone.match(img, region, &all[k], one, 1));
        EXPECT_EQ(std::memcmp(m[k].data, a.data, a.total() * sizeof(float)), 0) << k;
        if (k < 3) EXPECT_EQ(std::memcmp(m3[k].data, a.data, a.total() * sizeof(float)), 0) << k;
        matchTemplateReference(img, region, *all[k], ref);
        EXPECT_LT(maxDiff(m[k], ref), 1e-4) << k;
        EXPECT_GT(cv::countNonZero(m[k] > 0.3f), 0) << k;  // something matches each template
      }
    }
  }
  simd::forceTarget(simd::kBest);
}

// The mark of a pass is fusionMask() of its maps at the level over the region's rows, on every
// target, for two and four templates; the other rows are not written, and without a mask to
// trust (the reference path, a level of 0) none is marked.
TEST(NccMatcher, MarkIsTheFusionMaskOfTheMaps) {
  cv::RNG rng(7);
  cv::Mat img(140, 230, CV_8UC1, cv::Scalar(0));
  cv::line(img, cv::Point(30, 139), cv::Point(100, 20), cv::Scalar(210), 7);
  cv::line(img, cv::Point(200, 139), cv::Point(150, 10), cv::Scalar(180), 5);
  for (int i = 0; i < 60; ++i)
    img.at<uint8_t>(rng.uniform(0, 140), rng.uniform(0, 230)) =
        static_cast<uint8_t>(rng.uniform(1, 256));
  LineTemplate t[4];
  makeLineTemplate(32, 10, 3 * M_PI / 4 + 0.12, t[0]);
  makeLineTemplate(32, 10, M_PI / 4, t[1]);
  makeLineTemplate(32, 10, defaultLeftAngle(70.0), t[2]);
  makeLineTemplate(32, 10, defaultRightAngle(70.0), t[3]);
  const LineTemplate* all[4] = {&t[0], &t[1], &t[2], &t[3]};
  const cv::Rect region(0, 5, 230, 130);  // the detector's: whole rows
  const cv::Range rows(region.y, region.br().y);
  for (simd::Target target : simd::availableTargets()) {
    simd::forceTarget(target);
    for (int count : {2, 4}) {
      for (float level : {0.2f, 0.3f}) {
        SCOPED_TRACE(testing::Message() << simd::targetName(target) << ", " << count
                                        << " templates, level " << level);
        NccMatcher matcher;
        cv::Mat m[4], mask(img.size(), CV_8UC1, cv::Scalar(77)), expected;
        cv::Mat* maps[4] = {&m[0], &m[1], &m[2], &m[3]};
        NccMatcher::Mark mark;
        mark.level = level;
        mark.mask = &mask;
        ASSERT_TRUE(matcher.match(img, region, all, maps, count, &mark));
        EXPECT_TRUE(mark.marked);
        if (count == 2)
          fusionMask({&m[0], &m[1]}, level, rows, expected);
        else
          fusionMask({&m[0], &m[1], &m[2], &m[3]}, level, rows, expected);
        EXPECT_GT(cv::countNonZero(expected(cv::Rect(0, rows.start, img.cols, rows.size()))), 0);
        for (int y = 0; y < img.rows; ++y) {
          const bool inside = y >= rows.start && y < rows.end;
          for (int x = 0; x < img.cols; ++x)
            ASSERT_EQ(mask.at<uint8_t>(y, x), inside ? expected.at<uint8_t>(y, x) : 77)
                << "at " << x << ", " << y;
        }
      }
    }
  }
  simd::forceTarget(simd::kBest);
  NccMatcher matcher;
  cv::Mat m[2], mask;
  cv::Mat* maps[2] = {&m[0], &m[1]};
  NccMatcher::Mark mark;
  mark.mask = &mask;
  mark.level = 0.f;
  matcher.match(img, region, all, maps, 2, &mark);
  EXPECT_FALSE(mark.marked);
  mark.level = 0.5f;
  setReferenceStages(true);
  matcher.match(img, region, all, maps, 2, &mark);
  setReferenceStages(false);
  EXPECT_FALSE(mark.marked);
}

}  // namespace
}  // namespace rgbd_lane_detector
