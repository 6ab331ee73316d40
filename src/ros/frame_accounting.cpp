#include "frame_accounting.h"

#include <algorithm>
#include <cstring>

namespace rgbd_lane_detector {
namespace {

constexpr char kOtherReasons[] = "other reasons";  // drop-reason table full

void copyText(char (&to)[FrameAccounting::kReasonLength], const char* from) {
  std::strncpy(to, from, FrameAccounting::kReasonLength - 1);
  to[FrameAccounting::kReasonLength - 1] = '\0';
}

}  // namespace

const char* outcomeText(FrameOutcome outcome) {
  switch (outcome) {
    case FrameOutcome::kProcessed:
      return "processed";
    case FrameOutcome::kSkipped:
      return "skipped: no output subscriber";
    case FrameOutcome::kBadMessage:
      return "bad input message";
    case FrameOutcome::kInvalidFrame:
      return "frame refused by the detector";
    case FrameOutcome::kNoUpTransform:
      return "no transform from up_frame";
    case FrameOutcome::kNoTargetTransform:
      return "no transform to target_frame";
    case FrameOutcome::kDetectorException:
      return "detector exception";
  }
  return "unknown outcome";
}

int64_t FrameAccounting::Report::unaccounted() const {
  return static_cast<int64_t>(received) -
         static_cast<int64_t>(processed + dropped + skipped + not_synchronised + waiting);
}

uint64_t FrameAccounting::SequenceRun::gapBefore(uint32_t seq) {
  // Messages lost before the nodelet (transport, publisher or full subscriber queue): gaps in
  // header.seq, which publishers number per message sent. A run restarts at each
  // (re)subscription; a seq that does not increase (restarted publisher, publishers leaving seq
  // at 0) counts nothing.
  const uint64_t gap = !restart && seq > last ? seq - last - 1 : 0;
  restart = false;
  last = seq;
  return gap;
}

void FrameAccounting::depthReceived(uint32_t seq) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counts_.depth_received;
  counts_.depth_lost_before += depth_seq_.gapBefore(seq);
}

void FrameAccounting::cameraInfoReceived(uint32_t seq, double queue_wait_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counts_.info_received;
  counts_.info_lost_before += info_seq_.gapBefore(seq);
  counts_.window_max_info_wait_ms = std::max(counts_.window_max_info_wait_ms, queue_wait_ms);
}

void FrameAccounting::received(const void* id, int64_t stamp_ns, uint32_t seq) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counts_.received;
  counts_.lost_before += colour_seq_.gapBefore(seq);
  // Pending until the synchroniser emits it or a later image. The synchronisers hold at most
  // queue_size images per topic, so one evicted from the full ring was dropped there.
  if (pending_count_ == kPendingCapacity) {
    pending_head_ = (pending_head_ + 1) % kPendingCapacity;
    --pending_count_;
    ++counts_.not_synchronised;
    ++counts_.ring_overflow;
  }
  Pending& p = pendingAt(pending_count_);
  p.id = id;
  p.stamp_ns = stamp_ns;
  ++pending_count_;
}

void FrameAccounting::restartSequence() {
  std::lock_guard<std::mutex> lock(mutex_);
  colour_seq_.restart = depth_seq_.restart = info_seq_.restart = true;
}

void FrameAccounting::synchronised(const void* id, int64_t stamp_ns, FrameOutcome outcome,
                                   const char* detail, double callback_ms, double detect_ms,
                                   double callback_cpu_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  Report& c = counts_;
  ++c.synchronised;
  // Every pending image received before this one was passed over by the synchroniser.
  size_t i = 0;
  while (i < pending_count_ && !(pendingAt(i).id == id && pendingAt(i).stamp_ns == stamp_ns)) ++i;
  if (i == pending_count_) {  // same stamp, another message object (never expected)
    i = 0;
    while (i < pending_count_ && pendingAt(i).stamp_ns != stamp_ns) ++i;
  }
  if (i < pending_count_) {
    c.not_synchronised += i;
    pending_head_ = (pending_head_ + i + 1) % kPendingCapacity;
    pending_count_ -= i + 1;
  } else if (c.not_synchronised > 0) {  // counted as passed over before (ring overflow, ExactTime
    --c.not_synchronised;               // emitting an older stamp after a newer one)
    ++c.late_synchronised;
  } else {
    ++c.untracked;
  }

  switch (outcome) {
    case FrameOutcome::kProcessed:
      ++c.processed;
      ++c.window_processed;
      c.window_callback_ms += callback_ms;
      c.window_detect_ms += detect_ms;
      c.window_max_ms = std::max(c.window_max_ms, callback_ms);
      c.window_max_cpu_ms = std::max(c.window_max_cpu_ms, callback_cpu_ms);
      return;
    case FrameOutcome::kSkipped:
      ++c.skipped;
      return;
    default:
      countDrop(detail != nullptr && detail[0] != '\0' ? detail : outcomeText(outcome));
  }
}

void FrameAccounting::countDrop(const char* reason) {
  Report& c = counts_;
  ++c.dropped;
  ++c.window_dropped;
  copyText(c.last_drop, reason);
  // the table compares texts (truncated as stored); the last slot takes every further reason
  DropCount* slot = nullptr;
  for (size_t k = 0; k < c.drop_reasons && slot == nullptr; ++k)
    if (std::strncmp(c.drops[k].reason, reason, kReasonLength - 1) == 0) slot = &c.drops[k];
  if (slot == nullptr && c.drop_reasons < kMaxDropReasons - 1) {
    slot = &c.drops[c.drop_reasons++];
    copyText(slot->reason, reason);
  }
  if (slot == nullptr) {
    slot = &c.drops[kMaxDropReasons - 1];
    if (c.drop_reasons < kMaxDropReasons) {
      c.drop_reasons = kMaxDropReasons;
      copyText(slot->reason, kOtherReasons);
    }
  }
  ++slot->count;
}

FrameAccounting::Report FrameAccounting::report() {
  std::lock_guard<std::mutex> lock(mutex_);
  Report r = counts_;
  r.waiting = pending_count_;
  counts_.window_processed = counts_.window_dropped = 0;
  counts_.window_callback_ms = counts_.window_detect_ms = counts_.window_max_ms = 0.0;
  counts_.window_max_cpu_ms = counts_.window_max_info_wait_ms = 0.0;
  return r;
}

}  // namespace rgbd_lane_detector
