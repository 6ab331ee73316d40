// Bad input: a documented error status or an invalid result, never a crash or NaN output.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/lane_detector.h"
#include "synthetic_scene.h"

namespace rgbd_lane_detector {
namespace {

Frame goodFrame(cv::Mat& bgr, cv::Mat& depth) {
  test::RoadScene scene;
  scene.render(bgr, depth);
  Frame f;
  f.colour = bgr;
  f.depth = depth;
  f.intrinsics = scene.K;
  return f;
}

void expectFiniteOutputs(const Result& r) {
  for (const cv::Mat* m : {&r.response_left, &r.response_right, &r.geometric}) {
    ASSERT_FALSE(m->empty());
    EXPECT_TRUE(cv::checkRange(*m));  // no NaN / inf
  }
  EXPECT_TRUE(r.plane.normal.allFinite());
  EXPECT_TRUE(std::isfinite(r.plane.distance));
  for (const MarkerTrace* m : {&r.left, &r.right})
    for (const auto& p : m->pixels) EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y));
}

TEST(BadInput, StatusForEveryMalformedFrame) {
  cv::Mat bgr, depth;
  const Frame good = goodFrame(bgr, depth);
  LaneDetector det;
  Result r;

  Frame f = good;
  f.colour = cv::Mat();
  EXPECT_EQ(det.detect(f, r), Status::kEmptyImage);
  f = good;
  f.depth = cv::Mat();
  EXPECT_EQ(det.detect(f, r), Status::kEmptyImage);

  f = good;
  f.depth = depth(cv::Rect(0, 0, 320, 190));
  EXPECT_EQ(det.detect(f, r), Status::kSizeMismatch);

  f = good;
  f.format = PixelFormat::kMono8;  // 3-channel data announced as mono
  EXPECT_EQ(det.detect(f, r), Status::kUnsupportedColour);
  f = good;
  cv::Mat c16(bgr.size(), CV_16UC3, cv::Scalar(1, 1, 1));
  f.colour = c16;
  EXPECT_EQ(det.detect(f, r), Status::kUnsupportedColour);

  f = good;
  cv::Mat d8(bgr.size(), CV_8UC1, cv::Scalar(1));
  f.depth = d8;
  EXPECT_EQ(det.detect(f, r), Status::kUnsupportedDepth);
  f = good;
  cv::Mat d64(bgr.size(), CV_64FC1, cv::Scalar(1));
  f.depth = d64;
  EXPECT_EQ(det.detect(f, r), Status::kUnsupportedDepth);
  f = good;
  f.depth_scale = 0.0;
  EXPECT_EQ(det.detect(f, r), Status::kUnsupportedDepth);

  f = good;
  f.intrinsics = Intrinsics();
  EXPECT_EQ(det.detect(f, r), Status::kInvalidIntrinsics);
  f.intrinsics = Intrinsics{std::numeric_limits<double>::quiet_NaN(), 1, 1, 1};
  EXPECT_EQ(det.detect(f, r), Status::kInvalidIntrinsics);
  f.intrinsics = Intrinsics{-500, 500, 320, 190};
  EXPECT_EQ(det.detect(f, r), Status::kInvalidIntrinsics);

  // the detector is still usable afterwards
  EXPECT_EQ(det.detect(good, r), Status::kOk);
  EXPECT_TRUE(r.plane.valid);
  for (Status s : {Status::kEmptyImage, Status::kSizeMismatch, Status::kUnsupportedColour,
                   Status::kUnsupportedDepth, Status::kInvalidIntrinsics, Status::kImageTooSmall})
    EXPECT_GT(std::string(statusMessage(s)).size(), 10u);
}

TEST(BadInput, TinyImagesAndTemplatesLargerThanTheRegion) {
  LaneDetector det;
  Result r;
  for (cv::Size s : {cv::Size(1, 1), cv::Size(2, 3), cv::Size(31, 200), cv::Size(200, 40)}) {
    cv::Mat c(s, CV_8UC3, cv::Scalar(255, 255, 255)), d(s, CV_16UC1, cv::Scalar(1000));
    Frame f;
    f.colour = c;
    f.depth = d;
    f.intrinsics = Intrinsics{100, 100, s.width / 2.0, s.height / 2.0};
    EXPECT_EQ(det.detect(f, r), Status::kImageTooSmall) << s;
  }
  Params p;
  p.template_size = 256;  // larger than the 224-row region of a 640x380 frame
  det.setParams(p);
  cv::Mat bgr, depth;
  EXPECT_EQ(det.detect(goodFrame(bgr, depth), r), Status::kImageTooSmall);
}

TEST(BadInput, InvalidOrExtremeDepthGivesNoNaN) {
  cv::Mat bgr, depth;
  Frame f = goodFrame(bgr, depth);
  LaneDetector det;
  Result r;
  // all-invalid 16-bit depth
  cv::Mat zeros(depth.size(), CV_16UC1, cv::Scalar(0));
  f.depth = zeros;
  ASSERT_EQ(det.detect(f, r), Status::kOk);
  expectFiniteOutputs(r);
  EXPECT_FALSE(r.plane.valid);
  // float depth full of NaN, inf, negatives and huge values
  cv::Mat weird(depth.size(), CV_32FC1);
  const float specials[] = {std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::infinity(), -3.f, 1e30f, 0.f, 1e-30f};
  for (int i = 0; i < static_cast<int>(weird.total()); ++i)
    weird.at<float>(i) = specials[i % 6];
  f.depth = weird;
  ASSERT_EQ(det.detect(f, r), Status::kOk);
  expectFiniteOutputs(r);
  EXPECT_FALSE(r.plane.valid);
  // saturated 16-bit depth (65.535 m everywhere): a flat wall, not a road
  cv::Mat far(depth.size(), CV_16UC1, cv::Scalar(65535));
  f.depth = far;
  ASSERT_EQ(det.detect(f, r), Status::kOk);
  expectFiniteOutputs(r);
}

TEST(BadInput, NonContinuousImagesAreReadThroughTheirStep) {
  cv::Mat bgr, depth;
  const Frame good = goodFrame(bgr, depth);
  cv::Mat big_c(bgr.rows + 10, bgr.cols + 20, CV_8UC3, cv::Scalar(0, 0, 255));
  cv::Mat big_d(bgr.rows + 10, bgr.cols + 20, CV_16UC1, cv::Scalar(0));
  const cv::Rect inner(7, 3, bgr.cols, bgr.rows);
  bgr.copyTo(big_c(inner));
  depth.copyTo(big_d(inner));
  Frame f = good;
  f.colour = big_c(inner);
  f.depth = big_d(inner);
  ASSERT_FALSE(f.colour.isContinuous());
  LaneDetector a, b;
  Result ra, rb;
  ASSERT_EQ(a.detect(good, ra), Status::kOk);
  ASSERT_EQ(b.detect(f, rb), Status::kOk);
  EXPECT_EQ(cv::norm(ra.response_left, rb.response_left, cv::NORM_INF), 0.0);
  ASSERT_TRUE(ra.plane.valid && rb.plane.valid);
  EXPECT_NEAR(ra.plane.distance, rb.plane.distance, 1e-9);
}

}  // namespace
}  // namespace rgbd_lane_detector
