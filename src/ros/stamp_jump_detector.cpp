#include "stamp_jump_detector.h"

namespace rgbd_lane_detector {

StampJumpDetector::StampJumpDetector(size_t inputs, size_t max_stale, int64_t min_jump_ns)
    : inputs_(inputs), max_stale_(max_stale), min_jump_ns_(min_jump_ns) {}

StampJumpDetector::Verdict StampJumpDetector::update(size_t input, int64_t stamp_ns) {
  if (input >= inputs_.size()) return Verdict::kCurrent;
  Input& in = inputs_[input];
  Verdict verdict = Verdict::kCurrent;
  if (!in.seen) {
    in.seen = true;
    in.epoch = epoch_;
  } else if (stamp_ns < in.last_ns && in.last_ns - stamp_ns < min_jump_ns_) {
    last_out_of_order_ns_ = in.last_ns - stamp_ns;  // (the input's latest stamp stays)
    return Verdict::kOutOfOrder;
  } else if (stamp_ns < in.last_ns) {
    if (in.epoch == epoch_) {  // this input was in the current epoch already: a new jump
      ++epoch_;
      last_jump_ns_ = in.last_ns - stamp_ns;
      verdict = Verdict::kJump;
    }
    in.epoch = epoch_;              // else it joins the epoch another input started (the same jump)
  } else if (in.epoch != epoch_) {  // still behind: a late message from before the jump
    if (++in.stale < max_stale_) {
      in.last_ns = stamp_ns;
      return Verdict::kStale;
    }
    in.epoch = epoch_;  // a stream that does not loop with the others
  }
  in.stale = 0;
  in.last_ns = stamp_ns;
  return verdict;
}

}  // namespace rgbd_lane_detector
