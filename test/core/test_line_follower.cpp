// Following lines row by row on rendered cross-sections of a road: paint across dash gaps onto its
// centre, a double line onto the centre between its lines, a kerb onto the bottom of its face.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/line_follower.h"
#include "road_cross_section.h"

namespace rgbd_lane_detector {
namespace {

using namespace test;  // NOLINT: the rendered road

struct Road : RenderedRoad {
  LineFollower follower;
};

// A trace along the road line @p lateral m beside the camera (+ right), @p height below it, from
// @p z0 to @p z1 m ahead every 0.25 m: its pixels, near to far.
std::vector<cv::Point2f> traceAlong(double lateral, double z0, double z1,
                                   double height = kHeight) {
  std::vector<cv::Point2f> px;
  for (double z = z0; z <= z1; z += 0.25)
    px.emplace_back(static_cast<float>(kK.fx * lateral / z + kK.cx),
                    static_cast<float>(kK.fy * height / z + kK.cy));
  return px;
}

TEST(LineFollower, FollowLineCentresOnThePaintAndCrossesDashGaps) {
  // dashes of 4 m every 12 m at x = -1.7; the "trace" covers the dash 12-16 m ahead, 6 cm off
  // the paint's centre
  CrossSection cs;
  cs.colour = [](double x, double z) {
    const bool dash = std::fmod(z, 12.0) < 4.0;
    return dash && std::fabs(x + 1.7) < 0.075 ? grey(220) : grey(80);
  };
  Road f;
  f.render(cs);
  std::vector<cv::Point2f> px = traceAlong(-1.64, 12.0, 16.0);
  std::vector<Eigen::Vector3f> pts;
  const int rows = f.follower.followLine(f.in, px, pts, Params::improved(), 10.0, 60.0);
  ASSERT_GE(rows, 10);
  ASSERT_EQ(px.size(), pts.size());
  double nearest = 1e9, farthest = 0.0;
  for (const auto& c : px) {
    // on the paint's centre, not the trace (within 3 cm, or 0.6 px far away)
    EXPECT_NEAR(roadLateral(c), -1.7, std::max(0.03, 0.6 * roadForward(c) / kK.fx)) << c;
    nearest = std::min(nearest, roadForward(c));
    farthest = std::max(farthest, roadForward(c));
  }
  EXPECT_LT(nearest, 4.0);    // across the 8 m gap down to the dash at 0-4 m
  EXPECT_GT(farthest, 24.0);  // and up to the dash at 24-28 m
  for (size_t i = 1; i < px.size(); ++i) EXPECT_LT(px[i].y, px[i - 1].y);  // near to far
}

TEST(LineFollower, ASeamsBrightRimDoesNotSteerTheLine) {
  // a 15 cm dash at x = -1.7 6-10 m ahead (traced from 6.5 m) and the next one 2-3 m ahead; in
  // the gap a dark seam beside the line, its 1 cm bright rim (narrower than any paint's core)
  // leaving the line toward the lane (from 8 cm inside it at 5.5 m to 25 cm at 3 m): followed
  // toward the car, the painted line keeps its paint's heading across the gap and reaches the
  // near dash (the rim's rows do not steer it). Paint at least 12 cm wide (a motorway's): on the
  // rendered road's coarse pixels its core's width is resolved across the gap.
  auto rim = [](double z) { return -1.62 + 0.17 * (5.5 - z) / 2.5; };
  CrossSection cs;
  cs.colour = [rim](double x, double z) {
    const bool dash = (z >= 6.0 && z <= 10.0) || z <= 3.0;
    if (dash && std::fabs(x + 1.7) < 0.075) return grey(220);
    if (z > 3.0 && z < 5.5 && x > rim(z) - 0.005 && x <= rim(z) + 0.005) return grey(220);
    if (z > 3.0 && z < 5.5 && x > rim(z) + 0.005 && x < rim(z) + 0.05) return grey(30);
    return grey(80);
  };
  Road f;
  f.render(cs);
  std::vector<cv::Point2f> px = traceAlong(-1.7, 6.5, 10.0);
  Params p = Params::improved();
  p.paint_width_min = 0.12;
  std::vector<Eigen::Vector3f> pts;
  const int rows = f.follower.followLine(f.in, px, pts, p, 10.0, 60.0, LineFollower::kTraceReach,
                                         true);  // a painted line
  ASSERT_GE(rows, 10);
  int near_dash = 0;
  for (const auto& c : px) {
    const double z = roadForward(c);
    if (z > 3.0 && z < 5.5) continue;  // the gap: a rim row found there does not steer the line
    // on the dashes: on the paint's centre (within 3 cm, or 0.6 px far away)
    EXPECT_NEAR(roadLateral(c), -1.7, std::max(0.03, 0.6 * z / kK.fx)) << c;
    near_dash += z <= 3.0;
  }
  EXPECT_GE(near_dash, 3);  // across the seam to the near dash
}

TEST(LineFollower, BelowASeedGrainsFoundOneAtATimeDoNotTurnTheLine) {
  // a worn 15 cm dash at x = -1.7 9.5-12 m ahead, seeded at 10 m (the seed's line: straight
  // ahead 9-11 m), and a dash 3-5 m ahead on the same line; between them, toward the car, 5 cm
  // grains on every other image row along a streak leaving the line (0.1 m per m: a patch's
  // texture beside the dash's worn end). Rows found one at a time between rows that find nothing
  // do not turn the seed's line: it runs on straight across the gap and onto the near dash
  // (fitted through the first grains found, the line ran off along the streak).
  auto streak = [](double z) { return -1.7 + 0.1 * (9.4 - z); };
  CrossSection cs;
  cs.colour = [streak](double x, double z) {
    const bool dash = (z >= 9.5 && z <= 12.0) || (z >= 3.0 && z <= 5.0);
    if (dash && std::fabs(x + 1.7) < 0.075) return grey(220);
    const long row = std::lround(kK.fy * kHeight / z + kK.cy);
    if (z > 6.0 && z < 9.4 && row % 2 == 0 && std::fabs(x - streak(z)) < 0.025) return grey(220);
    return grey(80);
  };
  Road f;
  f.render(cs);
  std::vector<cv::Point2f> px = traceAlong(-1.7, 9.0, 11.0);
  std::vector<Eigen::Vector3f> pts;
  // (the rendered road's pixels are coarse, 3-4 cm here: grains are told from paint where a
  // third of paint_width_min spans two pixels)
  Params p = Params::improved();
  p.paint_width_min = 0.25;
  const int rows = f.follower.followLine(f.in, px, pts, p, 13.0, 60.0, 0.3, false,
                                         true);  // a seed's line
  ASSERT_GE(rows, 10);
  int near_dash = 0;
  for (const auto& c : px) {
    const double z = roadForward(c);
    if (z > 5.5) continue;  // (the gap's grains near the line may be found; they do not steer)
    // on the near dash's centre (within 3 cm)
    EXPECT_NEAR(roadLateral(c), -1.7, 0.03) << c;
    near_dash += z <= 5.0;
  }
  EXPECT_GE(near_dash, 5);  // across the gap to the near dash
}

TEST(LineFollower, ADoubleLineIsOneBoundaryAtItsCentre) {
  // two 0.12 m yellow lines 0.13 m apart centred at x = -1.8 (centres at -1.925 and -1.675)
  CrossSection cs;
  cs.colour = [](double x, double) {
    return std::fabs(x + 1.925) < 0.06 || std::fabs(x + 1.675) < 0.06 ? cv::Vec3b(204, 158, 36)
                                                                      : grey(90);
  };
  Road f;
  f.render(cs);  // traced on the inner line
  std::vector<cv::Point2f> px = linePixels(-1.675);
  std::vector<Eigen::Vector3f> pts(px.size());
  ASSERT_TRUE(f.follower.centreDoubleLine(f.in, px, pts, Params::improved()));
  for (const auto& c : px) EXPECT_NEAR(roadLateral(c), -1.8, 0.03) << c;
  EXPECT_TRUE(pts.front().allFinite());
  // a single line stays where it is
  CrossSection single;
  single.colour = [](double x, double) {
    return std::fabs(x + 1.8) < 0.075 ? grey(220) : grey(90);
  };
  Road g;
  g.render(single);
  std::vector<cv::Point2f> one = linePixels(-1.8);
  EXPECT_FALSE(g.follower.centreDoubleLine(g.in, one, pts, Params::improved()));
  for (const auto& c : one) EXPECT_NEAR(roadLateral(c), -1.8, 1e-3) << c;
}

TEST(LineFollower, FollowEdgeFindsWhereTheRoadEnds) {
  // a kerb at x = 1.8 whose top (light stones) was traced 10 cm beyond the edge, 8-12 m ahead;
  // leaves scattered in the gutter 0.3 m inside it are no edge
  CrossSection cs;
  cs.boxes = {{1.8, INFINITY, 0.12}};
  cs.colour = [](double x, double z) {
    if (x > 1.8 - 1e-6 && x < 1.95) return grey(200);  // its face and top
    if (x > 1.8) return grey(150);
    if (x > 1.45 && x < 1.5 && std::fmod(z, 1.0) < 0.2) return cv::Vec3b(160, 90, 30);  // leaf
    return grey(80);
  };
  Road f;
  f.render(cs);
  std::vector<cv::Point2f> px = traceAlong(1.9, 8.0, 12.0, kHeight - 0.12);
  std::vector<Eigen::Vector3f> pts;
  const int rows = f.follower.followEdge(f.in, px, pts, false, Params::improved(), 2.0, 60.0);
  ASSERT_GE(rows, 10);
  double nearest = 1e9, farthest = 0.0;
  for (const auto& c : px) {
    EXPECT_NEAR(roadLateral(c), 1.8, 0.06) << c;  // the bottom of the kerb's face
    nearest = std::min(nearest, roadForward(c));
    farthest = std::max(farthest, roadForward(c));
  }
  EXPECT_LT(nearest, 6.0);    // followed toward the car
  EXPECT_GT(farthest, 14.0);  // and beyond the trace
}

}  // namespace
}  // namespace rgbd_lane_detector
