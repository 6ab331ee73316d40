#include "node_diagnostics.h"

#include <time.h>

#include <algorithm>

namespace rgbd_lane_detector {

void processingStatus(const FrameAccounting::Report& r, bool subscribed,
                      diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const double n = static_cast<double>(std::max<uint64_t>(r.window_processed, 1));
  if (r.window_dropped > 0)
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%lu frame(s) dropped: %s",
                  static_cast<unsigned long>(r.window_dropped), r.last_drop);
  else if (!subscribed)
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "Idle: no subscribers");
  else if (r.window_processed == 0)
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "Waiting for frames");
  else
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::OK, "%.1f ms per frame",
                  r.window_callback_ms / n);
  // Cumulative accounting of every colour frame received (docs/NODELET.md):
  // received == processed + dropped + skipped + not synchronised + waiting.
  stat.add("Inputs subscribed", subscribed);
  stat.add("Frames received", r.received);
  stat.add("Frames synchronised", r.synchronised);
  stat.add("Frames processed", r.processed);
  stat.add("Frames dropped", r.dropped);
  stat.add("Frames skipped (no subscriber)", r.skipped);
  stat.add("Frames not synchronised", r.not_synchronised);
  stat.add("Frames waiting", r.waiting);
  stat.add("Frames unaccounted", r.unaccounted());
  stat.add("Frames lost before the nodelet", r.lost_before);
  // the other inputs: a colour image whose depth or camera_info was lost is not synchronised
  stat.add("Depth images received", r.depth_received);
  stat.add("Depth images lost before the nodelet", r.depth_lost_before);
  stat.add("Camera infos received", r.info_received);
  stat.add("Camera infos lost before the nodelet", r.info_lost_before);
  stat.add("Pending ring overflows", r.ring_overflow);
  stat.add("Frames synchronised late", r.late_synchronised);
  if (r.untracked > 0) stat.add("Frames synchronised untracked", r.untracked);
  for (size_t k = 0; k < r.drop_reasons; ++k)
    stat.add(std::string("Dropped: ") + r.drops[k].reason, r.drops[k].count);
  stat.add("Last drop reason", std::string(r.last_drop));
  stat.addf("Mean processing time (ms)", "%.3f", r.window_callback_ms / n);
  stat.addf("Mean detector time (ms)", "%.3f", r.window_detect_ms / n);
  stat.addf("Mean ROS overhead (ms)", "%.3f", (r.window_callback_ms - r.window_detect_ms) / n);
  stat.addf("Max processing time (ms)", "%.3f", r.window_max_ms);
  stat.addf("Max processing CPU time (ms)", "%.3f", r.window_max_cpu_ms);
  stat.addf("Max camera_info queue wait (ms)", "%.3f", r.window_max_info_wait_ms);
}

double NodeDiagnostics::threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

NodeDiagnostics::NodeDiagnostics(ros::NodeHandle& nh, ros::NodeHandle& pnh,
                                 const std::string& name, const NodeParams& params,
                                 std::function<bool()> subscribed)
    : subscribed_(std::move(subscribed)),
      min_rate_(params.diagnostic_min_rate),
      max_rate_(params.diagnostic_max_rate),
      updater_(nh, pnh, name) {
  updater_.setHardwareID(params.diagnostic_hardware_id);
  rate_.reset(new diagnostic_updater::TopicDiagnostic(
      "output rate", updater_, diagnostic_updater::FrequencyStatusParam(&min_rate_, &max_rate_, 0.1, 10),
      diagnostic_updater::TimeStampStatusParam(-1.0, params.diagnostic_max_delay)));
  updater_.add("processing", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) {
    processingStatus(accounting_.report(), subscribed_(), stat);
  });
  timer_ = nh.createTimer(ros::Duration(params.diagnostic_period),
                          [this](const ros::TimerEvent&) { updater_.force_update(); });
}

}  // namespace rgbd_lane_detector
