/**
 * @file frame_accounting.h
 * @brief The nodelet's frame accounting (private to the nodelet library, ROS-free): every colour
 * image received is, at any time, in exactly one state (processed, dropped by reason, skipped,
 * not synchronised, waiting), so that the diagnostics can show
 *   received == processed + dropped + skipped + not synchronised + waiting.
 * See docs/NODELET.md, "Frame accounting".
 */
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>

namespace rgbd_lane_detector {

/// What became of one set emitted by the synchroniser.
enum class FrameOutcome : uint8_t {
  kProcessed,          ///< the outputs were published
  kSkipped,            ///< emitted after the last output subscriber left (queued before)
  kBadMessage,         ///< a message the conversions refuse (encoding, step, sizes)
  kInvalidFrame,       ///< the core refused the frame (its Status)
  kNoUpTransform,      ///< no transform from up_frame
  kNoTargetTransform,  ///< no transform to target_frame
  kDetectorException,  ///< detect() threw (never expected: the frame was validated)
};

/**
 * @brief Static description of an outcome ("processed", "no transform to target_frame"...).
 * @param[in] outcome any outcome
 * @return static text, never null
 */
const char* outcomeText(FrameOutcome outcome);

/**
 * @brief Counts every colour image from its arrival to its fate, without heap allocation.
 *
 * Colour images are kept (identity and stamp) in a fixed ring in arrival order until the
 * synchroniser emits them or a later one: both message_filters synchronisers emit each topic's
 * messages in arrival order and discard the ones they pass over, so when a set is emitted the
 * entries received before its colour image were not synchronised and the ones after it are
 * still waiting. Thread-safe: every member function takes the internal mutex.
 */
class FrameAccounting {
 public:
  static constexpr size_t kPendingCapacity = 256;  ///< colour images tracked while waiting
  static constexpr size_t kMaxDropReasons = 24;    ///< the last slot counts every further reason
  static constexpr size_t kReasonLength = 112;     ///< characters kept of a drop reason (with NUL)

  /// Frames dropped for one reason (its text, copied).
  struct DropCount {
    char reason[kReasonLength] = {};
    uint64_t count = 0;
  };

  /// Cumulative counters, and the window since the previous report().
  struct Report {
    uint64_t received = 0;           ///< colour images received
    uint64_t synchronised = 0;       ///< sets emitted by the synchroniser
    uint64_t processed = 0;          ///< sets that produced the outputs
    uint64_t dropped = 0;            ///< sets dropped (the sum of the per-reason counts)
    uint64_t skipped = 0;            ///< sets emitted after the last output subscriber left
    uint64_t not_synchronised = 0;   ///< received, then passed over by the synchroniser
    uint64_t waiting = 0;            ///< received after the last emitted set
    uint64_t ring_overflow = 0;      ///< part of not_synchronised: evicted from the full ring
    uint64_t late_synchronised = 0;  ///< emitted after being counted as not synchronised
    uint64_t untracked = 0;          ///< emitted but never received (never expected)
    uint64_t lost_before = 0;        ///< gaps in the colour header.seq
    uint64_t depth_received = 0;     ///< depth images received
    uint64_t depth_lost_before = 0;  ///< gaps in the depth header.seq
    uint64_t info_received = 0;      ///< camera_infos received
    uint64_t info_lost_before = 0;   ///< gaps in the camera_info header.seq
    size_t drop_reasons = 0;         ///< used entries of drops
    DropCount drops[kMaxDropReasons];
    char last_drop[kReasonLength] = {};  ///< reason of the latest drop ("" if none)
    uint64_t window_processed = 0;       ///< processed in the window
    uint64_t window_dropped = 0;         ///< dropped in the window
    double window_callback_ms = 0.0;     ///< sum of whole-callback times in the window
    double window_detect_ms = 0.0;       ///< sum of core detect() times in the window
    double window_max_ms = 0.0;          ///< slowest callback in the window
    /// Largest CPU time of a callback's thread in the window: far below window_max_ms, the
    /// slowest callback waited for a core (other processes, threads) rather than computed
    double window_max_cpu_ms = 0.0;
    /// Longest time a camera_info waited between its arrival at the node (receipt) and its
    /// subscriber callback in the window. The three inputs share the nodelet's callback queue,
    /// so this is how far the callbacks ran behind: near queue_size frame periods, the subscriber
    /// queues were full and dropped their oldest messages; near 0 while images were lost before
    /// the nodelet, they were lost upstream (publisher queue, transport). (image_transport gives
    /// the image callbacks no receipt time.)
    double window_max_info_wait_ms = 0.0;

    /// @return received minus every state it is split into (0 when the rule holds)
    int64_t unaccounted() const;
  };

  /**
   * @brief A colour image reached the nodelet (called before the synchroniser sees it).
   * @param[in] id identity of the message (its address; only compared, never dereferenced)
   * @param[in] stamp_ns its header stamp in nanoseconds
   * @param[in] seq its header.seq: gaps while subscribed are images lost before the nodelet
   */
  void received(const void* id, int64_t stamp_ns, uint32_t seq);

  /**
   * @brief A depth image reached the nodelet: counted, and gaps in its header.seq are depth
   * images lost before the nodelet (a colour image whose depth was lost cannot be synchronised).
   * @param[in] seq its header.seq
   */
  void depthReceived(uint32_t seq);

  /**
   * @brief A camera_info reached the nodelet: counted as depthReceived() does.
   * @param[in] seq its header.seq
   * @param[in] queue_wait_ms time it waited in the callback queue (receipt to callback)
   */
  void cameraInfoReceived(uint32_t seq, double queue_wait_ms);

  /// The inputs were (re)subscribed: seq gaps across the unsubscribed period are not losses.
  void restartSequence();

  /**
   * @brief The synchroniser emitted the set whose colour image is @p id, and this was its fate.
   * @param[in] id identity of the colour message, as given to received()
   * @param[in] stamp_ns its header stamp in nanoseconds
   * @param[in] outcome processed, skipped or the drop's kind
   * @param[in] detail drop reason text (kBadMessage, kInvalidFrame); null or "" = outcomeText()
   * @param[in] callback_ms time of the whole frame callback (processed frames)
   * @param[in] detect_ms time of the core's detect() (processed frames)
   * @param[in] callback_cpu_ms CPU time of the callback's thread during it (processed frames)
   */
  void synchronised(const void* id, int64_t stamp_ns, FrameOutcome outcome,
                    const char* detail = nullptr, double callback_ms = 0.0, double detect_ms = 0.0,
                    double callback_cpu_ms = 0.0);

  /**
   * @brief The counters now; starts a new window.
   * @return cumulative counters and the window since the previous call
   */
  Report report();

 private:
  struct Pending {
    const void* id = nullptr;
    int64_t stamp_ns = 0;
  };
  Pending& pendingAt(size_t k) { return pending_[(pending_head_ + k) % kPendingCapacity]; }
  void countDrop(const char* reason);

  /// One input's header.seq run: gaps between consecutive seq are messages lost before the node.
  struct SequenceRun {
    bool restart = true;  ///< the next seq starts a run (first message, resubscription)
    uint32_t last = 0;
    /// @return the messages missing before @p seq (0 at a restart or a seq that did not increase)
    uint64_t gapBefore(uint32_t seq);
  };

  std::mutex mutex_;
  Report counts_;  ///< guarded by mutex_; waiting is pending_count_
  SequenceRun colour_seq_, depth_seq_, info_seq_;
  Pending pending_[kPendingCapacity];  ///< ring in arrival order
  size_t pending_head_ = 0, pending_count_ = 0;
};

}  // namespace rgbd_lane_detector
