/**
 * @file node_diagnostics.h
 * @brief The nodelet's /diagnostics: `<node>: output rate` (a TopicDiagnostic ticked per
 * published frame) and `<node>: processing` (the frame accounting and the processing times,
 * processingStatus()), updated by a timer on the nodelet's queue. Owns the FrameAccounting.
 * Private to the nodelet library.
 */
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/publisher.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>

#include "frame_accounting.h"
#include "node_params.h"

namespace rgbd_lane_detector {

/**
 * @brief The `processing` status from an accounting report: WARN when frames were dropped in
 * the window, else OK ("Idle: no subscribers", "Waiting for frames" or the mean time), and
 * every counter (docs/NODELET.md, Frame accounting).
 */
void processingStatus(const FrameAccounting::Report& r, bool subscribed,
                      diagnostic_updater::DiagnosticStatusWrapper& stat);

class NodeDiagnostics {
 public:
  /// @param subscribed whether the inputs are subscribed (called from the timer)
  NodeDiagnostics(ros::NodeHandle& nh, ros::NodeHandle& pnh, const std::string& name,
                  const NodeParams& params, std::function<bool()> subscribed);
  ~NodeDiagnostics() { stop(); }
  /// No update after this (the owner's teardown: the status reads its subscription state).
  void stop() { timer_.stop(); }

  FrameAccounting& accounting() { return accounting_; }
  /// A colour image reached the nodelet (its address is its identity until it is synchronised).
  void received(const sensor_msgs::Image& colour) {
    accounting_.received(&colour, static_cast<int64_t>(colour.header.stamp.toNSec()),
                         colour.header.seq);
  }
  /// When a frame callback started: the steady clock, and the CPU time of its thread.
  struct CallbackStart {
    std::chrono::steady_clock::time_point wall;
    double cpu_ms;
    static CallbackStart now() { return {std::chrono::steady_clock::now(), threadCpuMs()}; }
  };
  /// CPU time of the calling thread (ms).
  static double threadCpuMs();

  /// The synchronised set of @p colour met its fate (@p detail names a drop's problem); its
  /// callback started at @p start, detect() took @p detect_ms.
  void synchronised(const sensor_msgs::Image& colour, FrameOutcome outcome, const char* detail,
                    const CallbackStart& start, double detect_ms) {
    const std::chrono::duration<double, std::milli> ms =
        std::chrono::steady_clock::now() - start.wall;
    accounting_.synchronised(&colour, static_cast<int64_t>(colour.header.stamp.toNSec()), outcome,
                             detail, ms.count(), detect_ms, threadCpuMs() - start.cpu_ms);
  }
  /// A frame was published with this stamp.
  void tick(const ros::Time& stamp) { rate_->tick(stamp); }

 private:
  FrameAccounting accounting_;  ///< every colour frame's fate (thread-safe)
  std::function<bool()> subscribed_;
  double min_rate_, max_rate_;  ///< read by rate_ through pointers
  diagnostic_updater::Updater updater_;
  std::unique_ptr<diagnostic_updater::TopicDiagnostic> rate_;
  ros::Timer timer_;  ///< last: stopped first
};

}  // namespace rgbd_lane_detector
