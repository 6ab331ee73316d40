#include "rgbd_lane_detector/line_template.h"

#include <algorithm>
#include <cmath>

namespace rgbd_lane_detector {

void makeLineTemplate(int size, int width, double angle, LineTemplate& out) {
  size = std::max(size, 3);
  width = std::max(width, 1);
  out.size = size;
  out.width = width;
  out.angle = angle;
  out.image.create(size, size, CV_8UC1);
  out.image.setTo(0);
  out.run_begin.assign(size, 0);
  out.run_end.assign(size, 0);
  out.count = 0;

  const double c = std::cos(angle), s = std::sin(angle);
  const double half = 0.5 * size;
  // A near-horizontal line has no bounded horizontal extent per row; keep |sin| away from 0.
  const double abs_s = std::max(std::fabs(s), 0.05);
  const double cot = c / (s >= 0 ? abs_s : -abs_s);
  const double half_run = width / (2.0 * abs_s);
  for (int r = 0; r < size; ++r) {
    const double xc = half + (r + 0.5 - half) * cot;  // line centre on this row
    // columns whose centre c + 0.5 lies in [xc - half_run, xc + half_run]
    int b = static_cast<int>(std::ceil(xc - half_run - 0.5));
    int e = static_cast<int>(std::floor(xc + half_run - 0.5)) + 1;
    b = std::min(std::max(b, 0), size);
    e = std::min(std::max(e, b), size);
    out.run_begin[r] = b;
    out.run_end[r] = e;
    out.count += e - b;
    if (e > b) out.image.row(r).colRange(b, e).setTo(255);
  }
}

double defaultLeftAngle(double template_angle_deg) {
  return M_PI - template_angle_deg * M_PI / 180.0;
}

double defaultRightAngle(double template_angle_deg) { return template_angle_deg * M_PI / 180.0; }

}  // namespace rgbd_lane_detector
