#include "frame_processor.h"

#include <chrono>
#include <cmath>
#include <exception>

#include "rgbd_lane_detector/ros/conversions.h"

namespace rgbd_lane_detector {
namespace conv = conversions;

FrameProcessor::FrameProcessor(const Params& params)
    : detector_(params), frame_params_(detector_.params()), params_(params) {}

void FrameProcessor::setParams(const Params& params) {
  std::lock_guard<std::mutex> lock(params_mutex_);
  params_ = params;
  ++params_version_;
}

bool FrameProcessor::prepare(const sensor_msgs::CameraInfo& info,
                             const std::string& colour_topic, Preparation& out) {
  // A driver re-estimating its calibration (sameCamera()) is the same camera: its frames keep
  // the prepared intrinsics (load()), so the detector neither re-plans nor loses its tracks.
  const Intrinsics K = conv::intrinsicsFromCameraInfo(info);
  const cv::Size size(static_cast<int>(info.width), static_cast<int>(info.height));
  if (size == prepared_size_ && conv::sameCamera(prepared_K_, K)) return false;
  prepared_size_ = size;
  prepared_K_ = K;
  const auto start = std::chrono::steady_clock::now();
  out.error.clear();
  try {
    if (detector_.prepare(size, K) != Status::kOk) return false;  // its frames will be dropped
  } catch (const std::exception& e) {  // never expected (a corrupt camera_info?): not a crash
    out.error = e.what();
    return false;
  }
  out.size = size;
  out.K = K;
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
               .count();
  // A rectified image comes with its camera's camera_info (D of the raw lens, P of the
  // rectified image): only a colour topic that is not a rectified one is a problem
  out.warning.clear();
  if (conv::hasDistortion(info) && colour_topic.find("rect") == std::string::npos)
    out.warning = "camera_info has distortion coefficients (model '" + info.distortion_model +
                  "') and the colour topic '" + colour_topic +
                  "' is not a rectified image: the detector reads images as rectified (pinhole "
                  "P, else K), so lines toward the image edges come out displaced. Feed it "
                  "rectified images (image_proc: image_rect_color).";
  first_frame_pending_ = true;
  return true;
}

void FrameProcessor::applyParams(const Eigen::Vector3d* up) {
  Params p;
  bool changed = false;
  {
    std::lock_guard<std::mutex> lock(params_mutex_);
    if (params_version_ != applied_version_) {
      p = params_;
      applied_version_ = params_version_;
      changed = true;
    }
  }
  if (!changed) p = frame_params_;
  if (up != nullptr) {
    p.up_x = up->x();
    p.up_y = up->y();
    p.up_z = up->z();
  }
  const Params& q = frame_params_;
  constexpr double kUpTolerance = 1e-6;  // a static mount gives the same axis every frame
  if (changed || std::fabs(p.up_x - q.up_x) > kUpTolerance ||
      std::fabs(p.up_y - q.up_y) > kUpTolerance || std::fabs(p.up_z - q.up_z) > kUpTolerance) {
    detector_.setParams(p);
    frame_params_ = detector_.params();
  }
}

FrameOutcome FrameProcessor::load(const sensor_msgs::Image& colour, const sensor_msgs::Image& depth,
                                  const sensor_msgs::CameraInfo& info, Frame& frame,
                                  const char*& problem) {
  problem = conv::frameFromMsgs(colour, depth, info, frame, depth_swap_);
  if (problem != nullptr) return FrameOutcome::kBadMessage;
  if (frame.colour.size() == prepared_size_ && conv::sameCamera(prepared_K_, frame.intrinsics))
    frame.intrinsics = prepared_K_;  // calibration jitter (prepare())
  const Status valid = detector_.validate(frame);
  if (valid == Status::kOk) return FrameOutcome::kProcessed;
  problem = statusMessage(valid);
  return FrameOutcome::kInvalidFrame;
}

FrameOutcome FrameProcessor::detect(const Frame& frame, int64_t stamp_ns,
                                    const Eigen::Isometry3d* motion, bool full_geometric,
                                    const char*& problem) {
  problem = nullptr;
  restart_gap_s_ = 0.0;
  if (detected_ && max_gap_ns_ > 0 && stamp_ns - last_detected_ns_ > max_gap_ns_) {
    restart_gap_s_ = static_cast<double>(stamp_ns - last_detected_ns_) * 1e-9;
    reset();
  }
  if (motion != nullptr) detector_.predictMotion(*motion);
  // G everywhere only for the response/geometric image; R needs it where M >= tau_G only
  detector_.setFullGeometricMap(full_geometric);
  Status status;
  try {
    status = detector_.detect(frame, result_);
  } catch (const std::exception& e) {  // never expected: the frame was validated
    exception_text_ = e.what();
    return FrameOutcome::kDetectorException;
  }
  if (status == Status::kOk) {
    detected_ = true;
    last_detected_ns_ = stamp_ns;
    return FrameOutcome::kProcessed;
  }
  problem = statusMessage(status);
  return FrameOutcome::kInvalidFrame;
}

bool FrameProcessor::firstFrameAfterPrepare() {
  const bool first = first_frame_pending_;
  first_frame_pending_ = false;
  return first;
}

}  // namespace rgbd_lane_detector
