#include "rgbd_lane_detector_tools/dataset/real_variants.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include <opencv2/imgproc.hpp>

namespace rgbd_lane_detector {
namespace tools {
namespace {

constexpr double kNearRowsShare = 0.3;  // bottom share of the rows without depth
// night: the road lit by the vehicle's own lamps (bright near, dark toward the horizon) and the
// camera's gain raising the sensor noise with it
constexpr double kNightNear = 0.45;    // colour scale at the bottom row
constexpr double kNightFar = 0.08;     // ... at the principal point's row and above
constexpr double kNightNoise = 4.0;    // Gaussian sigma after the scale (0-255)
constexpr uint64_t kNightSeed = 0x6e16e7ULL;

// The frame at night (kNight): each row scaled from kNightNear at the bottom to kNightFar at
// the horizon (the principal point's row), Gaussian noise added, saturating.
cv::Mat atNight(const cv::Mat& colour, double cy) {
  cv::Mat f;
  colour.convertTo(f, CV_32F);
  const double horizon = std::max(0.0, std::min(cy, colour.rows - 1.0));
  for (int v = 0; v < f.rows; ++v) {
    const double t = v <= horizon ? 0.0 : (v - horizon) / std::max(1.0, colour.rows - 1 - horizon);
    f.row(v) *= kNightFar + (kNightNear - kNightFar) * t * t;
  }
  cv::Mat noise(f.size(), f.type());
  cv::RNG rng(kNightSeed);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, kNightNoise);
  f += noise;
  cv::Mat out;
  f.convertTo(out, colour.type());
  return out;
}

// A flipped copy (the source may share its buffer with another member of the frame).
cv::Mat flipped(const cv::Mat& m) {
  cv::Mat out;
  if (!m.empty()) cv::flip(m, out, 1);
  return out;
}

}  // namespace

const std::vector<RealVariant>& allRealVariants() {
  static const std::vector<RealVariant> all = {
      RealVariant::kAsIs,           RealVariant::kMirrored,     RealVariant::kNoNearDepth,
      RealVariant::kHalfResolution, RealVariant::kUnderexposed, RealVariant::kOverexposed,
      RealVariant::kNight};
  return all;
}

const char* realVariantName(RealVariant v) {
  switch (v) {
    case RealVariant::kAsIs:
      return "as_is";
    case RealVariant::kMirrored:
      return "mirrored";
    case RealVariant::kNoNearDepth:
      return "no_near_depth";
    case RealVariant::kHalfResolution:
      return "half_resolution";
    case RealVariant::kUnderexposed:
      return "underexposed";
    case RealVariant::kOverexposed:
      return "overexposed";
    case RealVariant::kNight:
      return "night";
  }
  return "unknown";
}

bool realVariantFromName(const std::string& name, RealVariant& v) {
  for (RealVariant c : allRealVariants()) {
    if (name == realVariantName(c)) {
      v = c;
      return true;
    }
  }
  return false;
}

void applyRealVariant(RealVariant v, DatasetFrame& frame, LabelledFrame& label) {
  switch (v) {
    case RealVariant::kAsIs:
      return;
    case RealVariant::kMirrored: {
      const int width = frame.colour.cols;
      frame.colour = flipped(frame.colour);
      frame.depth = flipped(frame.depth);
      frame.lidar_depth = flipped(frame.lidar_depth);
      frame.intrinsics.cx = width - 1 - frame.intrinsics.cx;
      frame.road_plane_normal.x() = -frame.road_plane_normal.x();
      for (LabelledSide* s : {&label.left, &label.right})
        for (cv::Point2d& p : s->points) p.x = width - 1 - p.x;
      std::swap(label.left, label.right);
      return;
    }
    case RealVariant::kNoNearDepth: {
      cv::Mat depth = frame.depth.clone();  // may be the LiDAR reference's buffer
      const int first = static_cast<int>(std::lround((1.0 - kNearRowsShare) * depth.rows));
      cv::Mat rows = depth.rowRange(first, depth.rows);
      if (depth.type() == CV_32FC1)
        rows.setTo(std::numeric_limits<float>::quiet_NaN());
      else
        rows.setTo(0);
      frame.depth = depth;
      return;
    }
    case RealVariant::kHalfResolution: {
      const double s = 0.5;
      cv::Mat colour, depth, lidar;
      cv::resize(frame.colour, colour, cv::Size(), s, s, cv::INTER_AREA);
      cv::resize(frame.depth, depth, colour.size(), 0, 0, cv::INTER_NEAREST);
      if (!frame.lidar_depth.empty())
        cv::resize(frame.lidar_depth, lidar, colour.size(), 0, 0, cv::INTER_NEAREST);
      frame.colour = colour;
      frame.depth = depth;
      frame.lidar_depth = lidar;
      Intrinsics& K = frame.intrinsics;  // pixel centres: (u + 0.5) s - 0.5
      K.fx *= s;
      K.fy *= s;
      K.cx = (K.cx + 0.5) * s - 0.5;
      K.cy = (K.cy + 0.5) * s - 0.5;
      for (LabelledSide* side : {&label.left, &label.right})
        for (cv::Point2d& p : side->points) p = (p + cv::Point2d(0.5, 0.5)) * s - cv::Point2d(0.5, 0.5);
      return;
    }
    case RealVariant::kUnderexposed:
    case RealVariant::kOverexposed: {
      cv::Mat colour;
      frame.colour.convertTo(colour, -1, v == RealVariant::kUnderexposed ? 0.6 : 1.4, 0.0);
      frame.colour = colour;
      return;
    }
    case RealVariant::kNight:
      frame.colour = atNight(frame.colour, frame.intrinsics.cy);
      return;
  }
}

}  // namespace tools
}  // namespace rgbd_lane_detector
