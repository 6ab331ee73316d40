#include "rgbd_lane_detector/line_template.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace rgbd_lane_detector {
namespace {

// Slope p / q (columns per row) for a line of cotangent a in a template of side size: the
// smallest q <= kMaxSlopeDenominator whose line stays within half a pixel of the requested one
// over the template's half-length (angle error <= atan(1 / size)), else the nearest one. Small
// q keeps the matcher's cost (4 + 4 q lookups per pixel) low.
void chooseSlope(double a, int size, int& p, int& q) {
  const double want = std::atan2(1.0, a), tolerance = std::atan(1.0 / size);
  double best = -1.0;
  for (int d = 1; d <= kMaxSlopeDenominator; ++d) {
    const int n = static_cast<int>(std::lround(a * d));
    const double err = std::fabs(std::atan2(static_cast<double>(d), static_cast<double>(n)) - want);
    if (best < 0.0 || err < best - 1e-12) {
      best = err;
      p = n;
      q = d;
    }
    if (err <= tolerance) return;
  }
}

}  // namespace

void makeLineTemplate(int size, int width, double angle, LineTemplate& out) {
  size = std::max(size, 3);
  width = std::max(width, 1);
  out.size = size;
  out.width = width;
  out.angle = angle;
  out.image.create(size, size, CV_8UC1);
  for (int r = 0; r < size; ++r) std::memset(out.image.ptr<uint8_t>(r), 0, size);
  out.run_begin.assign(size, 0);
  out.run_end.assign(size, 0);
  out.count = 0;

  // A near-horizontal line has no bounded horizontal extent per row; keep |sin| away from 0.
  const double c = std::cos(angle), s = std::sin(angle);
  const double abs_s = std::max(std::fabs(s), 0.05);
  int p = 0, q = 1;
  chooseSlope(c / (s >= 0 ? abs_s : -abs_s), size, p, q);
  out.slope_p = p;
  out.slope_q = q;
  out.drawn_angle = std::atan2(static_cast<double>(q), static_cast<double>(p));
  const double half_run = width * std::hypot(p, q) / (2.0 * q);  // width / (2 sin drawn)
  const double half = 0.5 * size;
  // Run ends of the first q rows; the others repeat them shifted by p every q rows, by
  // construction (no rounding can break the period the matcher relies on).
  for (int j = 0; j < q && j < size; ++j) {
    const double xc = half + (j + 0.5 - half) * p / q;  // line centre on row j
    const int b = static_cast<int>(std::ceil(xc - half_run - 0.5));
    const int e = static_cast<int>(std::floor(xc + half_run - 0.5)) + 1;
    for (int r = j, shift = 0; r < size; r += q, shift += p) {
      const int rb = std::min(std::max(b + shift, 0), size);
      const int re = std::min(std::max(e + shift, rb), size);
      out.run_begin[r] = rb;
      out.run_end[r] = re;
      out.count += re - rb;
      if (re > rb) std::memset(out.image.ptr<uint8_t>(r) + rb, 255, re - rb);
    }
  }
}

double defaultLeftAngle(double template_angle_deg) {
  return M_PI - template_angle_deg * M_PI / 180.0;
}

double defaultRightAngle(double template_angle_deg) {
  return template_angle_deg * M_PI / 180.0;
}

}  // namespace rgbd_lane_detector
