// Row profiles across a line on a rendered level road, 80 rows below the horizon (the road
// kHeight fy / 80 m ahead, 80 / kHeight = 53.3 px per metre across it): bands of paint width,
// narrower and wider; the backgrounds of both sides; the centre of a band; where the road ends.
#include <cmath>
#include <cstdint>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/band_profile.h"
#include "road_cross_section.h"

namespace rgbd_lane_detector {
namespace {

using namespace test;  // NOLINT: the rendered road

constexpr int kRow = 270;                // kK.cy + 80
constexpr double kPpm = 80.0 / kHeight;  // px per metre across the road on kRow
double columnOf(double x) {
  return kK.cx + x * kPpm;
}  // of lateral x on kRow

// A road of grey 80 with a band of grey 220 and width w centred at x = -1.8.
CrossSection bandOfWidth(double w) {
  CrossSection cs;
  cs.colour = [w](double x, double) { return std::fabs(x + 1.8) < 0.5 * w ? grey(220) : grey(80); };
  return cs;
}

struct Profile : RenderedRoad {
  BandProfile profile;
  RowMeasure m;
  bool measure(double x, bool left = true) {
    return profile.measureRow(in, cv::Point2f(static_cast<float>(columnOf(x)), kRow), left,
                              Params::improved(), 1.0, m);
  }
};

TEST(BandProfile, PaintIsABandOfItsWidthOnTheLine) {
  Profile f;
  f.render(bandOfWidth(0.16));  // 8.5 px: 8 or 9 pixels of paint
  ASSERT_TRUE(f.measure(-1.8));
  EXPECT_NEAR(f.m.ppm, kPpm, 1e-9);
  EXPECT_NEAR(f.m.depth, kHeight * kK.fx / 80.0, 1e-9);
  EXPECT_EQ(f.m.bg[0], 80.f);
  EXPECT_EQ(f.m.bg[1], 80.f);
  EXPECT_EQ(f.m.peak, 220.f);
  ASSERT_NE(f.m.paint, nullptr);
  EXPECT_EQ(f.m.narrow, nullptr);
  EXPECT_EQ(f.m.wide, nullptr);
  // a sharp band's half-peak edges are half a pixel outside its outer pixels
  const double width_px = f.m.paint->hi - f.m.paint->lo;
  EXPECT_TRUE(width_px == 8.0 || width_px == 9.0) << width_px;
  EXPECT_LE(std::fabs(0.5 * (f.m.paint->lo + f.m.paint->hi)), 0.5);  // on the line
}

TEST(BandProfile, NarrowAndWideBandsAreNotPaint) {
  Profile rail;
  rail.render(bandOfWidth(0.04));  // 2 px: a rail head
  ASSERT_TRUE(rail.measure(-1.8));
  EXPECT_EQ(rail.m.paint, nullptr);
  ASSERT_NE(rail.m.narrow, nullptr);
  EXPECT_LE(rail.m.narrow->hi - rail.m.narrow->lo, 3.0);
  Profile zebra;
  zebra.render(bandOfWidth(0.6));  // 32 px: a zebra stripe
  ASSERT_TRUE(zebra.measure(-1.8));
  EXPECT_EQ(zebra.m.paint, nullptr);
  ASSERT_NE(zebra.m.wide, nullptr);
  EXPECT_NEAR(zebra.m.wide->hi - zebra.m.wide->lo, 0.6 * kPpm, 1.5);  // 31 px
}

// A dark road at night: grey 20 with sensor noise of sigma 8 (uniform, per pixel column), with
// or without a band of paint 60 grey levels above it.
CrossSection noisyNight(bool paint) {
  CrossSection cs;
  cs.colour = [paint](double x, double) {
    const int column = static_cast<int>(std::lround(columnOf(x)));
    uint32_t h = static_cast<uint32_t>(column) * 2654435761u;  // a fixed pseudo-random value
    h ^= h >> 15;
    h *= 2246822519u;
    h ^= h >> 13;
    const double noise = (static_cast<double>(h % 1001) / 1000.0 - 0.5) * 2.0 * 13.9;  // sigma 8
    const double base = paint && std::fabs(x + 1.8) < 0.075 ? 80.0 : 20.0;
    return grey(static_cast<int>(std::lround(std::max(0.0, base + noise))));
  };
  return cs;
}

TEST(BandProfile, NoiseOnADarkRoadIsNoBand) {
  // (the relative paint contrast of a road of grey 20 is 5 grey levels, under its noise: runs of
  // noise would be narrow bands, rail heads; the row's own noise sets the contrast instead)
  Profile f;
  f.render(noisyNight(false));
  int measured = 0, bands = 0;
  for (double x = -2.4; x <= -1.2; x += 0.05) {
    if (!f.measure(x)) continue;
    ++measured;
    EXPECT_GT(f.m.noise, 4.0f);
    EXPECT_LT(f.m.noise, 14.0f);
    EXPECT_GE(f.m.contrast, 3.0f * f.m.noise);
    bands += f.m.narrow != nullptr || f.m.paint != nullptr || f.m.wide != nullptr;
  }
  EXPECT_GT(measured, 15);
  EXPECT_EQ(bands, 0);
}

TEST(BandProfile, PaintStandsOutOfTheNoise) {
  Profile f;
  f.render(noisyNight(true));  // 0.15 m of paint, 60 grey levels (7.5 sigma) above the road
  ASSERT_TRUE(f.measure(-1.8));
  ASSERT_NE(f.m.paint, nullptr);
  EXPECT_NEAR(0.5 * (f.m.paint->lo + f.m.paint->hi) / f.m.ppm, 0.0, 0.03);
  EXPECT_NEAR((f.m.paint->hi - f.m.paint->lo) / f.m.ppm, 0.15, 0.05);
}

TEST(BandProfile, SidesAreTheRoadBesideTheLineInnerThenOuter) {
  // beyond a line left of the vehicle (x < -1.9) the surface is brighter: the outer side
  CrossSection cs;
  cs.colour = [](double x, double) { return x < -1.9 ? grey(150) : grey(80); };
  Profile f;
  f.render(cs);
  ASSERT_TRUE(f.measure(-1.8, true));
  EXPECT_EQ(f.m.outer_dir, -1);
  EXPECT_EQ(f.m.bg[0], 80.f);
  EXPECT_EQ(f.m.bg[1], 150.f);
  EXPECT_EQ(f.m.top, 150.f);
  ASSERT_TRUE(f.measure(-1.8, false));  // the same line taken as right of the vehicle
  EXPECT_EQ(f.m.bg[0], 150.f);
  EXPECT_EQ(f.m.bg[1], 80.f);
}

// A row of a high-resolution camera near the vehicle (fx 2000 px, the row 500 px below the
// principal point: the road 6 m ahead, 333 px per metre across it, 3 mm per pixel) with a band
// of width w centred at x = -1.0 on a road of grey 80; textured paint: bright grains (230) and
// the darker binder between them (140) in turns of 2 pixels, as worn paint, the aggregate
// showing through or raised markers look at a few millimetres per pixel; a rail head is smooth.
struct NearRow {
  static constexpr int kCols = 1920, kRows = 1200, kV = 1100;
  cv::Mat bgr, grey, points;
  PlaneEstimate plane = level();
  ClassifierInput in;
  BandProfile profile;
  RowMeasure m;
  NearRow(double w, bool textured) {
    const Intrinsics K{2000.0, 2000.0, 960.0, 600.0};
    const double ppm = K.fx * (kV - K.cy) / (K.fy * kHeight);
    bgr.create(kRows, kCols, CV_8UC3);
    for (int u = 0; u < kCols; ++u) {
      const double x = (u - K.cx) / ppm;  // lateral position on row kV
      const int g = std::fabs(x + 1.0) >= 0.5 * w ? 80 : !textured || (u & 3) < 2 ? 230 : 140;
      bgr.col(u).setTo(cv::Scalar(g, g, g));
    }
    points.create(kRows, kCols, CV_32FC3);
    points.setTo(cv::Scalar::all(std::nanf("")));
    in = classifierInput(bgr, grey, points, plane, K);
    const float u = static_cast<float>(K.cx - 1.0 * ppm);
    measured = profile.measureRow(in, cv::Point2f(u, kV), true, Params::improved(), 1.0, m);
  }
  bool measured = false;
};

TEST(BandProfile, TexturedPaintIsOneBandOfPaintWidth) {
  // (read pixel by pixel, the 12 cm line's grains, 6 mm each, split it at the binder between
  // them into bands narrower than paint: rail heads)
  NearRow paint(0.12, true);
  ASSERT_TRUE(paint.measured);
  EXPECT_NEAR(paint.m.ppm, 333.3, 0.1);
  ASSERT_NE(paint.m.paint, nullptr);
  EXPECT_EQ(paint.m.narrow, nullptr);
  EXPECT_NEAR((paint.m.paint->hi - paint.m.paint->lo) / paint.m.ppm, 0.12, 0.01);
  EXPECT_LE(std::fabs(0.5 * (paint.m.paint->lo + paint.m.paint->hi)) / paint.m.ppm, 0.01);
  // a rail head, 5 cm, stays one band narrower than paint
  NearRow rail(0.05, false);
  ASSERT_TRUE(rail.measured);
  EXPECT_EQ(rail.m.paint, nullptr);
  ASSERT_NE(rail.m.narrow, nullptr);
  EXPECT_NEAR((rail.m.narrow->hi - rail.m.narrow->lo) / rail.m.ppm, 0.05, 0.01);
}

TEST(BandProfile, NoProfileOffTheRoadOrTooFar) {
  Profile f;
  f.render(bandOfWidth(0.16));
  RowMeasure m;
  const Params p = Params::improved();
  EXPECT_FALSE(f.profile.measureRow(f.in, cv::Point2f(300.f, 150.f), true, p, 1.0, m));  // sky
  // 10 rows below the horizon a pixel spans 0.15 m, more than 1 / kMinPixelsPerMetre
  EXPECT_FALSE(f.profile.measureRow(f.in, cv::Point2f(300.f, 200.f), true, p, 1.0, m));
  EXPECT_FALSE(f.profile.measureRow(f.in, cv::Point2f(5.f, kRow), true, p, 1.0, m));  // border
}

TEST(BandProfile, BandCentreIsTheMiddleOfTheBand) {
  Profile f;
  f.render(bandOfWidth(0.16));
  const Params p = Params::improved();
  double centre = 0.0;
  ASSERT_TRUE(f.profile.bandCentre(f.in, kRow, columnOf(-1.8) + 3.0, 8, 20.0, p, centre));
  EXPECT_NEAR(centre, columnOf(-1.8), 0.5);
  EXPECT_FALSE(f.profile.bandCentre(f.in, kRow, columnOf(-1.8), 8, 5.0, p, centre));  // too wide
  EXPECT_FALSE(f.profile.bandCentre(f.in, kRow, columnOf(0.0), 8, 20.0, p, centre));  // no band
}

TEST(BandProfile, EdgeInRowIsWhereTheRoadEnds) {
  // grass from x = 1.79 on, right of the vehicle: the first grass pixel is column 416 on kRow
  CrossSection cs;
  cs.colour = [](double x, double) { return x >= 1.79 ? cv::Vec3b(70, 110, 40) : grey(80); };
  Profile f;
  f.render(cs);
  const Params p = Params::improved();
  double edge = 0.0;
  ASSERT_TRUE(f.profile.edgeInRow(f.in, kRow, columnOf(1.9), kPpm, false, p, 0.3, edge));
  EXPECT_DOUBLE_EQ(edge, 415.5);
  // a road without an edge within reach
  Profile g;
  g.render(CrossSection());
  EXPECT_FALSE(g.profile.edgeInRow(g.in, kRow, columnOf(1.9), kPpm, false, p, 0.3, edge));
}

}  // namespace
}  // namespace rgbd_lane_detector
