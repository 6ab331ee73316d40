// PCA template refinement: the angle of drawn lines within 1 degree.
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector/pca_refinement.h"

namespace rgbd_lane_detector {
namespace {

cv::Mat drawLine(double angle, int thickness, cv::Point centre = cv::Point(100, 100)) {
  cv::Mat R(200, 200, CV_32FC1, cv::Scalar(0));
  const cv::Point2d d(std::cos(angle), std::sin(angle));
  cv::line(R, cv::Point2d(centre) - 80 * d, cv::Point2d(centre) + 80 * d, cv::Scalar(1.0),
           thickness, cv::LINE_8);
  return R;
}

TEST(PcaRefinement, AngleOfDrawnLinesWithinOneDegree) {
  std::vector<cv::Point> stack;
  std::vector<uint8_t> visited;
  for (double deg : {20.0, 35.0, 45.0, 60.0, 75.0, 90.0, 105.0, 120.0, 135.0, 150.0, 165.0}) {
    const double a = deg * M_PI / 180.0;
    const cv::Mat R = drawLine(a, 5);
    const PcaAngle res = pcaMarkerAngle(R, cv::Point(100, 100), 0.75f, 32, stack, visited);
    ASSERT_TRUE(res.valid) << deg;
    EXPECT_NEAR(res.angle * 180.0 / M_PI, deg, 1.0) << "count " << res.count;
    EXPECT_GE(std::sin(res.angle), 0.0);  // points down the image
    EXPECT_GT(res.count, 32);
  }
}

TEST(PcaRefinement, RegionIsConnectedAndBoundedByTheBox) {
  std::vector<cv::Point> stack;
  std::vector<uint8_t> visited;
  cv::Mat R = drawLine(M_PI / 4, 3);
  // a separate strong blob in the box, not connected to the line
  R(cv::Rect(106, 86, 6, 6)).setTo(1.0);
  const PcaAngle res = pcaMarkerAngle(R, cv::Point(100, 100), 0.75f, 32, stack, visited);
  ASSERT_TRUE(res.valid);
  EXPECT_NEAR(res.angle, M_PI / 4, 1.0 * M_PI / 180.0);
  EXPECT_LE(res.count, 33 * 33);
}

TEST(PcaRefinement, BelowThresholdOrBlobIsInvalid) {
  std::vector<cv::Point> stack;
  std::vector<uint8_t> visited;
  cv::Mat R(50, 50, CV_32FC1, cv::Scalar(0.5));
  EXPECT_FALSE(pcaMarkerAngle(R, cv::Point(25, 25), 0.75f, 32, stack, visited).valid);
  cv::circle(R, cv::Point(25, 25), 8, cv::Scalar(1.0), -1);  // isotropic disc
  const PcaAngle disc = pcaMarkerAngle(R, cv::Point(25, 25), 0.75f, 32, stack, visited);
  EXPECT_TRUE(!disc.valid || disc.elongation < 1.2);
  EXPECT_FALSE(pcaMarkerAngle(R, cv::Point(-1, 3), 0.75f, 32, stack, visited).valid);
  EXPECT_FALSE(pcaMarkerAngle(cv::Mat(), cv::Point(0, 0), 0.75f, 32, stack, visited).valid);
}

}  // namespace
}  // namespace rgbd_lane_detector
