// Boundary classification on rendered cross-sections of a road: paint, a rail head, a zebra
// stripe, a kerb, a shadow's edge, a grass edge, a rail beside paint, an object above the road.
#include <cmath>
#include <functional>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/boundary_classifier.h"
#include "rgbd_lane_detector/half_binary.h"

namespace rgbd_lane_detector {
namespace {

constexpr int kW = 640, kH = 380;
const Intrinsics kK{266.37, 266.37, 320.0, 190.0};
constexpr double kHeight = 1.5;

// A level road seen from kHeight, camera looking along the road (no pitch), with boxes running
// along the road (kerbs, sidewalks, a truck's top): the surface's colour (RGB) depends on the
// lateral position x (right) and the distance z.
struct Box {
  double x0, x1, height;  ///< lateral extent (m) and height above the road
};

struct CrossSection {
  std::function<cv::Vec3b(double x, double z)> colour = [](double, double) {
    return cv::Vec3b(90, 90, 90);
  };
  std::vector<Box> boxes;

  // the nearest surface along a pixel's ray (z = 1 units): road, box tops and box sides
  double hit(double rx, double ry) const {
    double best = ry > 1e-6 ? kHeight / ry : INFINITY;
    for (const Box& b : boxes) {
      const double top = kHeight - b.height;  // y of the top below the camera
      if (ry > 1e-6) {
        const double z = top / ry;
        if (rx * z >= b.x0 && rx * z <= b.x1) best = std::min(best, z);
      }
      for (double x : {b.x0, b.x1}) {
        if (std::fabs(rx) < 1e-9 || !std::isfinite(x)) continue;
        const double z = x / rx;
        if (z > 0 && ry * z >= top && ry * z <= kHeight) best = std::min(best, z);
      }
    }
    return best;
  }

  void render(cv::Mat& bgr, cv::Mat& points) const {
    bgr.create(kH, kW, CV_8UC3);
    bgr.setTo(cv::Scalar(200, 180, 160));  // sky
    points.create(kH, kW, CV_32FC3);
    points.setTo(cv::Scalar::all(std::nanf("")));
    for (int v = 0; v < kH; ++v) {
      for (int u = 0; u < kW; ++u) {
        const double rx = (u - kK.cx) / kK.fx, ry = (v - kK.cy) / kK.fy;
        const double z = hit(rx, ry);
        if (!(z <= 80.0)) continue;
        const cv::Vec3b rgb = colour(rx * z, z);
        bgr.at<cv::Vec3b>(v, u) = cv::Vec3b(rgb[2], rgb[1], rgb[0]);
        points.at<cv::Vec3f>(v, u) =
            cv::Vec3f(static_cast<float>(rx * z), static_cast<float>(ry * z), static_cast<float>(z));
      }
    }
  }
};

PlaneEstimate level() {
  PlaneEstimate p;
  p.valid = true;
  p.normal = Eigen::Vector3d(0, -1, 0);
  p.distance = kHeight;
  return p;
}

// Pixels of a line at lateral x on the road (height h), 4-25 m ahead, near to far.
std::vector<cv::Point2f> linePixels(double x, double h = 0.0) {
  std::vector<cv::Point2f> px;
  for (double z = 4.0; z <= 25.0; z *= 1.08)
    px.emplace_back(static_cast<float>(kK.fx * x / z + kK.cx),
                    static_cast<float>(kK.fy * (kHeight - h) / z + kK.cy));
  return px;
}

cv::Vec3b grey(int g) { return cv::Vec3b(g, g, g); }

struct Fixture {
  cv::Mat bgr, grey, points;
  PlaneEstimate plane = level();
  ClassifierInput in;
  BoundaryClassifier classifier;
  BoundaryEvidence ev;

  void classify(const CrossSection& cs, std::vector<cv::Point2f> px, bool left,
                const Params& p = Params::improved()) {
    cs.render(bgr, points);
    halfBinary(bgr, PixelFormat::kBgr8, 0, cv::Range(0, bgr.rows), grey);  // threshold 0: grey
    in.colour = &bgr;
    in.format = PixelFormat::kBgr8;
    in.grey = &grey;
    in.grey_rows = cv::Range(0, bgr.rows);
    in.K = kK;
    in.points = &points;
    in.plane = &plane;
    in.frame = RoadFrame::fromPlane(plane);
    pixels = std::move(px);
    classifier.classify(in, pixels, left, p, ev);
  }
  // measurePaint() along the same line (after classify() rendered the scene)
  void measure(bool left, float& coverage, float& yellowness) {
    classifier.measurePaint(in, pixels, left, Params::improved(), coverage, yellowness);
  }
  std::vector<cv::Point2f> pixels;
};

TEST(BoundaryClassifier, PaintIsABrightBandOfPaintWidth) {
  CrossSection cs;
  cs.colour = [](double x, double) { return std::fabs(x + 1.8) < 0.075 ? grey(220) : grey(80); };
  Fixture f;
  f.classify(cs, linePixels(-1.8), true);
  EXPECT_TRUE(f.ev.boundary) << f.ev.reason;
  EXPECT_EQ(f.ev.kind, BoundaryKind::kPaint);
  EXPECT_NEAR(f.ev.width, 0.15, 0.04);
  EXPECT_NEAR(f.ev.line_height, 0.0, 0.01);
  EXPECT_GT(f.ev.margin, 0.5f);
}

TEST(BoundaryClassifier, RailHeadIsARoadEdge) {
  // a 5 cm shiny head with the dark groove beside it, flush with the road
  CrossSection cs;
  cs.colour = [](double x, double) {
    if (std::fabs(x + 1.8) < 0.025) return grey(235);
    if (x > -1.775 && x < -1.735) return grey(25);
    return grey(80);
  };
  Fixture f;
  f.classify(cs, linePixels(-1.8), true);
  EXPECT_TRUE(f.ev.boundary) << f.ev.reason;
  EXPECT_EQ(f.ev.kind, BoundaryKind::kRoadEdge) << f.ev.reason;
  EXPECT_LT(f.ev.width, Params::improved().paint_width_min);
}

TEST(BoundaryClassifier, ZebraStripeIsNoBoundary) {
  CrossSection cs;
  cs.colour = [](double x, double) { return std::fabs(x + 1.5) < 0.25 ? grey(220) : grey(80); };
  Fixture f;
  f.classify(cs, linePixels(-1.5), true);
  EXPECT_FALSE(f.ev.boundary) << f.ev.reason;
  EXPECT_GT(f.ev.width, Params::improved().paint_width_max);
}

TEST(BoundaryClassifier, KerbIsARoadEdge) {
  // a 0.12 m kerb at x = 1.8 with a light face and a sidewalk beyond it
  CrossSection cs;
  cs.boxes = {{1.8, INFINITY, 0.12}};
  cs.colour = [](double x, double) {
    if (x > 1.8 && x < 1.95) return grey(200);  // kerb stones
    return x > 1.8 ? grey(150) : grey(80);
  };
  Fixture f;
  f.classify(cs, linePixels(1.87, 0.12), false);
  EXPECT_TRUE(f.ev.boundary) << f.ev.reason;
  EXPECT_EQ(f.ev.kind, BoundaryKind::kRoadEdge) << f.ev.reason;
  EXPECT_NEAR(f.ev.outer_height - f.ev.inner_height, 0.12, 0.03);
}

TEST(BoundaryClassifier, ShadowEdgeIsNoBoundary) {
  // sunlit asphalt right of x = 0.8, the shade left of it darker and bluer (sky-lit)
  CrossSection cs;
  cs.colour = [](double x, double) {
    return x < 0.8 ? cv::Vec3b(45, 50, 62) : cv::Vec3b(150, 145, 135);
  };
  Fixture f;
  f.classify(cs, linePixels(0.8), false);
  EXPECT_FALSE(f.ev.boundary) << f.ev.reason;
}

TEST(BoundaryClassifier, GrassEdgeIsARoadEdge) {
  CrossSection cs;
  // grass as bright as the asphalt: only the colour changes
  cs.colour = [](double x, double) {
    return x > 1.9 ? cv::Vec3b(70, 120, 45) : grey(95);
  };
  Fixture f;
  f.classify(cs, linePixels(1.9), false);
  EXPECT_TRUE(f.ev.boundary) << f.ev.reason;
  EXPECT_EQ(f.ev.kind, BoundaryKind::kRoadEdge);
  EXPECT_GT(f.ev.chroma_step, Params::improved().edge_chroma);
}

TEST(BoundaryClassifier, PaintBesideARailMovesTheLineOntoThePaint) {
  // a rail head at x = -1.6 (the brightest thing, traced) and a 12 cm painted line 12 cm to its
  // right, on the vehicle's side
  CrossSection cs;
  cs.colour = [](double x, double) {
    if (std::fabs(x + 1.6) < 0.025) return grey(250);
    if (x > -1.66 && x < -1.625) return grey(25);  // the groove
    if (std::fabs(x + 1.48) < 0.06) return grey(190);
    return grey(70);
  };
  Fixture f;
  f.classify(cs, linePixels(-1.6), true);
  EXPECT_TRUE(f.ev.boundary) << f.ev.reason;
  EXPECT_EQ(f.ev.kind, BoundaryKind::kPaint) << f.ev.reason;
  EXPECT_NEAR(f.ev.shift, 0.12, 0.03);
  // every measured pixel now lies on the paint's centre line
  const std::vector<cv::Point2f> paint = linePixels(-1.48);
  for (size_t i = 0; i < f.pixels.size(); ++i) {
    const double px_per_m = kK.fx * (f.pixels[i].y - kK.cy) / (kK.fy * kHeight);
    EXPECT_NEAR((f.pixels[i].x - paint[i].x) / px_per_m, 0.0, 0.03) << i;
  }
}

TEST(BoundaryClassifier, LineAboveTheRoadIsNoBoundary) {
  // a white stripe on the top of a 1 m high box (a truck's side seen from above)
  CrossSection cs;
  cs.boxes = {{-3.1, -1.9, 1.0}};
  cs.colour = [](double x, double) { return std::fabs(x + 2.5) < 0.07 ? grey(230) : grey(90); };
  Fixture f;
  f.classify(cs, linePixels(-2.5, 1.0), true);
  EXPECT_FALSE(f.ev.boundary) << f.ev.reason;
  EXPECT_GT(f.ev.line_height, 0.9f);
}

// A solid white line on the left, a yellow one on the right (solid, or 3 m dashes every 12 m).
CrossSection whiteAndYellow(bool dashed) {
  CrossSection cs;
  cs.colour = [dashed](double x, double z) {
    if (std::fabs(x + 1.8) < 0.075) return grey(220);
    if (std::fabs(x - 1.8) < 0.075 && (!dashed || std::fmod(z, 12.0) < 3.0))
      return cv::Vec3b(204, 158, 36);
    return grey(90);
  };
  return cs;
}

TEST(BoundaryClassifier, MeasurePaintTellsWhiteFromYellow) {
  Fixture f;
  float coverage = 0.f, yellowness = 0.f;
  f.classify(whiteAndYellow(false), linePixels(-1.8), true);
  f.measure(true, coverage, yellowness);
  EXPECT_GE(yellowness, 0.0f);
  EXPECT_LT(yellowness, 0.1f) << "white paint on grey asphalt";
  f.classify(whiteAndYellow(false), linePixels(1.8), false);
  f.measure(false, coverage, yellowness);
  // 1 - B'/((R' + G') / 2) of (204, 158, 36) against grey 90: 1 - 0.4 / 2.0 = 0.8
  EXPECT_NEAR(yellowness, 0.8f, 0.1f) << "yellow paint";
}

TEST(BoundaryClassifier, MeasurePaintTellsSolidFromDashed) {
  Fixture f;
  float coverage = 0.f, yellowness = 0.f;
  f.classify(whiteAndYellow(true), linePixels(-1.8), true);
  f.measure(true, coverage, yellowness);
  EXPECT_GT(coverage, 0.9f) << "solid";
  f.classify(whiteAndYellow(true), linePixels(1.8), false);
  f.measure(false, coverage, yellowness);
  EXPECT_NEAR(coverage, 0.25f, 0.1f) << "3 m of paint every 12 m";
}

TEST(BoundaryClassifier, NothingWithoutAPlane) {
  CrossSection cs;
  Fixture f;
  f.plane.valid = false;
  f.classify(cs, linePixels(-1.8), true);
  EXPECT_FALSE(f.ev.boundary);
}

// Lateral position (m, right) on the level road of an input pixel.
double roadLateral(const cv::Point2f& c) {
  const double z = kK.fy * kHeight / (c.y - kK.cy);
  return (c.x - kK.cx) / kK.fx * z;
}
double roadForward(const cv::Point2f& c) { return kK.fy * kHeight / (c.y - kK.cy); }

TEST(BoundaryClassifier, FollowLineCentresOnThePaintAndCrossesDashGaps) {
  // dashes of 4 m every 12 m at x = -1.7; the "trace" covers the dash 12-16 m ahead, 6 cm off
  // the paint's centre
  CrossSection cs;
  cs.colour = [](double x, double z) {
    const bool dash = std::fmod(z, 12.0) < 4.0;
    return dash && std::fabs(x + 1.7) < 0.075 ? grey(220) : grey(80);
  };
  Fixture f;
  f.classify(cs, linePixels(-1.7), true);  // renders the scene, sets the frame views
  std::vector<cv::Point2f> px;
  for (double z = 12.0; z <= 16.0; z += 0.25)
    px.emplace_back(static_cast<float>(kK.fx * -1.64 / z + kK.cx),
                    static_cast<float>(kK.fy * kHeight / z + kK.cy));
  std::vector<Eigen::Vector3f> pts;
  const int rows = f.classifier.followLine(f.in, px, pts, Params::improved(), 10.0, 60.0);
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

TEST(BoundaryClassifier, ADoubleLineIsOneBoundaryAtItsCentre) {
  // two 0.12 m yellow lines 0.13 m apart centred at x = -1.8 (centres at -1.925 and -1.675)
  CrossSection cs;
  cs.colour = [](double x, double) {
    return std::fabs(x + 1.925) < 0.06 || std::fabs(x + 1.675) < 0.06 ? cv::Vec3b(204, 158, 36)
                                                                        : grey(90);
  };
  Fixture f;
  f.classify(cs, linePixels(-1.675), true);  // traced on the inner line
  std::vector<cv::Point2f> px = linePixels(-1.675);
  std::vector<Eigen::Vector3f> pts(px.size());
  ASSERT_TRUE(f.classifier.centreDoubleLine(f.in, px, pts, Params::improved()));
  for (const auto& c : px) EXPECT_NEAR(roadLateral(c), -1.8, 0.03) << c;
  EXPECT_TRUE(pts.front().allFinite());
  // a single line stays where it is
  CrossSection single;
  single.colour = [](double x, double) { return std::fabs(x + 1.8) < 0.075 ? grey(220) : grey(90); };
  Fixture g;
  g.classify(single, linePixels(-1.8), true);
  std::vector<cv::Point2f> one = linePixels(-1.8);
  EXPECT_FALSE(g.classifier.centreDoubleLine(g.in, one, pts, Params::improved()));
  for (const auto& c : one) EXPECT_NEAR(roadLateral(c), -1.8, 1e-3) << c;
}

TEST(BoundaryClassifier, FollowEdgeFindsWhereTheRoadEnds) {
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
  Fixture f;
  f.classify(cs, linePixels(1.9, 0.12), false);
  ASSERT_TRUE(f.ev.boundary);
  ASSERT_EQ(f.ev.kind, BoundaryKind::kRoadEdge);
  std::vector<cv::Point2f> px;
  for (double z = 8.0; z <= 12.0; z += 0.25)
    px.emplace_back(static_cast<float>(kK.fx * 1.9 / z + kK.cx),
                    static_cast<float>(kK.fy * (kHeight - 0.12) / z + kK.cy));
  std::vector<Eigen::Vector3f> pts;
  const int rows = f.classifier.followEdge(f.in, px, pts, false, Params::improved(), 2.0, 60.0);
  ASSERT_GE(rows, 10);
  double nearest = 1e9, farthest = 0.0;
  for (const auto& c : px) {
    EXPECT_NEAR(roadLateral(c), 1.8, 0.06) << c;  // the bottom of the kerb's face
    nearest = std::min(nearest, roadForward(c));
    farthest = std::max(farthest, roadForward(c));
  }
  EXPECT_LT(nearest, 6.0);   // followed toward the car
  EXPECT_GT(farthest, 14.0);  // and beyond the trace
}

}  // namespace
}  // namespace rgbd_lane_detector
