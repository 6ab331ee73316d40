// Candidate boundaries of a frame: lines traced from a response map, best seed first, the next
// seeds off the lines already traced, the map restored; unclassified lines taken as paint.
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector/boundary_candidates.h"
#include "synthetic_scene.h"

namespace rgbd_lane_detector {
namespace {

constexpr int kW = 320, kH = 190;
const Intrinsics kK{133.0, 133.0, 160.0, 95.0};

struct Fixture {
  cv::Mat points, empty_map, colour, grey;
  PlaneEstimate road;
  LaneFitter fitter;
  CandidateFrame f;
  Params params = Params::improved();
  BoundaryCandidateFinder finder;

  Fixture() {
    test::DepthScene scene;
    scene.image_width = kW;
    scene.image_height = kH;
    scene.K = kK;
    points = scene.render();
    road.valid = true;
    road.normal = scene.normal();
    road.distance = scene.height;
    colour = cv::Mat(kH, kW, CV_8UC3, cv::Scalar::all(90));
    grey = cv::Mat(kH, kW, CV_8UC1, cv::Scalar(90));
    f.colour = &colour;
    f.grey = &grey;
    f.grey_rows = cv::Range(0, kH);
    f.K = kK;
    f.input_size = f.proc_size = cv::Size(kW, kH);
    f.roi = cv::Rect(0, static_cast<int>(0.41 * kH), kW, kH - static_cast<int>(0.41 * kH));
    f.roi_rows = cv::Range(f.roi.y, kH);
    f.col_map = f.row_map = &empty_map;
    f.points = &points;
    f.road = &road;
    f.fitter = &fitter;
    f.template_angle = {3 * M_PI / 4, M_PI / 4};
    params.boundary_candidates = 2;
    params.classify_boundaries = false;
    finder.setParams(params);
  }
};

// A right-side response map with two lines ("\" direction): a stronger one and a weaker one.
cv::Mat twoLines() {
  cv::Mat R(kH, kW, CV_32FC1, cv::Scalar(0.f));
  cv::line(R, cv::Point(170, 90), cv::Point(235, 170), cv::Scalar(1.4), 8);
  cv::line(R, cv::Point(200, 90), cv::Point(288, 170), cv::Scalar(1.1), 8);
  return R;
}

TEST(BoundaryCandidateFinder, TracesTheBestLineFirstThenTheNext) {
  Fixture fx;
  cv::Mat R = twoLines();
  const cv::Mat before = R.clone();
  fx.finder.clear();
  fx.finder.traceLines(fx.f, 1, R);
  int n = 0;
  const BoundaryCandidate* c = fx.finder.candidates(1, n);
  ASSERT_EQ(n, 2);
  EXPECT_NEAR(c[0].trace.peak_score, 1.4f, 1e-4f);
  EXPECT_NEAR(c[1].trace.peak_score, 1.1f, 1e-4f);
  for (int k = 0; k < 2; ++k) {
    ASSERT_GE(c[k].trace.pixels.size(), 5u) << k;
    EXPECT_EQ(c[k].trace.pixels.size(), c[k].trace.points.size());
    for (const auto& p : c[k].trace.points) EXPECT_TRUE(p.allFinite());  // the road's depth
  }
  // the first line's pixels lie on the stronger line, the second's on the weaker one
  for (const auto& px : c[0].trace.pixels)
    EXPECT_NEAR(px.x, 170.0 + (px.y - 90.0) * 65.0 / 80.0, 6.0) << px;
  for (const auto& px : c[1].trace.pixels)
    EXPECT_NEAR(px.x, 200.0 + (px.y - 90.0) * 88.0 / 80.0, 6.0) << px;
  EXPECT_EQ(cv::countNonZero(R != before), 0);  // the published map is put back
  int none = 0;
  fx.finder.candidates(0, none);
  EXPECT_EQ(none, 0);
}

TEST(BoundaryCandidateFinder, UnclassifiedLinesArePaint) {
  Fixture fx;
  cv::Mat R = twoLines();
  fx.finder.clear();
  fx.finder.traceLines(fx.f, 1, R);
  fx.finder.classify(fx.f);  // classify_boundaries off: the paper's view
  int n = 0;
  const BoundaryCandidate* c = fx.finder.candidates(1, n);
  ASSERT_EQ(n, 2);
  for (int k = 0; k < n; ++k) {
    EXPECT_TRUE(c[k].evidence.boundary);
    EXPECT_EQ(c[k].evidence.kind, BoundaryKind::kPaint);
  }
  fx.finder.clear();
  fx.finder.candidates(1, n);
  EXPECT_EQ(n, 0);
}

TEST(BoundaryCandidateFinder, NothingAboveTheTraceThreshold) {
  Fixture fx;
  cv::Mat R(kH, kW, CV_32FC1, cv::Scalar(0.5f));
  fx.finder.clear();
  fx.finder.traceLines(fx.f, 0, R);
  int n = 0;
  const BoundaryCandidate* c = fx.finder.candidates(0, n);
  ASSERT_LE(n, 1);  // at most the best seed, untraced (the paper reports its score)
  if (n == 1) {
    EXPECT_TRUE(c[0].trace.pixels.empty());
  }
}

}  // namespace
}  // namespace rgbd_lane_detector
