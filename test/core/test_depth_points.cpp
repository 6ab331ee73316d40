// Depth to organised 3D points (Eq. 1), invalid depth handling and hole filling.
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "guarded_mat.h"
#include "rgbd_lane_detector/depth_points.h"
#include "simd.h"  // private: targets

namespace rgbd_lane_detector {
namespace {

const Intrinsics kK{500.0, 400.0, 320.5, 240.25};

// Expects @p q to be the scalar definition's point of source pixel (u, v) at depth @p d, bit for
// bit (no point where d is NaN); true where the pixel has depth.
bool isDefinition(const cv::Vec3f& q, int u, int v, float d) {
  if (std::isnan(d)) {
    EXPECT_TRUE(std::isnan(q[0]) && std::isnan(q[1]) && std::isnan(q[2])) << u << " " << v;
    return false;
  }
  EXPECT_EQ(q[0], static_cast<float>((u - kK.cx) * (1.0 / kK.fx)) * d) << u << " " << v;
  EXPECT_EQ(q[1], static_cast<float>((v - kK.cy) * (1.0 / kK.fy)) * d) << u << " " << v;
  EXPECT_EQ(q[2], d) << u << " " << v;
  return true;
}

// 16-bit raw values of 1.3 mm and depth within 0.2-80 m (raw values outside it: no depth).
DepthDecoder rangedDecoder() {
  DepthDecoder dec;
  dec.scale = 0.0013;
  dec.min_depth = 0.2;
  dec.max_depth = 80.0;
  return dec;
}

TEST(DepthPoints, ExactBackProjection) {
  cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(2.0f));
  depth.at<float>(10, 600) = 7.5f;
  cv::Mat points;
  DepthDecoder dec;
  ASSERT_TRUE(depthToPoints(depth, dec, kK, cv::Range(0, 480), points));
  ASSERT_EQ(points.type(), CV_32FC3);
  const cv::Vec3f p = points.at<cv::Vec3f>(10, 600);
  EXPECT_NEAR(p[0], (600 - 320.5) / 500.0 * 7.5, 1e-5);
  EXPECT_NEAR(p[1], (10 - 240.25) / 400.0 * 7.5, 1e-5);
  EXPECT_FLOAT_EQ(p[2], 7.5f);
  const cv::Vec3f c = points.at<cv::Vec3f>(240, 320);
  EXPECT_NEAR(c[0], -0.5 / 500.0 * 2.0, 1e-7);
  EXPECT_NEAR(c[1], -0.25 / 400.0 * 2.0, 1e-7);
}

TEST(DepthPoints, InvalidDepthIsNaN) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  cv::Mat depth = (cv::Mat_<float>(1, 7) << 0.f, nan, inf, -1.f, 0.05f, 500.f, 3.f);
  DepthDecoder dec;
  dec.min_depth = 0.1;
  dec.max_depth = 100.0;
  cv::Mat points;
  ASSERT_TRUE(depthToPoints(depth, dec, kK, cv::Range(0, 1), points));
  for (int x = 0; x < 6; ++x) {
    const cv::Vec3f p = points.at<cv::Vec3f>(0, x);
    EXPECT_TRUE(std::isnan(p[0]) && std::isnan(p[1]) && std::isnan(p[2])) << "column " << x;
  }
  EXPECT_FLOAT_EQ(points.at<cv::Vec3f>(0, 6)[2], 3.f);
}

TEST(DepthPoints, SixteenBitScaleAndFloatAgree) {
  cv::RNG rng(3);
  cv::Mat mm(60, 80, CV_16UC1);
  rng.fill(mm, cv::RNG::UNIFORM, 0, 20000);
  mm.at<uint16_t>(5, 5) = 0;
  cv::Mat metres;
  mm.convertTo(metres, CV_32FC1, 0.001);
  metres.at<float>(5, 5) = 0.f;
  DepthDecoder dec;
  dec.scale = 0.001;
  cv::Mat a, b;
  ASSERT_TRUE(depthToPoints(mm, dec, kK, cv::Range(0, 60), a));
  ASSERT_TRUE(depthToPoints(metres, dec, kK, cv::Range(0, 60), b));
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 80; ++x)
      for (int c = 0; c < 3; ++c) {
        const float u = a.at<cv::Vec3f>(y, x)[c], v = b.at<cv::Vec3f>(y, x)[c];
        if (std::isnan(u) || std::isnan(v)) {
          EXPECT_TRUE(std::isnan(u) && std::isnan(v));
        } else {
          EXPECT_NEAR(u, v, 1e-5f * std::max(1.f, std::fabs(u)));
        }
      }
  // centimetres (SYNTHIA) through the scale
  dec.scale = 0.01;
  cv::Mat cm(1, 1, CV_16UC1, cv::Scalar(1234)), p;
  ASSERT_TRUE(depthToPoints(cm, dec, kK, cv::Range(0, 1), p));
  EXPECT_NEAR(p.at<cv::Vec3f>(0, 0)[2], 12.34f, 1e-5);
}

TEST(DepthPoints, UnsupportedTypeIsRejected) {
  cv::Mat d(4, 4, CV_8UC1, cv::Scalar(1)), p;
  EXPECT_FALSE(depthToPoints(d, DepthDecoder(), kK, cv::Range(0, 4), p));
}

TEST(DepthPoints, ResamplingMapsUseSourceCoordinates) {
  cv::Mat depth(8, 8, CV_32FC1, cv::Scalar(4.f));
  cv::Mat col_map = (cv::Mat_<int>(1, 4) << 0, 2, 4, 6);
  cv::Mat row_map = (cv::Mat_<int>(1, 4) << 1, 3, 5, 7);
  cv::Mat p;
  ASSERT_TRUE(depthToPoints(depth, DepthDecoder(), kK, cv::Range(0, 4), p, col_map, row_map));
  ASSERT_EQ(p.size(), cv::Size(4, 4));
  EXPECT_NEAR(p.at<cv::Vec3f>(2, 3)[0], (6 - kK.cx) / kK.fx * 4.0, 1e-5);
  EXPECT_NEAR(p.at<cv::Vec3f>(2, 3)[1], (5 - kK.cy) / kK.fy * 4.0, 1e-5);
}

TEST(DepthPoints, HoleFillingStaysOnThePlaneAndOnTheRay) {
  // ground plane y = 1.5 seen by a level camera: rows below the principal point
  const Intrinsics K{300, 300, 50, 20};
  cv::Mat depth(60, 100, CV_32FC1);
  for (int v = 0; v < 60; ++v)
    for (int u = 0; u < 100; ++u)
      depth.at<float>(v, u) = v > 20 ? static_cast<float>(1.5 * K.fy / (v - K.cy)) : 0.f;
  // a hole of 6 pixels on row 40 and one of 30 on row 45
  for (int u = 30; u < 36; ++u) depth.at<float>(40, u) = 0.f;
  for (int u = 10; u < 40; ++u) depth.at<float>(45, u) = 0.f;
  cv::Mat p;
  ASSERT_TRUE(depthToPoints(depth, DepthDecoder(), K, cv::Range(0, 60), p));
  fillDepthHoles(p, cv::Range(0, 60), 10);
  for (int u = 30; u < 36; ++u) {
    const cv::Vec3f q = p.at<cv::Vec3f>(40, u);
    ASSERT_FALSE(std::isnan(q[2]));
    EXPECT_NEAR(q[1], 1.5f, 1e-4);                       // on the plane
    EXPECT_NEAR(q[0] / q[2], (u - K.cx) / K.fx, 1e-5);   // on its ray
  }
  EXPECT_TRUE(std::isnan(p.at<cv::Vec3f>(45, 20)[2]));  // too long: left invalid
  EXPECT_TRUE(std::isnan(p.at<cv::Vec3f>(5, 5)[2]));    // no valid ends: left invalid
}

// Rows are converted eight pixels at a time where the CPU allows, the rest one by one: every
// point must be the scalar definition's, bit for bit (odd width: both paths in every row).
TEST(DepthPoints, EveryPixelIsTheScalarDefinitionBitForBit) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::RNG rng(9);
  cv::Mat mm(7, 83, CV_16UC1), metres(7, 83, CV_32FC1);
  rng.fill(mm, cv::RNG::UNIFORM, 0, 65536);
  rng.fill(metres, cv::RNG::UNIFORM, -1.0, 150.0);
  for (int i = 0; i < 60; ++i) {
    mm.at<uint16_t>(rng.uniform(0, 7), rng.uniform(0, 83)) = 0;
    metres.at<float>(rng.uniform(0, 7), rng.uniform(0, 83)) =
        i % 3 == 0 ? nan : (i % 3 == 1 ? std::numeric_limits<float>::infinity() : 0.f);
  }
  const DepthDecoder dec = rangedDecoder();
  for (const cv::Mat& depth : {mm, metres}) {
    cv::Mat p;
    ASSERT_TRUE(depthToPoints(depth, dec, kK, cv::Range(0, 7), p));
    for (int v = 0; v < 7; ++v)
      for (int u = 0; u < 83; ++u) {
        const float d = depth.type() == CV_16UC1 ? dec(depth.at<uint16_t>(v, u))
                                                 : dec(depth.at<float>(v, u));
        const cv::Vec3f q = p.at<cv::Vec3f>(v, u);
        isDefinition(q, u, v, d);
      }
  }
}

// Resampled through index maps (rows gathered, then the vector kernels) on every target: the
// scalar definition at the source pixel, bit for bit; and the depth block map: a block is empty
// exactly when none of its pixels has depth (depthBlocks() of the points says the same).
TEST(DepthPoints, ResampledRowsAndTheDepthBlockMap) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::RNG rng(5);
  cv::Mat mm(9, 83, CV_16UC1, cv::Scalar(0)), metres(9, 83, CV_32FC1, cv::Scalar(nan));
  for (int i = 0; i < 120; ++i) {  // sparse, as a LiDAR: most pixels without depth
    const int v = rng.uniform(0, 9), u = rng.uniform(0, 83);
    mm.at<uint16_t>(v, u) = static_cast<uint16_t>(rng.uniform(1, 65536));
    metres.at<float>(v, u) = static_cast<float>(rng.uniform(-1.0, 150.0));
  }
  cv::Mat col_map(1, 50, CV_32SC1), row_map(1, 6, CV_32SC1);
  for (int x = 0; x < 50; ++x)
    col_map.at<int>(x) = std::min(82, static_cast<int>((x + 0.5) * 83 / 50));
  for (int y = 0; y < 6; ++y) row_map.at<int>(y) = std::min(8, static_cast<int>((y + 0.5) * 9 / 6));
  const DepthDecoder dec = rangedDecoder();
  for (simd::Target target : simd::availableTargets()) {
    simd::forceTarget(target);
    for (const cv::Mat& depth : {mm, metres}) {
      SCOPED_TRACE(testing::Message() << simd::targetName(target) << ", type " << depth.type());
      cv::Mat p, blocks, again;
      ASSERT_TRUE(depthToPoints(depth, dec, kK, cv::Range(0, 6), p, col_map, row_map, &blocks));
      ASSERT_EQ(blocks.size(), cv::Size((50 + kDepthBlock - 1) / kDepthBlock, 6));
      int empty = 0;
      for (int y = 0; y < 6; ++y) {
        const int v = row_map.at<int>(y);
        std::vector<bool> any(blocks.cols, false);
        for (int x = 0; x < 50; ++x) {
          const int u = col_map.at<int>(x);
          const float d = depth.type() == CV_16UC1 ? dec(depth.at<uint16_t>(v, u))
                                                   : dec(depth.at<float>(v, u));
          const cv::Vec3f q = p.at<cv::Vec3f>(y, x);
          if (isDefinition(q, u, v, d)) any[x / kDepthBlock] = true;
        }
        for (int b = 0; b < blocks.cols; ++b) {
          EXPECT_EQ(blocks.at<uint8_t>(y, b), any[b] ? 1 : 0) << y << " " << b;
          empty += !any[b];
        }
      }
      EXPECT_GT(empty, 0);
      depthBlocks(p, cv::Range(0, 6), again);
      EXPECT_EQ(cv::countNonZero(again != blocks), 0);
    }
  }
  simd::forceTarget(simd::kBest);
}

// A LiDAR's resampled row is mostly source spans of raw 0, which are passed over without a
// gather: the points next to them, the span at the row's end (a source chunk shorter than the
// others) and the block map stay the scalar definition on every target.
TEST(DepthPoints, ResampledSparseRowsPassOverEmptySpans) {
  cv::Mat mm(4, 203, CV_16UC1, cv::Scalar(0));
  const int cols[] = {0, 31, 32, 95, 140, 141, 170, 202};  // chunk edges, the last column
  for (int v = 0; v < 3; ++v)  // row 3 without depth
    for (int k = 0; k < 8; ++k)
      if ((k + v) % 3 != 0) mm.at<uint16_t>(v, cols[k]) = static_cast<uint16_t>(1000 + 37 * k + v);
  const int w = 121;
  cv::Mat col_map(1, w, CV_32SC1), row_map(1, 4, CV_32SC1);
  for (int x = 0; x < w; ++x)
    col_map.at<int>(x) = std::min(202, static_cast<int>((x + 0.5) * 203 / w));
  for (int y = 0; y < 4; ++y) row_map.at<int>(y) = y;
  DepthDecoder dec;
  dec.scale = 0.0013;
  for (simd::Target target : simd::availableTargets()) {
    simd::forceTarget(target);
    SCOPED_TRACE(simd::targetName(target));
    cv::Mat p, blocks, again;
    ASSERT_TRUE(depthToPoints(mm, dec, kK, cv::Range(0, 4), p, col_map, row_map, &blocks));
    int with_depth = 0;
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < w; ++x) {
        const int u = col_map.at<int>(x);
        const float d = dec(mm.at<uint16_t>(y, u));
        const cv::Vec3f q = p.at<cv::Vec3f>(y, x);
        with_depth += isDefinition(q, u, y, d);
      }
    EXPECT_GT(with_depth, 6);
    depthBlocks(p, cv::Range(0, 4), again);
    EXPECT_EQ(cv::countNonZero(again != blocks), 0);
  }
  simd::forceTarget(simd::kBest);
}

// Resampled rows read straight from the source row through the column map (no row gathered
// first), with the caller's tables kept from a wider call: 16-bit values at the source row's last
// column (their 4 bytes would end past the row: the per-pixel definition reads them), float
// depth, a row wider than the chunks scanned between two prefetches; on every target, the scalar
// definition bit for bit and the same points as a call that makes its own tables.
TEST(DepthPoints, ResampledThroughTheColumnMapWithKeptTables) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::RNG rng(11);
  const int cols = 613;
  cv::Mat mm(5, cols, CV_16UC1), metres(5, cols, CV_32FC1);
  rng.fill(mm, cv::RNG::UNIFORM, 0, 65536);
  rng.fill(metres, cv::RNG::UNIFORM, -1.0, 150.0);
  for (int i = 0; i < 900; ++i) {  // runs of no depth, whole chunks among them
    const int v = rng.uniform(0, 5), u = rng.uniform(0, cols - 40);
    for (int k = 0; k < 40; ++k) {
      mm.at<uint16_t>(v, u + k) = 0;
      metres.at<float>(v, u + k) = nan;
    }
  }
  for (int v = 0; v < 5; ++v) mm.at<uint16_t>(v, cols - 1) = static_cast<uint16_t>(20000 + v);
  const DepthDecoder dec = rangedDecoder();
  // a wide map first (the tables grow), then one of 330 columns whose last 40 read the last
  // source column
  cv::Mat wide(1, 600, CV_32SC1), col_map(1, 330, CV_32SC1), row_map(1, 5, CV_32SC1);
  for (int x = 0; x < 600; ++x) wide.at<int>(x) = x;
  for (int x = 0; x < 330; ++x) col_map.at<int>(x) = std::min(cols - 1, x * 2);
  for (int x = 290; x < 330; ++x) col_map.at<int>(x) = cols - 1;
  for (int y = 0; y < 5; ++y) row_map.at<int>(y) = 4 - y;
  for (simd::Target target : simd::availableTargets()) {
    simd::forceTarget(target);
    for (const cv::Mat& depth : {mm, metres}) {
      SCOPED_TRACE(testing::Message() << simd::targetName(target) << ", type " << depth.type());
      DepthPointsTables tables;
      cv::Mat p, own, blocks, own_blocks;
      ASSERT_TRUE(depthToPoints(depth, dec, kK, cv::Range(0, 5), p, wide, row_map, &blocks,
                                &tables));
      ASSERT_TRUE(depthToPoints(depth, dec, kK, cv::Range(0, 5), p, col_map, row_map, &blocks,
                                &tables));
      ASSERT_TRUE(depthToPoints(depth, dec, kK, cv::Range(0, 5), own, col_map, row_map,
                                &own_blocks));
      ASSERT_GE(tables.ax.size(), 600u);
      int with_depth = 0;
      for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 330; ++x) {
          const int u = col_map.at<int>(x), v = row_map.at<int>(y);
          const float d = depth.type() == CV_16UC1 ? dec(depth.at<uint16_t>(v, u))
                                                   : dec(depth.at<float>(v, u));
          const cv::Vec3f q = p.at<cv::Vec3f>(y, x);
          EXPECT_EQ(std::memcmp(&q, &own.at<cv::Vec3f>(y, x), sizeof(q)), 0) << y << " " << x;
          with_depth += isDefinition(q, u, v, d);
        }
      EXPECT_GT(with_depth, 100);
      EXPECT_EQ(cv::countNonZero(blocks != own_blocks), 0);
    }
  }
  simd::forceTarget(simd::kBest);
}

// The source rows end where an inaccessible page begins (a read past a row's end faults, where an
// ordinary cv::Mat's padding takes it unseen): 16-bit and float depth with runs of no depth,
// read without a column map and through one whose last columns read the last source column (a
// 16-bit value is read as the low half of 4 bytes: 2 of them past the row there; 160 columns:
// on every target, vectors reach the map's last column), the source's last row read by every
// other output row; on every target, the scalar definition at every pixel.
TEST(DepthPoints, NoReadPastTheSourceRowsEnd) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::RNG rng(13);
  const int rows = 3, cols = 203;
  cv::Mat mm(rows, cols, CV_16UC1), metres(rows, cols, CV_32FC1);
  rng.fill(mm, cv::RNG::UNIFORM, 1, 65536);
  rng.fill(metres, cv::RNG::UNIFORM, 0.5, 70.0);
  for (int v = 0; v < rows; ++v)
    for (int u = 40 * v; u < 40 * v + 70; ++u) {  // a run of no depth, empty blocks among it
      mm.at<uint16_t>(v, u) = 0;
      metres.at<float>(v, u) = nan;
    }
  for (int v = 0; v < rows; ++v) {  // depth at the last column
    mm.at<uint16_t>(v, cols - 1) = static_cast<uint16_t>(20000 + v);
    metres.at<float>(v, cols - 1) = 26.0f + v;
  }
  const test::GuardedMat guarded_mm(mm), guarded_metres(metres);
  const int w = 160;
  cv::Mat col_map(1, w, CV_32SC1), row_map = (cv::Mat_<int>(1, 5) << 2, 0, 2, 1, 2);
  for (int x = 0; x < w; ++x) col_map.at<int>(x) = std::min(cols - 1, x * 3 / 2);
  for (int x = w - 12; x < w; ++x) col_map.at<int>(x) = cols - 1 - (x % 3 == 1);
  ASSERT_EQ(col_map.at<int>(w - 1), cols - 1);
  const DepthDecoder dec = rangedDecoder();
  for (simd::Target target : simd::availableTargets()) {
    simd::forceTarget(target);
    for (const test::GuardedMat* guarded : {&guarded_mm, &guarded_metres}) {
      const cv::Mat& depth = guarded->mat();
      ASSERT_EQ(guarded->end(), guarded->guard());
      SCOPED_TRACE(testing::Message() << simd::targetName(target) << ", type " << depth.type());
      auto decoded = [&](int v, int u) {
        return depth.type() == CV_16UC1 ? dec(depth.at<uint16_t>(v, u))
                                        : dec(depth.at<float>(v, u));
      };
      cv::Mat p, blocks;
      int with_depth = 0;
      ASSERT_TRUE(depthToPoints(depth, dec, kK, cv::Range(0, rows), p, cv::Mat(), cv::Mat(),
                                &blocks));
      for (int v = 0; v < rows; ++v)
        for (int u = 0; u < cols; ++u)
          with_depth += isDefinition(p.at<cv::Vec3f>(v, u), u, v, decoded(v, u));
      ASSERT_TRUE(depthToPoints(depth, dec, kK, cv::Range(0, 5), p, col_map, row_map, &blocks));
      for (int y = 0; y < 5; ++y)
        for (int x = 0; x < w; ++x) {
          const int u = col_map.at<int>(x), v = row_map.at<int>(y);
          with_depth += isDefinition(p.at<cv::Vec3f>(y, x), u, v, decoded(v, u));
        }
      EXPECT_GT(with_depth, 500);
      EXPECT_TRUE(isDefinition(p.at<cv::Vec3f>(4, w - 1), cols - 1, 2, decoded(2, cols - 1)));
    }
  }
  simd::forceTarget(simd::kBest);
}

}  // namespace
}  // namespace rgbd_lane_detector
