/**
 * @file stamp_jump_detector.h
 * @brief Notices the input stamps going back (rosbag loop, a camera clock restarting) once per
 * jump across several synchronised inputs (private to the nodelet library, ROS-free).
 */
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rgbd_lane_detector {

/**
 * @brief Reports a jump back in time once, whichever input shows it first.
 *
 * Each input's stamps increase while its stream runs. When one input's stamp goes back, a new
 * epoch starts (reported). The other inputs still in the previous epoch join the new one when
 * their own stamps go back (the same jump, not reported again); until then their messages are
 * late ones from before the jump (stale: to be dropped, they would pair with nothing). An input
 * that stays behind for max_stale messages in a row joins anyway (a stream that never loops).
 * An input already in the current epoch that goes back starts the next epoch. A stamp less than
 * min_jump before its input's latest is no jump: a message out of order (a driver's clock
 * jittering back by a millisecond, a message overtaken on the way), to be dropped; a loop of a bag
 * or a camera clock restarting goes back by seconds.
 */
class StampJumpDetector {
 public:
  /// What a message is to the current epoch.
  enum class Verdict {
    kCurrent,  ///< of the current epoch: pass it on
    kJump,     ///< it starts a new epoch (time went back): reset what depends on time, pass it on
    kStale,    ///< a late message from before the last jump: drop it
    kOutOfOrder,  ///< behind its input's latest stamp by less than min_jump: drop it
  };

  /// The default min_jump: 0.5 s back is a jump (a bag's loop, a clock restart), less is jitter.
  static constexpr int64_t kMinJumpNs = 500000000;

  /**
   * @param[in] inputs number of input streams (indices 0 .. inputs - 1)
   * @param[in] max_stale messages in a row an input may stay behind before it joins anyway
   * @param[in] min_jump_ns how far (ns) a stamp must go back to be a jump (kMinJumpNs)
   */
  explicit StampJumpDetector(size_t inputs, size_t max_stale = 10,
                             int64_t min_jump_ns = kMinJumpNs);

  /**
   * @brief One message's stamp.
   * @param[in] input index of the input stream (an unknown index is always current)
   * @param[in] stamp_ns the message's stamp in nanoseconds
   * @return what the message is to the current epoch
   */
  Verdict update(size_t input, int64_t stamp_ns);

  /// @return how far (ns) the stamps went back at the last reported jump (0 before any)
  int64_t lastJumpNs() const { return last_jump_ns_; }

  /// @return number of jumps reported so far
  uint64_t jumps() const { return epoch_; }

  /// @return how far (ns) the last message out of order was behind its input's latest stamp
  int64_t lastOutOfOrderNs() const { return last_out_of_order_ns_; }

 private:
  struct Input {
    bool seen = false;
    int64_t last_ns = 0;
    uint64_t epoch = 0;
    size_t stale = 0;  ///< messages in a row behind the current epoch
  };
  std::vector<Input> inputs_;
  size_t max_stale_;
  int64_t min_jump_ns_;
  uint64_t epoch_ = 0;
  int64_t last_jump_ns_ = 0;
  int64_t last_out_of_order_ns_ = 0;
};

}  // namespace rgbd_lane_detector
