// The lane fit's plane: the paper mode's lane plane from the marker points (three points or
// robust least squares, gated by the previous plane, the markers snapped onto it, the lane width
// checked), and the checks both modes apply to a plane (plausible tilt and height, smoothing).
#include "rgbd_lane_detector/lane_fitter.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rgbd_lane_detector/lane_plane.h"

namespace rgbd_lane_detector {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

}  // namespace

void LaneFitter::copyTrace(const MarkerTrace& from, MarkerTrace& to) const {
  // element-wise: the vectors keep their capacity (no allocation in steady state)
  to.found = from.found;
  to.kind = from.kind;
  to.confidence = from.confidence;
  to.peak_score = from.peak_score;
  to.seed = from.seed;
  to.seed_point = from.seed_point;
  to.angle = from.angle;
  to.angle_valid = from.angle_valid;
  to.pixels.assign(from.pixels.begin(), from.pixels.end());
  to.scores.assign(from.scores.begin(), from.scores.end());
  to.points.assign(from.points.begin(), from.points.end());
  to.num_valid_points = from.num_valid_points;
}

// --- paper mode: the plane from the markers ----------------------------------------------

void LaneFitter::fitMarkerPlane(const LaneFitInput& in, Result& result) {
  const Params& p = params_;
  MarkerTrace& L = result.left;
  MarkerTrace& R = result.right;
  // plane gate: drop marker points far from the previous plane
  if (p.plane_gate > 0.0 && previous_plane_.valid) {
    for (MarkerTrace* m : {&L, &R}) {
      for (auto& q : m->points) {
        if (!std::isnan(q.z()) && std::fabs(planeDistance(previous_plane_, q)) > p.plane_gate) {
          q = Eigen::Vector3f(kNaN, kNaN, kNaN);
          --m->num_valid_points;
        }
      }
    }
  }
  L.found = L.num_valid_points >= p.min_marker_points;
  R.found = R.num_valid_points >= p.min_marker_points;
  PlaneEstimate& plane = result.plane;
  if (!L.found || !R.found) {
    rejectIncomplete(result);
    return;
  }
  if (p.plane_fit == PlaneFit::kThreePoint) {
    // v_a1: best left match, v_b: best right match, v_a2: furthest right centroid
    Eigen::Vector3f a2(kNaN, kNaN, kNaN);
    for (auto it = R.points.rbegin(); it != R.points.rend(); ++it) {
      if (!std::isnan(it->z())) {
        a2 = *it;
        break;
      }
    }
    planeFromThreePoints(L.seed_point, R.seed_point, a2, plane);
  } else {
    fit_points_.clear();
    fit_points_.insert(fit_points_.end(), L.points.begin(), L.points.end());
    fit_points_.insert(fit_points_.end(), R.points.begin(), R.points.end());
    fitPlaneLeastSquares(fit_points_, 0.1, 3, plane);
  }
  if (!plane.valid || !planePlausible(plane)) {
    plane.valid = false;
    rejectIncomplete(result);
    return;
  }
  smoothPlane(plane);
  if (p.snap_to_plane) {
    snapToPlane(in.K, plane, L);
    snapToPlane(in.K, plane, R);
  }
  if (p.lane_width_max > 0.0) {
    const double width = laneWidth(plane, L, R);
    if (!(width >= p.lane_width_min && width <= p.lane_width_max)) {
      plane.valid = false;
      rejectIncomplete(result);
    }
  }
}

// --- the checks of both modes --------------------------------------------------------------

bool LaneFitter::planePlausible(const PlaneEstimate& plane) const {
  const Params& p = params_;
  const Eigen::Vector3d up(p.up_x, p.up_y, p.up_z);
  // the normal points toward the camera, i.e. up; allow |tilt| up to plane_max_tilt_deg
  const double cos_tilt = plane.normal.dot(up);
  if (p.plane_max_tilt_deg < 90.0 && cos_tilt < std::cos(p.plane_max_tilt_deg * M_PI / 180.0))
    return false;
  return plane.distance >= p.plane_distance_min && plane.distance <= p.plane_distance_max;
}

void LaneFitter::smoothPlane(PlaneEstimate& plane) const {
  if (!(params_.plane_smoothing > 0.0) || !previous_plane_.valid) return;
  const double w = params_.plane_smoothing;
  const Eigen::Vector3d n = (1.0 - w) * plane.normal + w * previous_plane_.normal;
  if (n.norm() > 1e-9) {
    plane.normal = n.normalized();
    plane.distance = (1.0 - w) * plane.distance + w * previous_plane_.distance;
  }
}

void LaneFitter::snapToPlane(const Intrinsics& K, const PlaneEstimate& plane,
                             MarkerTrace& m) const {
  // Markers are paint on the road: their 3D points are where their pixel rays meet the plane.
  m.num_valid_points = 0;
  for (size_t i = 0; i < m.pixels.size(); ++i) {
    const Eigen::Vector3d ray = K.ray(m.pixels[i].x, m.pixels[i].y);
    double t = -1.0;
    rayPlaneDepth(plane, ray, t);
    if (t > 0.0 && t <= params_.max_depth) {  // (t: the depth, ray z = 1)
      m.points[i] = (ray * t).cast<float>();
      ++m.num_valid_points;
    } else {
      m.points[i] = Eigen::Vector3f(kNaN, kNaN, kNaN);
    }
  }
  m.found = m.num_valid_points >= params_.min_marker_points;
}

double LaneFitter::laneWidth(const PlaneEstimate& plane, const MarkerTrace& L,
                             const MarkerTrace& R) const {
  const RoadFrame frame = RoadFrame::fromPlane(plane);
  if (!frame.valid()) return std::numeric_limits<double>::quiet_NaN();
  // for each left point, the right point nearest in the forward direction
  width_samples_.clear();
  for (const auto& l : L.points) {
    if (!l.allFinite()) continue;
    const Eigen::Vector2d ql = frame.toRoad(l.cast<double>());
    double best = std::numeric_limits<double>::infinity(), lat = 0.0;
    for (const auto& r : R.points) {
      if (!r.allFinite()) continue;
      const Eigen::Vector2d qr = frame.toRoad(r.cast<double>());
      const double df = std::fabs(qr.x() - ql.x());
      if (df < best) {
        best = df;
        lat = ql.y() - qr.y();
      }
    }
    if (best < 2.0) width_samples_.push_back(lat);
  }
  if (width_samples_.size() < 3) return std::numeric_limits<double>::quiet_NaN();
  std::nth_element(width_samples_.begin(), width_samples_.begin() + width_samples_.size() / 2,
                   width_samples_.end());
  return width_samples_[width_samples_.size() / 2];
}

void LaneFitter::rejectIncomplete(Result& result) const {
  if (!params_.report_only_complete) return;
  result.left.found = false;
  result.right.found = false;
  result.left.confidence = result.right.confidence = 0.0f;
}

}  // namespace rgbd_lane_detector
