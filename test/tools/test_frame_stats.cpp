// FramePlayerNodelet's bookkeeping (tools/ros/frame_stats.h, issue 23): which published frames
// came back, each once, and the latency quantiles.
#include <gtest/gtest.h>

#include "frame_stats.h"

using rgbd_lane_detector::tools::FrameStats;

TEST(FrameStats, CountsEachFrameOnceAndSeparatesTheWarmUp) {
  FrameStats s(8);
  s.published(1, true);   // warm-up
  s.published(2, true);   // warm-up, never back
  s.published(10, false);
  s.published(11, false);
  s.published(12, false);  // never back
  EXPECT_FALSE(s.allBack());
  s.output(1, 5.0);
  s.output(10, 4.0);
  s.output(10, 4.0);  // the same frame again
  s.output(11, 6.0);
  s.output(99, 1.0);  // not published
  const auto r = s.summary();
  EXPECT_EQ(r.published, 3);
  EXPECT_EQ(r.outputs, 2);
  EXPECT_EQ(r.lost, 1);
  EXPECT_EQ(r.duplicates, 1);
  EXPECT_EQ(r.unknown, 1);
  EXPECT_EQ(r.warmup_published, 2);
  EXPECT_EQ(r.warmup_outputs, 1);
  EXPECT_EQ(s.outstanding(), 1);
  EXPECT_DOUBLE_EQ(r.mean_ms, 5.0);  // the warm-up frame's latency is not counted
  EXPECT_DOUBLE_EQ(r.max_ms, 6.0);
  EXPECT_FALSE(s.allBack());
  s.output(12, 7.0);
  s.output(2, 8.0);
  EXPECT_TRUE(s.allBack());
}

TEST(FrameStats, NearestRankQuantiles) {
  FrameStats s(100);
  for (int i = 1; i <= 100; ++i) s.published(i, false);
  for (int i = 100; i >= 1; --i) s.output(i, static_cast<double>(i));  // any arrival order
  const auto r = s.summary();
  EXPECT_DOUBLE_EQ(r.p50_ms, 50.0);
  EXPECT_DOUBLE_EQ(r.p99_ms, 99.0);
  EXPECT_DOUBLE_EQ(r.max_ms, 100.0);
  EXPECT_DOUBLE_EQ(r.mean_ms, 50.5);
  EXPECT_DOUBLE_EQ(FrameStats::quantile({3.0}, 0.99), 3.0);
  EXPECT_DOUBLE_EQ(FrameStats::quantile({}, 0.5), 0.0);
  const auto empty = FrameStats().summary();
  EXPECT_EQ(empty.published, 0);
  EXPECT_DOUBLE_EQ(empty.p99_ms, 0.0);
}
