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

/// A model's validity test of one disparity, in floats, and its valid window on an image.
struct DisparityTest {
  float fT, lo, hi, min_abs;
  cv::Rect window;  ///< clipped to the image; empty: no valid pixel
  DisparityTest(const DisparityModel& model, const cv::Size& size)
      : fT(static_cast<float>(model.focal * model.baseline)),
        lo(floatAtLeast(model.min_disparity)),
        hi(model.max_disparity > model.min_disparity ? floatAtMost(model.max_disparity) : kInf),
        min_abs(floatAtLeast(model.delta_d)) {
    const cv::Rect image(0, 0, size.width, size.height);
    window = model.valid_window.empty() ? image : (model.valid_window & image);
  }
  /// Within the disparity range and not zero (a NaN disparity fails every comparison).
  bool inRange(float v) const { return (v >= lo) & (v <= hi) & (std::fabs(v) >= min_abs); }
  bool rowIn(int y) const { return y >= window.y && y < window.y + window.height; }
};

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

  const DisparityTest test(model, disparity.size());
  const cv::Rect& window = test.window;
  const int x0 = window.x, x1 = window.x + window.width;  // empty window: no valid column
  const float nan = std::numeric_limits<float>::quiet_NaN();

  depth.create(disparity.size(), CV_32FC1);
  for (int y = 0; y < disparity.rows; ++y) {
    const float* d = disparity.ptr<float>(y);
    float* z = depth.ptr<float>(y);
    if (!test.rowIn(y) || window.empty()) {
      std::fill(z, z + disparity.cols, nan);
      continue;
    }
    std::fill(z, z + x0, nan);
    // Branch-free so that the compiler vectorises it; a NaN disparity fails every comparison.
    for (int x = x0; x < x1; ++x) {
      const float v = d[x];
      const float depth_m = test.fT / v;  // +-inf for v = 0: rejected below
      const bool ok = test.inRange(v) & (depth_m > 0.f) & (depth_m < kInf);
      z[x] = ok ? depth_m : nan;
    }
    std::fill(z + x1, z + disparity.cols, nan);
  }
  return nullptr;
}

DisparityCounts countDisparities(const cv::Mat& disparity, const DisparityModel& model) {
  DisparityCounts n;
  if (disparity.empty() || disparity.type() != CV_32FC1 || model.problem() != nullptr) return n;
  const DisparityTest test(model, disparity.size());
  for (int y = test.window.y; y < test.window.y + test.window.height; ++y) {
    const float* d = disparity.ptr<float>(y);
    for (int x = test.window.x; x < test.window.x + test.window.width; ++x) {
      if (!test.inRange(d[x])) continue;
      const float depth_m = test.fT / d[x];
      n.valid += depth_m > 0.f && depth_m < kInf;
      n.wrong_sign += depth_m < 0.f && depth_m > -kInf;
    }
  }
  return n;
}

}  // namespace rgbd_lane_detector
