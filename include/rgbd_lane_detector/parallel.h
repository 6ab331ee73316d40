/**
 * @file parallel.h
 * @brief Two independent stages on two cores through OpenCV's thread pool (cv::parallel_for_).
 */
#pragma once

#include <type_traits>

#include <opencv2/core/utility.hpp>

namespace rgbd_lane_detector {
namespace detail {

/// The two tasks of runPair() as one OpenCV loop body over the range [0, 2).
template <typename A, typename B>
class PairBody : public cv::ParallelLoopBody {
 public:
  PairBody(A& a, B& b) : a_(a), b_(b) {}
  void operator()(const cv::Range& range) const override {
    for (int i = range.start; i < range.end; ++i) {
      if (i == 0)
        a_();
      else
        b_();
    }
  }

 private:
  A& a_;
  B& b_;
};

}  // namespace detail

/**
 * @brief Run a() and b(), which must not depend on each other: as two stripes of
 * cv::parallel_for_ when OpenCV may use more than one thread (cv::getNumThreads(), so
 * cv::setNumThreads(1) keeps the whole detector on one thread), one after the other otherwise
 * and under ThreadSanitizer. OpenCV also runs the loop serially when it is nested in another
 * parallel loop, and its nesting flag is process-wide: while one thread of the process is inside
 * cv::parallel_for_ (another detector, or any OpenCV call that parallelises), this pair runs on
 * the calling thread, one after the other. Returns when both are done; an exception of either
 * reaches the caller. Allocates nothing per call with Debian's OpenCV (TBB back end;
 * test_allocations).
 */
template <typename A, typename B>
void runPair(A&& a, B&& b) {
#if defined(__SANITIZE_THREAD__)
  // ThreadSanitizer cannot see the hand-over inside OpenCV's (uninstrumented) TBB pool and would
  // report the stages' buffers as races: one after the other there.
  const bool serial = true;
#else
  const bool serial = cv::getNumThreads() < 2;
#endif
  if (serial) {
    a();
    b();
    return;
  }
  const detail::PairBody<std::remove_reference_t<A>, std::remove_reference_t<B>> body(a, b);
  cv::parallel_for_(cv::Range(0, 2), body, 2);
}

}  // namespace rgbd_lane_detector
