#include "rgbd_lane_detector_tools/synth/road.h"

#include <cmath>

namespace rgbd_lane_detector {
namespace synth {

RoadGeometry::RoadGeometry(const SceneSettings& s)
    : curvature_(s.curvature),
      radius_(std::fabs(s.curvature) > 1e-9 ? 1.0 / s.curvature : 0.0),
      lane_width_(s.lane_width) {
  if (radius_ == 0.0) curvature_ = 0.0;
  const double W = s.lane_width;
  left_edge_ = -0.5 * W - s.lanes_left * W;
  right_edge_ = 0.5 * W + s.lanes_right * W;
  // lines from left to right: k = 0 is the left road edge
  const int n_lines = s.lanes_left + s.lanes_right + 2;
  for (int k = 0; k < n_lines; ++k) {
    const double offset = left_edge_ + k * W;
    const bool is_edge = k == 0 || k == n_lines - 1;
    const bool is_ego_left = k == s.lanes_left;
    const bool is_ego_right = k == s.lanes_left + 1;
    MarkerKind kind = is_edge ? s.edges : s.separators;
    if (is_ego_left) kind = s.ego_left;
    if (is_ego_right) kind = s.ego_right;
    if (kind == MarkerKind::kNone) continue;
    MarkerLine m;
    m.offset = offset;
    m.width = (is_edge && !is_ego_left && !is_ego_right) ? s.edge_marker_width : s.marker_width;
    m.dashed = kind == MarkerKind::kDashed;
    m.dash_length = s.dash_length;
    m.period = s.dash_length + s.dash_gap;
    m.phase = 1.7 * k;  // neighbouring lines are not in phase
    if (is_ego_left) ego_left_ = static_cast<int>(markers_.size());
    if (is_ego_right) ego_right_ = static_cast<int>(markers_.size());
    markers_.push_back(m);
  }
}

Eigen::Vector2d RoadGeometry::point(double s, double t) const {
  if (curvature_ == 0.0) return Eigen::Vector2d(t, s);
  const double phi = s * curvature_;
  const double rho = radius_ - t;
  return Eigen::Vector2d(radius_ - rho * std::cos(phi), rho * std::sin(phi));
}

void RoadGeometry::coordinates(double x, double z, double s_ref, double& s, double& t) const {
  if (curvature_ == 0.0) {
    s = z;
    t = x;
    return;
  }
  const double vx = x - radius_, vz = z;
  const double r = std::hypot(vx, vz);
  const double rho = radius_ > 0 ? r : -r;
  t = radius_ - rho;
  const double phi = rho != 0.0 ? std::atan2(vz / rho, -vx / rho) : 0.0;
  s = phi * radius_;
  const double turn = 2.0 * M_PI * std::fabs(radius_);
  s += std::round((s_ref - s) / turn) * turn;
}

bool RoadGeometry::rayToLateral(double ox, double oz, double dx, double dz, double t_line,
                                double min_l, double max_l, double& lambda) const {
  if (curvature_ == 0.0) {
    if (std::fabs(dx) < 1e-12) return false;
    lambda = (t_line - ox) / dx;
    return lambda > min_l && lambda < max_l;
  }
  // |o + l d - C|^2 = (R - t)^2 with C = (R, 0)
  const double px = ox - radius_, pz = oz;
  const double a = dx * dx + dz * dz;
  const double b = 2.0 * (px * dx + pz * dz);
  const double rr = radius_ - t_line;
  const double c = px * px + pz * pz - rr * rr;
  const double disc = b * b - 4.0 * a * c;
  if (a < 1e-18 || disc < 0.0) return false;
  const double sq = std::sqrt(disc);
  const double l1 = (-b - sq) / (2.0 * a), l2 = (-b + sq) / (2.0 * a);
  if (l1 > min_l && l1 < max_l) {
    lambda = l1;
    return true;
  }
  if (l2 > min_l && l2 < max_l) {
    lambda = l2;
    return true;
  }
  return false;
}

int RoadGeometry::markerAt(double s, double t) const {
  for (size_t i = 0; i < markers_.size(); ++i) {
    const MarkerLine& m = markers_[i];
    if (std::fabs(t - m.offset) > 0.5 * m.width) continue;
    if (m.dashed) {
      double u = std::fmod(s - m.phase, m.period);
      if (u < 0) u += m.period;
      if (u >= m.dash_length) continue;
    }
    return static_cast<int>(i);
  }
  return -1;
}

}  // namespace synth
}  // namespace rgbd_lane_detector
