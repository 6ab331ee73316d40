// The processing image of a frame: its scale (processingScale()), its geometry (size, the index
// maps to the input image, the searched rows), the colour resampled to it, and the validation of
// a frame (formats, sizes, a searched region that holds a template).
#include "rgbd_lane_detector/lane_detector.h"

#include <algorithm>
#include <cmath>

#include "rgbd_lane_detector/pixel_kernels.h"

namespace rgbd_lane_detector {
namespace {

constexpr double kLeastResample = 0.8;    // the automatic scale resamples below this only

}  // namespace

double processingScale(const Params& params, const cv::Size& size, const Intrinsics& intrinsics) {
  if (params.processing_scale > 0.0) return params.processing_scale;
  constexpr double kLineWidth = 0.10;   // m, a narrow lane line
  constexpr double kNearWidthPx = 24.0; // its width at the bottom row the templates suit
  const double below = size.height - 1 - intrinsics.cy;
  const double near_px = kLineWidth * below / std::max(0.2, params.camera_height);
  if (!(near_px > kNearWidthPx)) return 1.0;  // also: cy at or below the bottom row
  // a processing image of at least 64 px a side (the templates must fit)
  const double floor_scale = 64.0 / std::max(1, std::min(size.width, size.height));
  const double scale = std::max(std::min(1.0, floor_scale), kNearWidthPx / near_px);
  // resampling costs a pass over the input and the classifier's grey at full size: shrinking
  // by less than a fifth saves less than that
  return scale > kLeastResample ? 1.0 : scale;
}

Status LaneDetector::validate(const Frame& frame) const {
  if (frame.colour.empty() || frame.depth.empty()) return Status::kEmptyImage;
  if (frame.colour.size() != frame.depth.size()) return Status::kSizeMismatch;
  if (frame.colour.depth() != CV_8U || frame.colour.channels() != pixelLayout(frame.format).channels)
    return Status::kUnsupportedColour;
  if (frame.depth.type() == CV_16UC1) {
    if (!(frame.depth_scale > 0.0) || !std::isfinite(frame.depth_scale))
      return Status::kUnsupportedDepth;
  } else if (frame.depth.type() != CV_32FC1) {
    return Status::kUnsupportedDepth;
  }
  if (!frame.intrinsics.valid()) return Status::kInvalidIntrinsics;
  // searched region at the processing scale must hold a template
  const double s = processingScale(params_, frame.colour.size(), frame.intrinsics);
  const int pw = std::max(1, static_cast<int>(std::lround(frame.colour.cols * s)));
  const int ph = std::max(1, static_cast<int>(std::lround(frame.colour.rows * s)));
  const int top = static_cast<int>(std::lround(params_.roi_top * ph));
  const int bottom = static_cast<int>(std::lround(params_.roi_bottom * ph));
  if (pw < params_.template_size || bottom - top < params_.template_size)
    return Status::kImageTooSmall;
  return Status::kOk;
}

void LaneDetector::prepareGeometry(const Frame& frame) {
  const double s = processingScale(params_, frame.colour.size(), frame.intrinsics);
  const cv::Size in = frame.colour.size();
  const cv::Size proc(std::max(1, static_cast<int>(std::lround(in.width * s))),
                      std::max(1, static_cast<int>(std::lround(in.height * s))));
  if (in != input_size_ || proc != proc_size_ || s != scale_) {
    input_size_ = in;
    proc_size_ = proc;
    scale_ = s;
    if (proc == in) {
      col_map_.release();
      row_map_.release();
    } else {
      col_map_.create(1, proc.width, CV_32SC1);
      row_map_.create(1, proc.height, CV_32SC1);
      for (int x = 0; x < proc.width; ++x)
        col_map_.at<int>(x) = std::min(in.width - 1, static_cast<int>((x + 0.5) * in.width / proc.width));
      for (int y = 0; y < proc.height; ++y)
        row_map_.at<int>(y) =
            std::min(in.height - 1, static_cast<int>((y + 0.5) * in.height / proc.height));
    }
    // buffers change size: start from zeroed maps (rows outside the ROI stay 0)
    geometric_.release();
    response_left_.release();
    response_right_.release();
  }
  const int top = static_cast<int>(std::lround(params_.roi_top * proc.height));
  const int bottom = static_cast<int>(std::lround(params_.roi_bottom * proc.height));
  const cv::Rect roi(0, top, proc.width, bottom - top);
  if (roi != roi_) {
    roi_ = roi;
    geometric_.release();
  }
  roi_rows_ = cv::Range(roi_.y, roi_.y + roi_.height);
  proc_K_ = frame.intrinsics;
}

void LaneDetector::resampleColour(const Frame& frame) {
  if (col_map_.empty()) return;
  remapNearest(frame.colour, col_map_, row_map_, colour_small_);
}

}  // namespace rgbd_lane_detector
