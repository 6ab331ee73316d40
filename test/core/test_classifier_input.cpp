// What the classifier reads of its input, on a rendered level road seen from kHeight: the road
// under a pixel (forward distance, pixels per metre), heights above the road, depth points, a
// line's heading on the road, one image row's colours in either channel order.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/classifier_input.h"
#include "road_cross_section.h"

namespace rgbd_lane_detector {
namespace {

using namespace test;  // NOLINT: the rendered road

// Input pixel of the road point (lateral x right, forward z), height h above the road.
cv::Point2f pixelOf(double x, double z, double h = 0.0) {
  return cv::Point2f(static_cast<float>(kK.fx * x / z + kK.cx),
                     static_cast<float>(kK.fy * (kHeight - h) / z + kK.cy));
}

TEST(ClassifierInput, RoadAtGivesTheForwardDistanceAndPixelsPerMetre) {
  RenderedRoad r;
  r.render(CrossSection());
  double f = 0.0, ppm = 0.0;
  // 80 rows below the horizon the ray's y is 80 / fy: the road is 1.5 fy / 80 ahead
  ASSERT_TRUE(r.in.roadAt(100.0, kK.cy + 80.0, f, ppm));
  EXPECT_NEAR(f, kHeight * kK.fy / 80.0, 1e-9);
  EXPECT_NEAR(ppm, 80.0 / kHeight, 1e-9);                 // fx / depth
  EXPECT_FALSE(r.in.roadAt(100.0, kK.cy - 5.0, f, ppm));  // above the horizon
}

TEST(ClassifierInput, HeightAtIsTheDepthAboveTheRoad) {
  RenderedRoad r;
  CrossSection cs;
  cs.boxes = {{1.8, INFINITY, 0.12}};  // a kerb's top from x = 1.8 on
  r.render(cs);
  const cv::Point2f on_road = pixelOf(0.5, 8.0), on_kerb = pixelOf(2.5, 8.0, 0.12);
  auto height = [&](const cv::Point2f& c) {
    return r.in.heightAt(static_cast<int>(std::lround(c.x)), static_cast<int>(std::lround(c.y)));
  };
  EXPECT_NEAR(height(on_road), 0.0f, 1e-4f);
  EXPECT_NEAR(height(on_kerb), 0.12f, 1e-4f);
  EXPECT_TRUE(std::isnan(r.in.heightAt(300, 20)));  // the sky: no depth
  // a row without depth (between LiDAR rows) reads the nearest row with depth in its column
  const int u = static_cast<int>(std::lround(on_kerb.x));
  const int v = static_cast<int>(std::lround(on_kerb.y));
  for (int dv = -3; dv <= 2; ++dv) r.points.at<cv::Vec3f>(v + dv, u) = cv::Vec3f::all(NAN);
  r.points.at<cv::Vec3f>(v + 3, u) = cv::Vec3f(2.5f, static_cast<float>(kHeight - 0.12), 8.0f);
  EXPECT_NEAR(r.in.heightAt(u, v), 0.12f, 1e-5f);
  // a filled point (the plane extended over missing depth) is no measurement
  cv::Mat filled(r.points.size(), CV_8UC1, cv::Scalar(0));
  filled.at<uint8_t>(v + 3, u) = 255;
  r.in.filled = &filled;
  EXPECT_TRUE(std::isnan(r.in.heightAt(u, v)));
}

TEST(ClassifierInput, PointAtReadsTheProcessingScale) {
  RenderedRoad r;
  r.render(CrossSection());
  const cv::Vec3f q = r.points.at<cv::Vec3f>(300, 200);
  EXPECT_EQ(r.in.pointAt(200, 300), Eigen::Vector3f(q[0], q[1], q[2]));
  // points at half the input resolution: input pixel (401, 601) is processing pixel (200, 300)
  r.in.scale_x = r.in.scale_y = 0.5;
  EXPECT_EQ(r.in.pointAt(401, 601), Eigen::Vector3f(q[0], q[1], q[2]));
  EXPECT_TRUE(std::isnan(r.in.pointAt(2 * kW, 10).z()));  // outside the image
}

TEST(ClassifierInput, CosHeadingOfALineOnTheRoad) {
  RenderedRoad r;
  r.render(CrossSection());
  // along the road: 1; 45 deg across it: cos 45 deg; nearly across: clamped to 0.5
  EXPECT_NEAR(r.in.cosHeading({pixelOf(-1.8, 5.0), pixelOf(-1.8, 9.0), pixelOf(-1.8, 15.0)}), 1.0,
              1e-6);
  EXPECT_NEAR(r.in.cosHeading({pixelOf(-3.0, 6.0), pixelOf(-1.0, 8.0), pixelOf(1.0, 10.0)}),
              std::sqrt(0.5), 1e-5);
  EXPECT_EQ(r.in.cosHeading({pixelOf(-3.0, 8.0), pixelOf(3.0, 8.5)}), 0.5);
  // shorter than 0.5 m on the road, or above the horizon: 1
  EXPECT_EQ(r.in.cosHeading({pixelOf(0.0, 8.0), pixelOf(0.3, 8.2)}), 1.0);
  EXPECT_EQ(r.in.cosHeading({cv::Point2f(100.f, 10.f), cv::Point2f(500.f, 20.f)}), 1.0);
}

TEST(ClassifierInput, ImageRowReadsEitherChannelOrder) {
  cv::Mat colour(4, 8, CV_8UC3, cv::Scalar(10, 20, 30)), grey(4, 8, CV_8UC1, cv::Scalar(21));
  ClassifierInput in;
  in.colour = &colour;
  in.grey = &grey;
  in.grey_rows = cv::Range(1, 3);
  in.format = PixelFormat::kBgr8;
  float R, G, B;
  const ImageRow bgr(in, 1);
  ASSERT_TRUE(bgr.valid());
  bgr.rgb(5, R, G, B);
  EXPECT_EQ(R, 30.f);
  EXPECT_EQ(G, 20.f);
  EXPECT_EQ(B, 10.f);
  EXPECT_EQ(bgr.grey(5), 21.f);
  float r, g;
  bgr.chroma(5, r, g);
  EXPECT_NEAR(r, 0.5f, 1e-4f);
  EXPECT_NEAR(g, 1.f / 3.f, 1e-4f);
  in.format = PixelFormat::kRgb8;
  ImageRow(in, 2).rgb(0, R, G, B);
  EXPECT_EQ(R, 10.f);
  EXPECT_EQ(B, 30.f);
  EXPECT_FALSE(ImageRow(in, 0).valid());  // outside the grey rows
  EXPECT_FALSE(ImageRow(in, 3).valid());
}

// Without a grey image (the detector at a processing scale) the grey values are greyValue() of
// the colour: what the input's grey image would hold, in either channel order and for mono.
TEST(ClassifierInput, ImageRowWithoutGreyComputesItFromTheColour) {
  cv::Mat colour(3, 5, CV_8UC3), mono(3, 5, CV_8UC1);
  cv::randu(colour, 0, 256);
  cv::randu(mono, 0, 256);
  ClassifierInput in;
  in.grey_rows = cv::Range(0, 3);
  for (PixelFormat f : {PixelFormat::kBgr8, PixelFormat::kRgb8}) {
    in.colour = &colour;
    in.format = f;
    const bool bgr = f == PixelFormat::kBgr8;
    const ImageRow row(in, 1);
    ASSERT_TRUE(row.valid());
    for (int u = 0; u < 5; ++u) {
      const cv::Vec3b c = colour.at<cv::Vec3b>(1, u);
      EXPECT_EQ(row.grey(u), greyValue(c[bgr ? 2 : 0], c[1], c[bgr ? 0 : 2]));
    }
  }
  in.colour = &mono;
  in.format = PixelFormat::kMono8;
  EXPECT_EQ(ImageRow(in, 2).grey(3), mono.at<uint8_t>(2, 3));
  EXPECT_FALSE(ImageRow(in, 3).valid());  // outside the rows
}

// A run of grey values (the profiles' read of a row, converted by the SIMD row kernel) is grey()
// pixel for pixel, and a run's colour sums are those of rgb(): every format, with and without a
// grey image, runs of any length and start (whole vectors and their tails).
TEST(ClassifierInput, GreyRunAndColourSumsAreThoseOfEveryPixel) {
  const int w = 203;
  cv::Mat c3(2, w, CV_8UC3), c4(2, w, CV_8UC4), mono(2, w, CV_8UC1), grey(2, w, CV_8UC1);
  cv::randu(c3, 0, 256);
  cv::randu(c4, 0, 256);
  cv::randu(mono, 0, 256);
  cv::randu(grey, 0, 256);
  struct Case {
    const cv::Mat* colour;
    PixelFormat format;
    const cv::Mat* grey;
  };
  const Case cases[] = {{&c3, PixelFormat::kBgr8, nullptr},  {&c3, PixelFormat::kRgb8, nullptr},
                        {&c4, PixelFormat::kBgra8, nullptr}, {&c4, PixelFormat::kRgba8, nullptr},
                        {&mono, PixelFormat::kMono8, nullptr}, {&c3, PixelFormat::kBgr8, &grey}};
  std::vector<uint8_t> run(w);
  for (const Case& c : cases) {
    ClassifierInput in;
    in.colour = c.colour;
    in.format = c.format;
    in.grey = c.grey;
    in.grey_rows = cv::Range(0, 2);
    const ImageRow row(in, 1);
    ASSERT_TRUE(row.valid());
    for (int u0 : {0, 1, 7, 40}) {
      for (int n : {1, 3, 16, 33, 97, w - 40}) {
        row.greyRun(u0, n, run.data());
        for (int i = 0; i < n; ++i)
          ASSERT_EQ(run[i], row.grey(u0 + i)) << static_cast<int>(c.format) << " " << u0 + i;
        if (c.format == PixelFormat::kMono8) continue;
        int R = 0, G = 0, B = 0;
        row.rgbSums(u0, n, R, G, B);
        double r = 0.0, g = 0.0, b = 0.0;  // the colours one by one, as the profiles read them
        for (int i = 0; i < n; ++i) {
          float Ri, Gi, Bi;
          row.rgb(u0 + i, Ri, Gi, Bi);
          r += Ri, g += Gi, b += Bi;
        }
        EXPECT_EQ(R, r);
        EXPECT_EQ(G, g);
        EXPECT_EQ(B, b);
      }
    }
  }
}

}  // namespace
}  // namespace rgbd_lane_detector
