// Sliding-box tracing: solid and dashed markers end to end, stops at borders and empty boxes.
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector/sliding_box.h"

namespace rgbd_lane_detector {
namespace {

const cv::Point2f kNear(60, 360), kFar(260, 160);  // a "/" marker: near end bottom-left
const double kAngle = 3 * M_PI / 4;                 // pointing down the image (toward kNear)

double distToLine(const cv::Point2f& p) {
  const cv::Point2f d = (kFar - kNear) / cv::norm(kFar - kNear);
  const cv::Point2f q = p - kNear;
  return std::fabs(q.x * d.y - q.y * d.x);
}

cv::Mat solidMarker() {
  cv::Mat R(400, 400, CV_32FC1, cv::Scalar(0.1));
  cv::line(R, kNear, kFar, cv::Scalar(1.2), 7);
  return R;
}

TEST(SlidingBox, TracesASolidMarkerEndToEndNearToFar) {
  const cv::Mat R = solidMarker();
  TraceParams tp;
  std::vector<cv::Point2f> pts;
  std::vector<float> scores;
  traceMarker(R, cv::Point2f(160, 260), kAngle, tp, cv::Rect(0, 0, 400, 400), pts, scores);
  ASSERT_GT(pts.size(), 40u);  // 283 px of marker at 5 px steps
  ASSERT_EQ(pts.size(), scores.size());
  EXPECT_GT(pts.front().y, kNear.y - 20);  // reaches the near end
  EXPECT_LT(pts.back().y, kFar.y + 20);    // and the far end
  for (size_t i = 0; i < pts.size(); ++i) {
    EXPECT_LT(distToLine(pts[i]), 1.5) << i;
    EXPECT_GT(scores[i], 0.75f);
    if (i > 0) {
      EXPECT_LT(pts[i].y, pts[i - 1].y);  // ordered near (bottom) to far (top)
    }
  }
}

TEST(SlidingBox, StopsAtTheBorder) {
  cv::Mat R(200, 200, CV_32FC1, cv::Scalar(0));
  cv::line(R, cv::Point(-50, 250), cv::Point(250, -50), cv::Scalar(1.0), 7);  // crosses the image
  TraceParams tp;
  tp.max_steps = 1000000;  // only the border may stop it
  std::vector<cv::Point2f> pts;
  std::vector<float> scores;
  const cv::Rect bounds(0, 40, 200, 160);
  traceMarker(R, cv::Point2f(100, 100), kAngle, tp, bounds, pts, scores);
  ASSERT_GT(pts.size(), 10u);
  for (const auto& p : pts) EXPECT_TRUE(bounds.contains(cv::Point(p)));
  EXPECT_GT(pts.front().y, 180);  // ran to the bottom border
  EXPECT_LT(pts.back().y, 60);    // and to the top of the bounds
}

TEST(SlidingBox, DashedMarkerStopsAtAGapUnlessGapsAreAllowed) {
  cv::Mat R(400, 400, CV_32FC1, cv::Scalar(0));
  const cv::Point2f d = (kFar - kNear) / cv::norm(kFar - kNear);
  for (float s = 0; s < 283; s += 120)  // 40 px dashes, 80 px gaps
    cv::line(R, kNear + s * d, kNear + (s + 40) * d, cv::Scalar(1.0), 7);
  TraceParams tp;
  std::vector<cv::Point2f> pts;
  std::vector<float> scores;
  const cv::Point2f seed = kNear + 140.f * d;  // on the second dash
  traceMarker(R, seed, kAngle, tp, cv::Rect(0, 0, 400, 400), pts, scores);
  ASSERT_FALSE(pts.empty());
  const float span_paper = pts.front().y - pts.back().y;
  EXPECT_LT(span_paper, 40 * std::fabs(d.y) + 10);  // one dash only

  tp.gap_steps = 12;
  traceMarker(R, seed, kAngle, tp, cv::Rect(0, 0, 400, 400), pts, scores);
  const float span_gaps = pts.front().y - pts.back().y;
  EXPECT_GT(span_gaps, 230 * std::fabs(d.y));  // all three dashes
  for (const auto& p : pts) EXPECT_LT(distToLine(p), 1.5);
}

TEST(SlidingBox, EmptySeedBoxGivesNothing) {
  cv::Mat R(100, 100, CV_32FC1, cv::Scalar(0.2));
  TraceParams tp;
  std::vector<cv::Point2f> pts(3);
  std::vector<float> scores(3);
  traceMarker(R, cv::Point2f(50, 50), kAngle, tp, cv::Rect(0, 0, 100, 100), pts, scores);
  EXPECT_TRUE(pts.empty());
  EXPECT_TRUE(scores.empty());
  traceMarker(R, cv::Point2f(500, 50), kAngle, tp, cv::Rect(0, 0, 100, 100), pts, scores);
  EXPECT_TRUE(pts.empty());
}

}  // namespace
}  // namespace rgbd_lane_detector
