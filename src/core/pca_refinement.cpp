#include "rgbd_lane_detector/pca_refinement.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rgbd_lane_detector {

PcaAngle pcaMarkerAngle(const cv::Mat& R, const cv::Point& peak, float threshold, int box_size,
                        std::vector<cv::Point>& stack, std::vector<uint8_t>& visited) {
  PcaAngle out;
  if (R.empty() || R.type() != CV_32FC1) return out;
  if (peak.x < 0 || peak.y < 0 || peak.x >= R.cols || peak.y >= R.rows) return out;
  if (!(R.at<float>(peak) > threshold)) return out;

  const int half = std::max(box_size, 1) / 2;
  const cv::Rect box = cv::Rect(peak.x - half, peak.y - half, 2 * half + 1, 2 * half + 1) &
                       cv::Rect(0, 0, R.cols, R.rows);
  visited.assign(static_cast<size_t>(box.area()), 0);
  stack.clear();
  stack.push_back(peak);
  visited[(peak.y - box.y) * box.width + (peak.x - box.x)] = 1;

  // 8-connected region growing; accumulate first and second moments.
  double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  int n = 0;
  while (!stack.empty()) {
    const cv::Point p = stack.back();
    stack.pop_back();
    ++n;
    sx += p.x;
    sy += p.y;
    sxx += static_cast<double>(p.x) * p.x;
    sxy += static_cast<double>(p.x) * p.y;
    syy += static_cast<double>(p.y) * p.y;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const cv::Point q(p.x + dx, p.y + dy);
        if (!box.contains(q)) continue;
        // a disc, not the square: clipping a band by a square tilts its principal axis
        // toward the square's diagonal; a disc centred on the band clips it symmetrically
        const int ox = q.x - peak.x, oy = q.y - peak.y;
        if (ox * ox + oy * oy > half * half) continue;
        uint8_t& seen = visited[(q.y - box.y) * box.width + (q.x - box.x)];
        if (seen) continue;
        seen = 1;
        if (R.at<float>(q) > threshold) stack.push_back(q);
      }
    }
  }
  out.count = n;
  if (n < 3) return out;
  const double mx = sx / n, my = sy / n;
  const double cxx = sxx / n - mx * mx, cxy = sxy / n - mx * my, cyy = syy / n - my * my;
  // eigen decomposition of the 2x2 covariance
  const double tr = cxx + cyy, det = cxx * cyy - cxy * cxy;
  const double disc = std::sqrt(std::max(tr * tr / 4 - det, 0.0));
  const double l1 = tr / 2 + disc, l2 = tr / 2 - disc;
  if (!(l1 > 0.0) || l1 - l2 <= 1e-9 * l1) return out;  // isotropic blob: no direction
  double ax, ay;  // first principal axis
  if (std::fabs(cxy) > 1e-12) {
    ax = l1 - cyy;
    ay = cxy;
  } else if (cxx >= cyy) {
    ax = 1;
    ay = 0;
  } else {
    ax = 0;
    ay = 1;
  }
  if (ay < 0 || (ay == 0 && ax < 0)) {
    ax = -ax;
    ay = -ay;
  }
  out.valid = true;
  out.angle = std::atan2(ay, ax);
  out.centroid = cv::Point2f(static_cast<float>(mx), static_cast<float>(my));
  out.elongation = l2 > 0 ? std::sqrt(l1 / l2) : std::numeric_limits<double>::infinity();
  return out;
}

}  // namespace rgbd_lane_detector
