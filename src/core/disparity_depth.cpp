#include "rgbd_lane_detector/disparity_depth.h"

#include <algorithm>
#include <cmath>

namespace rgbd_lane_detector {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// The smallest float >= b (so that, for a float d, d >= result exactly when d >= b).
float floatAtLeast(double b) {
  if (b <= -static_cast<double>(std::numeric_limits<float>::max())) return -kInf;
  if (b > static_cast<double>(std::numeric_limits<float>::max())) return kInf;
  float f = static_cast<float>(b);
  if (static_cast<double>(f) < b) f = std::nextafter(f, kInf);
  return f;
}

// The largest float <= b.
float floatAtMost(double b) { return -floatAtLeast(-b); }

}  // namespace

const char* DisparityModel::problem() const {
  if (!(std::isfinite(focal) && focal > 0.0))
    return "focal length f is not a finite positive number";
  if (!(std::isfinite(baseline) && baseline != 0.0)) return "baseline T is zero or not finite";
  if (!(std::fabs(focal * baseline) <= std::numeric_limits<float>::max()))
    return "f * T is out of range";
  if (std::isnan(min_disparity) || std::isnan(max_disparity))
    return "minimum or maximum disparity is NaN";
  if (!(std::isfinite(delta_d) && delta_d >= 0.0))
    return "disparity resolution delta_d is negative or not finite";
  return nullptr;
}

const char* disparityToDepth(const cv::Mat& disparity, const DisparityModel& model,
                             cv::Mat& depth) {
  if (disparity.empty()) return "disparity image is empty";
  if (disparity.type() != CV_32FC1) return "disparity image is not CV_32FC1";
  if (const char* problem = model.problem()) return problem;

  const float fT = static_cast<float>(model.focal * model.baseline);
  const float lo = floatAtLeast(model.min_disparity);
  const float hi = model.max_disparity > model.min_disparity ? floatAtMost(model.max_disparity)
                                                             : kInf;
  const float min_abs = floatAtLeast(model.delta_d);
  const float nan = std::numeric_limits<float>::quiet_NaN();

  const cv::Rect image(0, 0, disparity.cols, disparity.rows);
  const cv::Rect window = model.valid_window.empty() ? image : (model.valid_window & image);
  const int x0 = window.x, x1 = window.x + window.width;  // empty window: no valid column

  depth.create(disparity.size(), CV_32FC1);
  for (int y = 0; y < disparity.rows; ++y) {
    const float* d = disparity.ptr<float>(y);
    float* z = depth.ptr<float>(y);
    if (y < window.y || y >= window.y + window.height || window.empty()) {
      std::fill(z, z + disparity.cols, nan);
      continue;
    }
    std::fill(z, z + x0, nan);
    // Branch-free so that the compiler vectorises it; a NaN disparity fails every comparison.
    for (int x = x0; x < x1; ++x) {
      const float v = d[x];
      const float depth_m = fT / v;  // +-inf for v = 0: rejected below
      const bool ok = (v >= lo) & (v <= hi) & (std::fabs(v) >= min_abs) & (depth_m > 0.f) &
                      (depth_m < kInf);
      z[x] = ok ? depth_m : nan;
    }
    std::fill(z + x1, z + disparity.cols, nan);
  }
  return nullptr;
}

}  // namespace rgbd_lane_detector
