// Boundary classification on rendered cross-sections of a road: paint, a rail head, a thin line
// running into a dash, a zebra stripe, a kerb, a shadow's edge, a grass edge, a rail beside
// paint, an object above the road; the paint's coverage and colour (also where the sun clips it,
// and on a worn line).
// (Following lines row by row: test_line_follower.)
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/boundary_classifier.h"
#include "road_cross_section.h"

namespace rgbd_lane_detector {
namespace {

using namespace test;  // NOLINT: the rendered road

struct Fixture : RenderedRoad {
  BoundaryClassifier classifier;
  BoundaryEvidence ev;

  void classify(const CrossSection& cs, std::vector<cv::Point2f> px, bool left,
                const Params& p = Params::improved()) {
    render(cs);
    pixels = std::move(px);
    classifier.classify(in, pixels, left, p, ev);
  }
  // measurePaint() along the same line (after classify() rendered the scene)
  void measure(bool left, float& coverage, float& yellowness) {
    classifier.measurePaint(in, pixels, left, Params::improved(), coverage, yellowness);
  }
  // measurePaint()'s coverage of the line x = @p x (m) of the rendered road @p cs
  float coverageOf(const CrossSection& cs, double x) {
    float coverage = 0.f, yellowness = 0.f;
    classify(cs, linePixels(x), x < 0.0);
    measure(x < 0.0, coverage, yellowness);
    return coverage;
  }
  std::vector<cv::Point2f> pixels;
};

// One point per image row of the road line x = @p x (m, + right), from @p z_near to @p z_far m
// ahead, near to far (as a followed line has).
std::vector<cv::Point2f> rowPoints(double x, double z_near, double z_far) {
  std::vector<cv::Point2f> px;
  const double v_far = kK.fy * kHeight / z_far + kK.cy;
  for (double v = std::floor(kK.fy * kHeight / z_near + kK.cy); v >= v_far; v -= 1.0) {
    const double z = kK.fy * kHeight / (v - kK.cy);
    px.emplace_back(static_cast<float>(kK.fx * x / z + kK.cx), static_cast<float>(v));
  }
  return px;
}

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

// A 5 cm shiny rail head 1.8 m left of the camera with the dark groove beside it, flush with
// the road.
CrossSection railHead() {
  CrossSection cs;
  cs.colour = [](double x, double) {
    if (std::fabs(x + 1.8) < 0.025) return grey(235);
    if (x > -1.775 && x < -1.735) return grey(25);
    return grey(80);
  };
  return cs;
}

TEST(BoundaryClassifier, RailHeadIsARoadEdge) {
  const CrossSection cs = railHead();
  Fixture f;
  f.classify(cs, linePixels(-1.8), true);
  EXPECT_TRUE(f.ev.boundary) << f.ev.reason;
  EXPECT_EQ(f.ev.kind, BoundaryKind::kRoadEdge) << f.ev.reason;
  EXPECT_LT(f.ev.width, Params::improved().paint_width_min);
}

TEST(BoundaryClassifier, NarrowBandThatNoDepthPutsOnTheRoadIsNoBoundary) {
  // the rail head's look without a measured point on it (a vehicle's trim, a glint on its body):
  // no road edge; still typed one, with its narrow rows, for the worn-paint check
  const CrossSection cs = railHead();
  Fixture f;
  f.render(cs);
  f.points.setTo(cv::Scalar::all(std::nanf("")));
  f.pixels = linePixels(-1.8);
  f.classifier.classify(f.in, f.pixels, true, Params::improved(), f.ev);
  EXPECT_FALSE(f.ev.boundary) << f.ev.reason;
  EXPECT_EQ(f.ev.kind, BoundaryKind::kRoadEdge) << f.ev.reason;
  EXPECT_GE(f.ev.narrow_rows, f.ev.rows / 2);
}

// A thin bright line (4 cm: a rail head's width, a worn dash's core, a seam's glint) 1.8 m left,
// classified from 3 to 10 m ahead, one point per image row (as a followed line has), at paint
// width (15 cm) from @p paint_from to @p paint_to m ahead.
BoundaryEvidence thinLineWithPaint(double paint_from, double paint_to) {
  CrossSection cs;
  cs.colour = [paint_from, paint_to](double x, double z) {
    const double half = z >= paint_from && z <= paint_to ? 0.075 : 0.02;
    return std::fabs(x + 1.8) < half ? grey(235) : grey(80);
  };
  Fixture f;
  f.classify(cs, rowPoints(-1.8, 3.0, 10.0), true);
  return f.ev;
}

TEST(BoundaryClassifier, ThinLineRunningIntoADashIsPaint) {
  // the thin line from 3 to 5 m, then the next dash of the same line at paint width from 5 to
  // 10 m: a rail head never widens to a dash
  const BoundaryEvidence ev = thinLineWithPaint(5.0, 10.0);
  EXPECT_TRUE(ev.boundary) << ev.reason;
  EXPECT_EQ(ev.kind, BoundaryKind::kPaint) << ev.reason;
  EXPECT_GT(ev.narrow_rows, ev.paint_rows) << "mostly the thin line";
}

TEST(BoundaryClassifier, WornDashOfOneAndAHalfMetresMakesAThinLinePaint) {
  // the thin core at paint width from 5 to 6.5 m only: a rail head never widens to paint over a
  // metre or more (the shortest lane-line dash), a worn dash keeps its paint width over part of
  // its length
  const BoundaryEvidence ev = thinLineWithPaint(5.0, 6.5);
  EXPECT_TRUE(ev.boundary) << ev.reason;
  EXPECT_EQ(ev.kind, BoundaryKind::kPaint) << ev.reason;
  EXPECT_GT(ev.narrow_rows, 2 * ev.paint_rows) << "mostly the thin core";
}

TEST(BoundaryClassifier, AVehicleBeyondAStrokeIsNoArrowHead) {
  // a 2.5 m stroke of paint at x = -1.8 (4-6.5 m ahead) and beyond it a bright shape 0.8 m wide
  // that narrows to a tip (7-8.5 m): on the road, a lane arrow's head; where the depth measures
  // it 0.7 m above the road, a white vehicle's bumper and its corner, and no head
  auto half = [](double z) { return z >= 7.0 && z <= 8.5 ? 0.4 * (8.5 - z) / 1.5 : 0.0; };
  CrossSection cs;
  cs.colour = [half](double x, double z) {
    if (z >= 4.0 && z <= 6.5 && std::fabs(x + 1.8) < 0.075) return grey(230);
    return std::fabs(x + 1.8) < half(z) ? grey(230) : grey(80);
  };
  Fixture f;
  f.render(cs);
  const std::vector<cv::Point2f> px = rowPoints(-1.8, 4.0, 6.5);
  const Params p = Params::improved();
  EXPECT_TRUE(f.classifier.arrowHead(f.in, px, p)) << "on the road: an arrow's head";
  // the shape's points 0.7 m above the road (camera y down: the road at y = kHeight)
  for (int v = 0; v < kH; ++v)
    for (int u = 0; u < kW; ++u) {
      cv::Vec3f& q = f.points.at<cv::Vec3f>(v, u);
      if (std::isfinite(q[2]) && std::fabs(q[0] + 1.8) < half(q[2])) q[1] -= 0.7f;
    }
  EXPECT_FALSE(f.classifier.arrowHead(f.in, px, p)) << "a vehicle beyond the stroke";
}

TEST(BoundaryClassifier, ALineRunningOnBeyondABrightPatchIsNoArrowHead) {
  // a 15 cm stroke at x = -1.8 (4-6.5 m ahead), beyond it a bright patch 0.8 m wide (7-7.6 m:
  // 4 rows wider than paint_width_max, a patch of sunlight) and the line running on at 15 cm
  // from 7.6 to 10 m: the patch narrows to paint width (below half its width) like a head to its
  // tip, but the narrow run keeps its width for more than kArrowTip (1.5 m): a line, no head.
  // Ending at 8.5 m instead (0.9 m of narrow run, then road), the same shape is a head.
  for (const double end : {10.0, 8.5}) {
    CrossSection cs;
    cs.colour = [end](double x, double z) {
      const double off = std::fabs(x + 1.8);
      const bool stroke = off < 0.075 && ((z >= 4.0 && z <= 6.5) || (z >= 7.6 && z <= end));
      const bool patch = off < 0.4 && z >= 7.0 && z < 7.6;
      return stroke || patch ? grey(230) : grey(80);
    };
    Fixture f;
    f.render(cs);
    const std::vector<cv::Point2f> px = rowPoints(-1.8, 4.0, 6.5);
    EXPECT_EQ(f.classifier.arrowHead(f.in, px, Params::improved()), end < 9.0)
        << "line to " << end << " m";
  }
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

// (x, z) on the road is paint of a 15 cm line at x = @p centre: solid, or 3 m dashes every 12 m.
bool onLine(double x, double z, double centre, bool dashed) {
  return std::fabs(x - centre) < 0.075 && (!dashed || std::fmod(z, 12.0) < 3.0);
}

// A solid white line on the left, a yellow one on the right (solid, or dashed).
CrossSection whiteAndYellow(bool dashed) {
  CrossSection cs;
  cs.colour = [dashed](double x, double z) {
    if (onLine(x, z, -1.8, false)) return grey(220);
    return onLine(x, z, 1.8, dashed) ? cv::Vec3b(204, 158, 36) : grey(90);
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

// In the sun up to 7 m ahead (a bright road, paint that clips) and in shadow beyond: a white
// line on the left clips in every channel, a yellow one on the right in red and green only.
CrossSection sunlitWhiteAndYellow() {
  CrossSection cs;
  cs.colour = [](double x, double z) {
    const bool sun = z < 7.0;
    if (std::fabs(x + 1.8) < 0.075) return sun ? grey(255) : grey(200);
    if (std::fabs(x - 1.8) < 0.075) return sun ? cv::Vec3b(255, 255, 190) : cv::Vec3b(150, 120, 60);
    return sun ? cv::Vec3b(185, 178, 170) : grey(90);
  };
  return cs;
}

TEST(BoundaryClassifier, MeasurePaintTellsYellowWhoseRedAndGreenClip) {
  Fixture f;
  float coverage = 0.f, yellowness = 0.f;
  f.classify(sunlitWhiteAndYellow(), linePixels(1.8), false);
  f.measure(false, coverage, yellowness);
  // in the sun the clipped colour reads 1 - (190/170) / ((255/185 + 255/178) / 2) = 0.20 (white
  // below yellow_threshold 0.25) on most of the rows whose band is resolved (4-7 m); in the
  // shadow 1 - (60/90) / 1.5 = 0.56
  EXPECT_NEAR(yellowness, 0.56f, 0.1f) << "yellow paint, red and green clipped in the sun";
  f.classify(sunlitWhiteAndYellow(), linePixels(-1.8), true);
  f.measure(true, coverage, yellowness);
  EXPECT_GE(yellowness, 0.0f) << "white paint clipped in every channel still has a colour";
  EXPECT_LT(yellowness, 0.1f) << "white paint";
}

TEST(BoundaryClassifier, MeasurePaintTakesTheColourOfPaintWornNarrow) {
  // a yellow line worn to 5 cm (narrower than paint_width_min on every row): no row has a band
  // of paint width, the colour is the worn rows'
  CrossSection cs;
  cs.colour = [](double x, double) {
    return std::fabs(x - 1.8) < 0.025 ? cv::Vec3b(204, 158, 36) : grey(90);
  };
  Fixture f;
  float coverage = 0.f, yellowness = 0.f;
  f.classify(cs, linePixels(1.8), false);
  f.measure(false, coverage, yellowness);
  EXPECT_NEAR(yellowness, 0.8f, 0.1f) << "worn yellow paint (-1: no colour)";
  // at night (a road of 12 grey levels) the ratios of a worn core's few pixels are noise (one
  // level of the road's blue moves 1 - B'/((R' + G') / 2) by 0.08): no colour rather than a guess
  cs.colour = [](double x, double) {
    return std::fabs(x - 1.8) < 0.025 ? cv::Vec3b(18, 18, 18) : cv::Vec3b(12, 12, 12);
  };
  f.classify(cs, linePixels(1.8), false);
  f.measure(false, coverage, yellowness);
  EXPECT_EQ(yellowness, -1.0f) << "a worn line on a dark road";
}

TEST(BoundaryClassifier, MeasurePaintTellsSolidFromDashed) {
  Fixture f;
  EXPECT_GT(f.coverageOf(whiteAndYellow(true), -1.8), 0.9f) << "solid";
  EXPECT_NEAR(f.coverageOf(whiteAndYellow(true), 1.8), 0.25f, 0.1f) << "3 m of paint every 12 m";
}

// A white line 1.8 m left (solid, or 3 m dashes every 12 m) under dappled shade: bands of shade
// 2 m long every 4 m, crossing the line obliquely (their edges run 2 m along the road per metre
// across it), so that on most rows one side of the line is sunlit and the other shaded. The
// paint is 1.5x its road in the sun and in the shade, and in the shade darker than the sunlit
// road.
CrossSection lineUnderDappledShade(bool dashed) {
  CrossSection cs;
  cs.colour = [dashed](double x, double z) {
    const bool shade = std::fmod(z + 2.0 * x + 100.0, 4.0) < 2.0;
    const bool paint = onLine(x, z, -1.8, dashed);
    return shade ? grey(paint ? 75 : 50) : grey(paint ? 225 : 150);
  };
  return cs;
}

TEST(BoundaryClassifier, MeasurePaintTellsSolidFromDashedUnderDappledShade) {
  // a row with no paint between a sunlit and a shaded side is no gap: the shaded paint stands
  // above its own side, not above the sunlit one that sets the contrast
  Fixture f;
  EXPECT_GT(f.coverageOf(lineUnderDappledShade(false), -1.8), Params::improved().dashed_coverage)
      << "solid";
  const float dashed = f.coverageOf(lineUnderDappledShade(true), -1.8);
  EXPECT_GE(dashed, 0.0f) << "enough road measured";
  EXPECT_LT(dashed, 0.5f) << "3 m of paint every 12 m";
}

TEST(BoundaryClassifier, NothingWithoutAPlane) {
  CrossSection cs;
  Fixture f;
  f.plane.valid = false;
  f.classify(cs, linePixels(-1.8), true);
  EXPECT_FALSE(f.ev.boundary);
}

// A line on the road running up to a vehicle's body 12 m ahead (1 m above the road), seen by a
// sparse LiDAR that measured nothing nearer than the vehicle: the line is cut at the vehicle.
// Rows nearer than 12 m carry no depth unless @p off_road is set: then one of the line's pixels
// there reads 0.2 m above the road (off the road, no object), which contradicts the line.
void sparseDepthToAVehicle(RenderedRoad& r, const std::vector<cv::Point2f>& line, bool off_road) {
  for (int v = 0; v < kH; ++v) {
    const double ry = (v - kK.cy) / kK.fy;
    if (!(ry > 1e-6)) continue;
    for (int u = 0; u < kW; ++u) {
      const double rx = (u - kK.cx) / kK.fx;
      cv::Vec3f& q = r.points.at<cv::Vec3f>(v, u);
      if (kHeight / ry < 12.0) {
        q = cv::Vec3f::all(std::nanf(""));
      } else {
        const double z = (kHeight - 1.0) / ry;  // the vehicle's body, 1 m above the road
        q = cv::Vec3f(static_cast<float>(rx * z), static_cast<float>(ry * z), static_cast<float>(z));
      }
    }
  }
  if (!off_road) return;
  const cv::Point2f& c = line[2];
  const double ry = (c.y - kK.cy) / kK.fy, rx = (c.x - kK.cx) / kK.fx;
  const double z = (kHeight - 0.2) / ry;
  r.points.at<cv::Vec3f>(static_cast<int>(std::lround(c.y)), static_cast<int>(std::lround(c.x))) =
      cv::Vec3f(static_cast<float>(rx * z), static_cast<float>(ry * z), static_cast<float>(z));
}

TEST(BoundaryClassifier, LineIsCutAtAVehicleThatSparseDepthAloneMeasures) {
  CrossSection cs;
  cs.colour = [](double x, double) { return std::fabs(x + 1.8) < 0.075 ? grey(220) : grey(80); };
  Fixture f;
  f.render(cs);
  const std::vector<cv::Point2f> line = linePixels(-1.8);
  sparseDepthToAVehicle(f, line, false);
  std::vector<cv::Point2f> px = line;
  ASSERT_TRUE(f.classifier.cutAtObject(f.in, px, true, Params::improved()));
  ASSERT_FALSE(px.empty());
  ASSERT_LT(px.size(), line.size());
  // the line ends at its last pixel before the vehicle (heights are read up to a few rows
  // beside a pixel, so the cut may come a pixel early)
  EXPECT_LT(roadForward(px.back()), 12.0);
  EXPECT_GT(roadForward(line[px.size()]), 11.0);

  // one measured pixel before the vehicle off the road: nothing says the line lies on the road
  Fixture g;
  g.render(cs);
  sparseDepthToAVehicle(g, line, true);
  px = line;
  EXPECT_FALSE(g.classifier.cutAtObject(g.in, px, true, Params::improved()));
  EXPECT_EQ(px.size(), line.size());
}

TEST(BoundaryClassifier, RaisedSurfaceBeyondWithoutDepthOnTheRoadIsNoStep) {
  // a painted line at x = -1.8 and, from 0.15 m beyond it, a surface 0.15 m above the road (a kerb,
  // or a vehicle's sill in the next lane): with the depth of the road on the vehicle's side,
  // a height step; where no depth measures the line and the road beside it (a LiDAR's blind
  // zone), nothing shows the step rising from the road: the line is what it looks like, paint
  CrossSection cs;
  cs.boxes = {{-INFINITY, -1.95, 0.15}};
  cs.colour = [](double x, double) { return std::fabs(x + 1.8) < 0.075 ? grey(220) : grey(80); };
  Fixture f;
  f.classify(cs, linePixels(-1.8), true);
  EXPECT_TRUE(f.ev.boundary) << f.ev.reason;
  EXPECT_EQ(f.ev.kind, BoundaryKind::kRoadEdge) << f.ev.reason;

  // the depth measures the raised surface only, and the line 4-12 m ahead (farther, the rows
  // near a pixel, where its height is sought, reach the raised surface beyond)
  Fixture g;
  g.render(cs);
  for (int v = 0; v < kH; ++v)
    for (int u = 0; u < kW; ++u) {
      cv::Vec3f& q = g.points.at<cv::Vec3f>(v, u);
      if (q[0] > -1.95f) q = cv::Vec3f::all(std::nanf(""));
    }
  g.pixels = linePixels(-1.8);
  while (roadForward(g.pixels.back()) > 12.0) g.pixels.pop_back();
  g.classifier.classify(g.in, g.pixels, true, Params::improved(), g.ev);
  EXPECT_FALSE(std::isfinite(g.ev.inner_height));
  EXPECT_FALSE(std::isfinite(g.ev.line_height));
  EXPECT_NEAR(g.ev.outer_height, 0.15, 0.02);
  EXPECT_TRUE(g.ev.boundary) << g.ev.reason;
  EXPECT_EQ(g.ev.kind, BoundaryKind::kPaint) << g.ev.reason;
}

}  // namespace
}  // namespace rgbd_lane_detector
