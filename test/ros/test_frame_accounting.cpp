// Unit tests of the nodelet's frame accounting (ROS-free; src/ros/frame_accounting.h).
#include <cstdint>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "../../src/ros/frame_accounting.h"

namespace rgbd_lane_detector {
namespace {

using Report = FrameAccounting::Report;

/// Distinct identities for fake messages (only compared, never dereferenced).
const void* idOf(size_t i) {
  static std::vector<char> storage(1 << 16);
  return &storage[i % storage.size()];
}

uint64_t reasonCount(const Report& r, const std::string& reason) {
  for (size_t k = 0; k < r.drop_reasons; ++k)
    if (reason == r.drops[k].reason) return r.drops[k].count;
  return 0;
}

uint64_t sumOfReasons(const Report& r) {
  uint64_t sum = 0;
  for (size_t k = 0; k < r.drop_reasons; ++k) sum += r.drops[k].count;
  return sum;
}

TEST(FrameAccounting, ProcessedFramesAreCountedWithTheirTimes) {
  FrameAccounting a;
  for (size_t i = 0; i < 3; ++i) {
    a.received(idOf(i), 1000 + i, static_cast<uint32_t>(i));
    a.synchronised(idOf(i), 1000 + i, FrameOutcome::kProcessed, nullptr, 2.0 + i, 1.0,
                   i == 1 ? 3.5 : 1.5);
  }
  const Report r = a.report();
  EXPECT_EQ(r.received, 3u);
  EXPECT_EQ(r.synchronised, 3u);
  EXPECT_EQ(r.processed, 3u);
  EXPECT_EQ(r.waiting, 0u);
  EXPECT_EQ(r.unaccounted(), 0);
  EXPECT_EQ(r.window_processed, 3u);
  EXPECT_DOUBLE_EQ(r.window_callback_ms, 2.0 + 3.0 + 4.0);
  EXPECT_DOUBLE_EQ(r.window_detect_ms, 3.0);
  EXPECT_DOUBLE_EQ(r.window_max_ms, 4.0);
  // the largest CPU time, whichever callback it was (not the slowest one's: that one waited)
  EXPECT_DOUBLE_EQ(r.window_max_cpu_ms, 3.5);
  // the next report starts a new window and keeps the cumulative counters
  const Report next = a.report();
  EXPECT_EQ(next.processed, 3u);
  EXPECT_EQ(next.window_processed, 0u);
  EXPECT_DOUBLE_EQ(next.window_callback_ms, 0.0);
  EXPECT_DOUBLE_EQ(next.window_max_ms, 0.0);
  EXPECT_DOUBLE_EQ(next.window_max_cpu_ms, 0.0);
}

TEST(FrameAccounting, ImagesPassedOverAreNotSynchronisedAndLaterOnesWait) {
  FrameAccounting a;
  for (size_t i = 0; i < 5; ++i) a.received(idOf(i), 100 * i, static_cast<uint32_t>(i));
  a.synchronised(idOf(2), 200, FrameOutcome::kProcessed);  // 0 and 1 were passed over
  Report r = a.report();
  EXPECT_EQ(r.not_synchronised, 2u);
  EXPECT_EQ(r.waiting, 2u);  // 3 and 4
  EXPECT_EQ(r.unaccounted(), 0);
  a.synchronised(idOf(4), 400, FrameOutcome::kSkipped);
  r = a.report();
  EXPECT_EQ(r.not_synchronised, 3u);
  EXPECT_EQ(r.skipped, 1u);
  EXPECT_EQ(r.waiting, 0u);
  EXPECT_EQ(r.unaccounted(), 0);
}

TEST(FrameAccounting, DropReasonsAreComparedByTextNotByAddress) {
  FrameAccounting a;
  // the same reason from two different buffers (e.g. a copied string) shares one count
  const std::string first = "unsupported colour encoding";
  const std::string second = first;
  ASSERT_NE(first.c_str(), second.c_str());
  a.received(idOf(0), 1, 0);
  a.synchronised(idOf(0), 1, FrameOutcome::kBadMessage, first.c_str());
  a.received(idOf(1), 2, 1);
  a.synchronised(idOf(1), 2, FrameOutcome::kBadMessage, second.c_str());
  // without a detail, the outcome's own text is the reason
  a.received(idOf(2), 3, 2);
  a.synchronised(idOf(2), 3, FrameOutcome::kNoTargetTransform);
  a.received(idOf(3), 4, 3);
  a.synchronised(idOf(3), 4, FrameOutcome::kDetectorException, "");
  const Report r = a.report();
  EXPECT_EQ(r.dropped, 4u);
  EXPECT_EQ(r.window_dropped, 4u);
  EXPECT_EQ(r.drop_reasons, 3u);
  EXPECT_EQ(reasonCount(r, first), 2u);
  EXPECT_EQ(reasonCount(r, outcomeText(FrameOutcome::kNoTargetTransform)), 1u);
  EXPECT_EQ(reasonCount(r, outcomeText(FrameOutcome::kDetectorException)), 1u);
  EXPECT_STREQ(r.last_drop, outcomeText(FrameOutcome::kDetectorException));
  EXPECT_EQ(r.processed, 0u);
  EXPECT_EQ(r.unaccounted(), 0);
}

TEST(FrameAccounting, EveryOutcomeHasItsOwnText) {
  const FrameOutcome all[] = {FrameOutcome::kProcessed,        FrameOutcome::kSkipped,
                              FrameOutcome::kBadMessage,       FrameOutcome::kInvalidFrame,
                              FrameOutcome::kNoUpTransform,    FrameOutcome::kNoTargetTransform,
                              FrameOutcome::kDetectorException};
  for (size_t i = 0; i < sizeof(all) / sizeof(all[0]); ++i)
    for (size_t j = i + 1; j < sizeof(all) / sizeof(all[0]); ++j)
      EXPECT_STRNE(outcomeText(all[i]), outcomeText(all[j]));
}

TEST(FrameAccounting, AFullReasonTableCountsFurtherReasonsAsOther) {
  FrameAccounting a;
  const size_t distinct = FrameAccounting::kMaxDropReasons + 6;
  for (size_t i = 0; i < distinct; ++i) {
    const std::string reason = "reason " + std::to_string(i);
    for (size_t k = 0; k <= i % 3; ++k) {  // 1-3 frames each
      a.received(idOf(i * 3 + k), static_cast<int64_t>(i * 3 + k), 0);
      a.synchronised(idOf(i * 3 + k), static_cast<int64_t>(i * 3 + k), FrameOutcome::kInvalidFrame,
                     reason.c_str());
    }
  }
  const Report r = a.report();
  EXPECT_EQ(r.drop_reasons, FrameAccounting::kMaxDropReasons);
  EXPECT_STREQ(r.drops[FrameAccounting::kMaxDropReasons - 1].reason, "other reasons");
  // the first kMaxDropReasons - 1 reasons keep their own counts
  for (size_t i = 0; i + 1 < FrameAccounting::kMaxDropReasons; ++i)
    EXPECT_EQ(reasonCount(r, "reason " + std::to_string(i)), i % 3 + 1) << i;
  EXPECT_EQ(sumOfReasons(r), r.dropped);
  EXPECT_EQ(r.unaccounted(), 0);
}

TEST(FrameAccounting, LongReasonsAreTruncatedConsistently) {
  FrameAccounting a;
  const std::string base(FrameAccounting::kReasonLength + 20, 'x');
  const std::string a_reason = base + "a", b_reason = base + "b";  // equal as stored
  a.received(idOf(0), 1, 0);
  a.synchronised(idOf(0), 1, FrameOutcome::kBadMessage, a_reason.c_str());
  a.received(idOf(1), 2, 1);
  a.synchronised(idOf(1), 2, FrameOutcome::kBadMessage, b_reason.c_str());
  const Report r = a.report();
  ASSERT_EQ(r.drop_reasons, 1u);
  EXPECT_EQ(r.drops[0].count, 2u);
  EXPECT_EQ(std::string(r.drops[0].reason).size(), FrameAccounting::kReasonLength - 1);
}

TEST(FrameAccounting, SequenceGapsAreImagesLostBeforeTheNodelet) {
  FrameAccounting a;
  size_t n = 0;
  const auto receive = [&](uint32_t seq) {
    a.received(idOf(n), static_cast<int64_t>(n), seq);
    ++n;
  };
  for (uint32_t s : {10u, 11u, 14u, 15u}) receive(s);  // 12 and 13 lost
  EXPECT_EQ(a.report().lost_before, 2u);
  // a publisher that restarts numbers from 0 again: no loss
  receive(0);
  receive(1);
  EXPECT_EQ(a.report().lost_before, 2u);
  // a resubscription starts a new run: the gap across it is not a loss
  a.restartSequence();
  receive(50);
  receive(52);
  EXPECT_EQ(a.report().lost_before, 3u);
}

TEST(FrameAccounting, DepthAndCameraInfoGapsAreCountedPerInput) {
  FrameAccounting a;
  // colour complete, depth missing 3 and 4, camera_info missing 2
  for (uint32_t s = 1; s <= 6; ++s) a.received(idOf(s), static_cast<int64_t>(s), s);
  for (uint32_t s : {1u, 2u, 5u, 6u}) a.depthReceived(s);
  for (uint32_t s : {1u, 3u, 4u, 5u, 6u}) a.cameraInfoReceived(s, 0.0);
  Report r = a.report();
  EXPECT_EQ(r.received, 6u);
  EXPECT_EQ(r.lost_before, 0u);
  EXPECT_EQ(r.depth_received, 4u);
  EXPECT_EQ(r.depth_lost_before, 2u);
  EXPECT_EQ(r.info_received, 5u);
  EXPECT_EQ(r.info_lost_before, 1u);
  EXPECT_EQ(r.unaccounted(), 0) << "depth and camera_info are not colour frames";
  // each input's run restarts at a resubscription: the gaps across it are not losses
  a.restartSequence();
  a.depthReceived(40);
  a.cameraInfoReceived(90, 0.0);
  a.depthReceived(42);
  r = a.report();
  EXPECT_EQ(r.depth_lost_before, 3u);
  EXPECT_EQ(r.info_lost_before, 1u);
}

TEST(FrameAccounting, TheLongestCameraInfoWaitIsPerWindow) {
  FrameAccounting a;
  a.cameraInfoReceived(0, 7.0);
  a.cameraInfoReceived(1, 40.0);
  a.cameraInfoReceived(2, 2.5);
  EXPECT_DOUBLE_EQ(a.report().window_max_info_wait_ms, 40.0);
  a.cameraInfoReceived(3, 3.0);
  EXPECT_DOUBLE_EQ(a.report().window_max_info_wait_ms, 3.0) << "a new window starts empty";
  EXPECT_DOUBLE_EQ(a.report().window_max_info_wait_ms, 0.0);
}

TEST(FrameAccounting, RingOverflowAndLateEmissionKeepTheRule) {
  FrameAccounting a;
  const size_t n = FrameAccounting::kPendingCapacity + 44;
  for (size_t i = 0; i < n; ++i) a.received(idOf(i), static_cast<int64_t>(i), 0);
  Report r = a.report();
  EXPECT_EQ(r.ring_overflow, 44u);
  EXPECT_EQ(r.not_synchronised, 44u);
  EXPECT_EQ(r.waiting, FrameAccounting::kPendingCapacity);
  EXPECT_EQ(r.unaccounted(), 0);
  // an evicted image emitted after all: moved from not synchronised to synchronised late
  a.synchronised(idOf(3), 3, FrameOutcome::kProcessed);
  r = a.report();
  EXPECT_EQ(r.late_synchronised, 1u);
  EXPECT_EQ(r.not_synchronised, 43u);
  EXPECT_EQ(r.processed, 1u);
  EXPECT_EQ(r.unaccounted(), 0);
}

TEST(FrameAccounting, AnImageNeverReceivedIsUntracked) {
  FrameAccounting a;
  a.synchronised(idOf(7), 7, FrameOutcome::kProcessed);
  const Report r = a.report();
  EXPECT_EQ(r.untracked, 1u);
  EXPECT_EQ(r.processed, 1u);
  EXPECT_EQ(r.unaccounted(), -1) << "an untracked set is one more than was received";
}

TEST(FrameAccounting, SameStampFromAnotherMessageObjectIsMatchedByStamp) {
  FrameAccounting a;
  a.received(idOf(0), 10, 0);
  a.received(idOf(1), 20, 1);
  a.received(idOf(2), 30, 2);
  a.synchronised(idOf(99), 20, FrameOutcome::kProcessed);  // a copy of the second image
  const Report r = a.report();
  EXPECT_EQ(r.not_synchronised, 1u);
  EXPECT_EQ(r.waiting, 1u);
  EXPECT_EQ(r.untracked, 0u);
  EXPECT_EQ(r.unaccounted(), 0);
}

// A simulated synchroniser: images arrive, some sets are emitted (in arrival order, passing over
// the ones before), with every outcome; the rule holds after every step.
TEST(FrameAccounting, TheRuleHoldsThroughARandomStream) {
  FrameAccounting a;
  std::mt19937 rng(7);
  std::vector<size_t> queue;  // images the simulated synchroniser still holds, in arrival order
  size_t next = 0;
  uint32_t seq = 0;
  const FrameOutcome outcomes[] = {FrameOutcome::kProcessed, FrameOutcome::kSkipped,
                                   FrameOutcome::kBadMessage, FrameOutcome::kInvalidFrame,
                                   FrameOutcome::kNoUpTransform};
  uint64_t lost = 0;
  for (int step = 0; step < 5000; ++step) {
    if (rng() % 3 != 0) {
      if (rng() % 10 == 0) {  // an image lost before the nodelet
        ++seq;
        ++lost;
      }
      a.received(idOf(next), static_cast<int64_t>(next), seq++);
      queue.push_back(next++);
    } else if (!queue.empty()) {
      const size_t k = rng() % std::min<size_t>(queue.size(), 4);  // pass over up to 3
      const size_t img = queue[k];
      queue.erase(queue.begin(), queue.begin() + static_cast<long>(k) + 1);
      a.synchronised(idOf(img), static_cast<int64_t>(img), outcomes[rng() % 5], "bad");
    }
    if (step % 97 == 0) {
      const Report r = a.report();
      ASSERT_EQ(r.unaccounted(), 0) << "step " << step;
      ASSERT_EQ(sumOfReasons(r), r.dropped);
      ASSERT_EQ(r.waiting, queue.size());
      ASSERT_EQ(r.lost_before, lost);
      ASSERT_EQ(r.untracked, 0u);
    }
  }
}

TEST(FrameAccounting, ConcurrentReportsSeeAConsistentState) {
  FrameAccounting a;
  constexpr size_t kFrames = 20000;
  std::thread frames([&] {
    for (size_t i = 0; i < kFrames; ++i) {
      a.received(idOf(i), static_cast<int64_t>(i), static_cast<uint32_t>(i));
      if (i % 2 == 1) a.synchronised(idOf(i), static_cast<int64_t>(i), FrameOutcome::kProcessed);
    }
  });
  bool consistent = true;
  for (int k = 0; k < 2000; ++k) consistent = consistent && a.report().unaccounted() == 0;
  frames.join();
  EXPECT_TRUE(consistent);
  const Report r = a.report();
  EXPECT_EQ(r.received, kFrames);
  EXPECT_EQ(r.processed, kFrames / 2);
  EXPECT_EQ(r.not_synchronised, kFrames / 2);
}

}  // namespace
}  // namespace rgbd_lane_detector
