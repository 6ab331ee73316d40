// Unit tests of the nodelet's jump-back-in-time detection (ROS-free;
// src/ros/stamp_jump_detector.h).
#include <cstdint>

#include <gtest/gtest.h>

#include "../../src/ros/stamp_jump_detector.h"

namespace rgbd_lane_detector {
namespace {

constexpr int64_t kS = 1000000000;  // ns per s
using Verdict = StampJumpDetector::Verdict;

TEST(StampJumpDetector, IncreasingStampsAreNoJump) {
  StampJumpDetector d(3);
  for (int64_t t = 0; t < 50; ++t)
    for (size_t i = 0; i < 3; ++i)
      EXPECT_EQ(Verdict::kCurrent, d.update(i, 100 * kS + t * kS / 10));
  EXPECT_EQ(d.jumps(), 0u);
  EXPECT_EQ(d.lastJumpNs(), 0);
  // a repeated stamp (a resent frame) is no jump either
  EXPECT_EQ(Verdict::kCurrent, d.update(0, 100 * kS + 49 * kS / 10));
}

TEST(StampJumpDetector, ALoopIsReportedOnceWhicheverInputShowsItFirst) {
  StampJumpDetector d(3);
  const int64_t start = 1700 * kS, end = start + 5 * kS;
  for (size_t i = 0; i < 3; ++i) d.update(i, start);
  for (size_t i = 0; i < 3; ++i) d.update(i, end);
  // the bag starts again: depth arrives first, then colour and camera_info
  EXPECT_EQ(Verdict::kJump, d.update(1, start));
  EXPECT_EQ(d.lastJumpNs(), 5 * kS);
  EXPECT_EQ(Verdict::kCurrent, d.update(0, start)) << "the same jump, seen on a second input";
  EXPECT_EQ(Verdict::kCurrent, d.update(2, start));
  EXPECT_EQ(d.jumps(), 1u);
  // the second loop goes on, then starts again: one more jump
  for (size_t i = 0; i < 3; ++i) EXPECT_EQ(Verdict::kCurrent, d.update(i, end));
  EXPECT_EQ(Verdict::kJump, d.update(0, start));
  EXPECT_EQ(Verdict::kCurrent, d.update(2, start));
  EXPECT_EQ(Verdict::kCurrent, d.update(1, start));
  EXPECT_EQ(d.jumps(), 2u);
}

TEST(StampJumpDetector, LateMessagesFromBeforeTheJumpAreStale) {
  StampJumpDetector d(2);
  d.update(0, 10 * kS);
  d.update(1, 10 * kS);
  EXPECT_EQ(Verdict::kJump, d.update(0, 2 * kS));  // colour loops back first
  // camera_info still delivers the end of the previous loop (stale), then loops back itself
  EXPECT_EQ(Verdict::kStale, d.update(1, 11 * kS));
  EXPECT_EQ(Verdict::kCurrent, d.update(1, 2 * kS));
  EXPECT_EQ(Verdict::kCurrent, d.update(0, 3 * kS));
  EXPECT_EQ(Verdict::kCurrent, d.update(1, 3 * kS));
  EXPECT_EQ(d.jumps(), 1u);
}

TEST(StampJumpDetector, AnInputThatNeverLoopsJoinsAfterMaxStaleMessages) {
  StampJumpDetector d(2, 3);
  int64_t live = 0;  // input 1: a live stream whose stamps only increase
  d.update(0, 5 * kS);
  d.update(1, live += kS);
  EXPECT_EQ(Verdict::kJump, d.update(0, 1 * kS));
  EXPECT_EQ(Verdict::kStale, d.update(1, live += kS));
  EXPECT_EQ(Verdict::kStale, d.update(1, live += kS));
  EXPECT_EQ(Verdict::kCurrent, d.update(1, live += kS)) << "third message in a row: joins";
  EXPECT_EQ(Verdict::kCurrent, d.update(1, live += kS));
  // input 0 loops again: a new jump; input 1 is behind again for up to 2 messages
  EXPECT_EQ(Verdict::kCurrent, d.update(0, 5 * kS));
  EXPECT_EQ(Verdict::kJump, d.update(0, 1 * kS));
  EXPECT_EQ(d.lastJumpNs(), 4 * kS);
  EXPECT_EQ(Verdict::kStale, d.update(1, live += kS));
  EXPECT_EQ(d.jumps(), 2u);
}

TEST(StampJumpDetector, AnInputSeenFirstAfterAJumpJoinsTheCurrentEpoch) {
  StampJumpDetector d(3);
  d.update(0, 9 * kS);
  EXPECT_EQ(Verdict::kJump, d.update(0, 1 * kS));
  EXPECT_EQ(Verdict::kCurrent, d.update(2, 1 * kS));  // first message of input 2
  EXPECT_EQ(Verdict::kCurrent, d.update(2, 2 * kS));
  EXPECT_EQ(Verdict::kJump, d.update(2, 1 * kS)) << "input 2 was in the current epoch";
}

// A driver's clock jittering back by a millisecond, or a message overtaken on the way, is no loop:
// that message is out of order (dropped), nothing restarts, and the next ones are current. Half a
// second back (kMinJumpNs) is a jump.
TEST(StampJumpDetector, AStepBackShorterThanAJumpIsOutOfOrder) {
  StampJumpDetector d(2);
  const int64_t ms = kS / 1000;
  d.update(0, 10 * kS);
  d.update(1, 10 * kS);
  EXPECT_EQ(Verdict::kOutOfOrder, d.update(0, 10 * kS - ms));
  EXPECT_EQ(d.lastOutOfOrderNs(), ms);
  EXPECT_EQ(Verdict::kOutOfOrder, d.update(0, 10 * kS - 499 * ms)) << "against the latest stamp";
  EXPECT_EQ(d.jumps(), 0u);
  EXPECT_EQ(Verdict::kCurrent, d.update(0, 10 * kS + 33 * ms));
  EXPECT_EQ(Verdict::kCurrent, d.update(1, 10 * kS + 33 * ms));
  EXPECT_EQ(Verdict::kJump, d.update(1, 10 * kS + 33 * ms - StampJumpDetector::kMinJumpNs));
  EXPECT_EQ(d.lastJumpNs(), StampJumpDetector::kMinJumpNs);
  EXPECT_EQ(d.jumps(), 1u);
}

TEST(StampJumpDetector, UnknownInputsAreIgnored) {
  StampJumpDetector d(1);
  EXPECT_EQ(Verdict::kCurrent, d.update(5, 3 * kS));
  EXPECT_EQ(Verdict::kCurrent, d.update(5, 1 * kS));
  EXPECT_EQ(d.jumps(), 0u);
}

}  // namespace
}  // namespace rgbd_lane_detector
