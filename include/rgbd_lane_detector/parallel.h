/**
 * @file parallel.h
 * @brief Two independent stages on two cores: a persistent helper thread, no allocation per call.
 */
#pragma once

#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <type_traits>
#include <utility>

#include <opencv2/core/utility.hpp>

namespace rgbd_lane_detector {
namespace detail {

/// The process' helper thread: runs one task at a time for runPair().
class Helper {
 public:
  static Helper& instance() {
    static Helper helper;
    return helper;
  }

  /// Start task(ctx) on the helper; false (nothing started) when another caller holds it.
  bool start(void (*task)(void*), void* ctx) {
    if (!busy_.try_lock()) return false;
    {
      std::lock_guard<std::mutex> lock(m_);
      task_ = task;
      ctx_ = ctx;
      done_ = false;
      error_ = nullptr;
    }
    cv_.notify_one();
    return true;
  }

  /// Wait for the task started by start(), rethrowing what it threw.
  void wait() {
    std::exception_ptr error;
    {
      std::unique_lock<std::mutex> lock(m_);
      cv_.wait(lock, [this] { return done_; });
      error = error_;
      task_ = nullptr;
    }
    busy_.unlock();
    if (error) std::rethrow_exception(error);
  }

 private:
  Helper() : thread_([this] { loop(); }) {}
  ~Helper() {
    {
      std::lock_guard<std::mutex> lock(m_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }

  void loop() {
    std::unique_lock<std::mutex> lock(m_);
    for (;;) {
      cv_.wait(lock, [this] { return stop_ || (task_ && !done_); });
      if (stop_) return;
      lock.unlock();
      std::exception_ptr error;
      try {
        task_(ctx_);
      } catch (...) {
        error = std::current_exception();
      }
      lock.lock();
      error_ = error;
      done_ = true;
      cv_.notify_all();
    }
  }

  std::mutex busy_;  ///< held by the caller between start() and wait()
  std::mutex m_;
  std::condition_variable cv_;
  void (*task_)(void*) = nullptr;
  void* ctx_ = nullptr;
  bool done_ = false, stop_ = false;
  std::exception_ptr error_;
  std::thread thread_;  ///< last: starts once the members above exist
};

}  // namespace detail

/**
 * @brief Run a() and b(), which must not depend on each other: a() on a second core while the
 * caller runs b(), when OpenCV may use more than one thread (cv::getNumThreads(), so
 * cv::setNumThreads(1) keeps the whole detector on one thread) and the helper is free; one
 * after the other otherwise. Returns when both are done; an exception of either is rethrown.
 */
template <typename A, typename B>
void runPair(A&& a, B&& b) {
  if (cv::getNumThreads() < 2) {
    a();
    b();
    return;
  }
  detail::Helper& helper = detail::Helper::instance();
  auto task = [](void* ctx) { (*static_cast<std::remove_reference_t<A>*>(ctx))(); };
  if (!helper.start(task, &a)) {
    a();
    b();
    return;
  }
  try {
    b();
  } catch (...) {
    helper.wait();
    throw;
  }
  helper.wait();
}

}  // namespace rgbd_lane_detector
