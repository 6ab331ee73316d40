#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector/lane_plane.h"

// Lane plane fitting, plausibility checks and the temporal lane model of LaneDetector
// (METHOD.md section 4 and the named improvements).

namespace rgbd_lane_detector {

void LaneDetector::fitPlane(Result& result) {
  const Params& p = params_;
  MarkerTrace& L = result.left;
  MarkerTrace& R = result.right;
  // plane gate: drop marker points far from the previous plane
  if (p.plane_gate > 0.0 && previous_plane_.valid) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (MarkerTrace* m : {&L, &R}) {
      for (auto& q : m->points) {
        if (!std::isnan(q.z()) && std::fabs(planeDistance(previous_plane_, q)) > p.plane_gate) {
          q = Eigen::Vector3f(nan, nan, nan);
          --m->num_valid_points;
        }
      }
    }
  }
  L.found = L.num_valid_points >= p.min_marker_points;
  R.found = R.num_valid_points >= p.min_marker_points;
  PlaneEstimate& plane = result.plane;
  plane.valid = false;
  if (p.track_lanes) {
    fitTracked(result);
    return;
  }
  if (!L.found || !R.found) {
    rejectIncomplete(result);
    return;
  }

  if (p.plane_fit == PlaneFit::kThreePoint) {
    // v_a1: best left match, v_b: best right match, v_a2: furthest right centroid
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const Eigen::Vector3f& a1 = L.seed_point;
    const Eigen::Vector3f& b = R.seed_point;
    Eigen::Vector3f a2(nan, nan, nan);
    for (auto it = R.points.rbegin(); it != R.points.rend(); ++it) {
      if (!std::isnan(it->z())) {
        a2 = *it;
        break;
      }
    }
    planeFromThreePoints(a1, b, a2, plane);
  } else {
    fit_points_.clear();
    for (const auto& q : L.points) fit_points_.push_back(q);
    for (const auto& q : R.points) fit_points_.push_back(q);
    fitPlaneLeastSquares(fit_points_, 0.1, 3, plane);
  }
  if (!plane.valid || !planePlausible(plane)) {
    plane.valid = false;
    rejectIncomplete(result);
    return;
  }
  if (p.plane_smoothing > 0.0 && previous_plane_.valid) {
    const double w = p.plane_smoothing;
    Eigen::Vector3d n = (1.0 - w) * plane.normal + w * previous_plane_.normal;
    const double len = n.norm();
    if (len > 1e-9) {
      plane.normal = n / len;
      plane.distance = (1.0 - w) * plane.distance + w * previous_plane_.distance;
    }
  }
  if (p.snap_to_plane) {
    snapToPlane(plane, L);
    snapToPlane(plane, R);
  }
  if (!laneWidthPlausible(plane, L, R)) {
    plane.valid = false;
    rejectIncomplete(result);
  }
}

bool LaneDetector::planePlausible(const PlaneEstimate& plane) const {
  const Params& p = params_;
  const Eigen::Vector3d up(p.up_x, p.up_y, p.up_z);
  // the normal points toward the camera, i.e. up; allow |tilt| up to plane_max_tilt_deg
  const double cos_tilt = plane.normal.dot(up);
  if (p.plane_max_tilt_deg < 90.0 && cos_tilt < std::cos(p.plane_max_tilt_deg * M_PI / 180.0))
    return false;
  return plane.distance >= p.plane_distance_min && plane.distance <= p.plane_distance_max;
}

void LaneDetector::snapToPlane(const PlaneEstimate& plane, MarkerTrace& m) const {
  // Markers are paint on the road: their 3D points are where their pixel rays meet the plane.
  m.num_valid_points = 0;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (size_t i = 0; i < m.pixels.size(); ++i) {
    const Eigen::Vector3d ray((m.pixels[i].x - proc_K_.cx) / proc_K_.fx,
                              (m.pixels[i].y - proc_K_.cy) / proc_K_.fy, 1.0);
    const double denom = plane.normal.dot(ray);
    const double t = denom < -1e-9 ? -plane.distance / denom : -1.0;
    if (t > 0.0 && t * ray.z() <= params_.max_depth) {
      m.points[i] = (ray * t).cast<float>();
      ++m.num_valid_points;
    } else {
      m.points[i] = Eigen::Vector3f(nan, nan, nan);
    }
  }
  m.found = m.num_valid_points >= params_.min_marker_points;
}

bool LaneDetector::laneWidthPlausible(const PlaneEstimate& plane, const MarkerTrace& L,
                                      const MarkerTrace& R) const {
  const Params& p = params_;
  if (p.lane_width_max <= 0.0) return true;
  // lateral axis of the road: the optical axis projected into the plane, crossed with the normal
  Eigen::Vector3d fwd = Eigen::Vector3d::UnitZ() - plane.normal * plane.normal.z();
  if (fwd.norm() < 1e-6) return false;
  fwd.normalize();
  const Eigen::Vector3d side = fwd.cross(plane.normal).normalized();
  // for each left point, the right point nearest in the forward direction
  width_samples_.clear();
  for (const auto& l : L.points) {
    if (!l.allFinite()) continue;
    const double fl = fwd.dot(l.cast<double>());
    double best = std::numeric_limits<double>::infinity(), lat = 0.0;
    for (const auto& r : R.points) {
      if (!r.allFinite()) continue;
      const double df = std::fabs(fwd.dot(r.cast<double>()) - fl);
      if (df < best) {
        best = df;
        lat = side.dot((r - l).cast<double>());
      }
    }
    if (best < 2.0) width_samples_.push_back(std::fabs(lat) * (lat >= 0 ? 1.0 : -1.0));
  }
  if (width_samples_.size() < 3) return false;
  std::nth_element(width_samples_.begin(), width_samples_.begin() + width_samples_.size() / 2,
                   width_samples_.end());
  const double width = width_samples_[width_samples_.size() / 2];
  return width >= p.lane_width_min && width <= p.lane_width_max;
}

void LaneDetector::fitTracked(Result& result) {
  const Params& p = params_;
  MarkerTrace* sides[2] = {&result.left, &result.right};
  PlaneEstimate& plane = result.plane;
  TrackerParams tp;
  tp.memory = p.track_memory;
  tp.max_age = p.track_max_age;
  tp.gate = p.track_gate;
  tp.min_points = p.min_marker_points;

  // Plane: least squares over this frame's traced points; a side without evidence but with a
  // live model contributes its model's points on the previous plane.
  fit_points_.clear();
  const PlaneFrame previous = PlaneFrame::fromPlane(previous_plane_);
  for (int i = 0; i < 2; ++i) {
    if (sides[i]->found) {
      for (const auto& q : sides[i]->points)
        if (q.allFinite()) fit_points_.push_back(q);
    } else if (tracker_.valid(i) && previous.valid) {
      tracker_.sample(i, previous, tp.sample_step, samples_);
      fit_points_.insert(fit_points_.end(), samples_.begin(), samples_.end());
    }
  }
  const bool any_evidence = sides[0]->found || sides[1]->found;
  bool have_plane = any_evidence && fitPlaneLeastSquares(fit_points_, 0.1, 3, plane) &&
                    planePlausible(plane);
  if (!have_plane && previous_plane_.valid && tracker_.valid(0) &&
      tracker_.valid(1)) {
    // Coast: no usable evidence this frame (a gap in both dashed lines, a washed-out frame);
    // keep the last plane while both lane models live (at most track_max_age frames).
    plane.valid = true;
    plane.normal = previous_plane_.normal;
    plane.distance = previous_plane_.distance;
    plane.support.clear();
    plane.rms = 0.0;
    plane.fit_method = static_cast<int>(PlaneFit::kLeastSquares);
    have_plane = true;
  }
  if (!have_plane) {
    plane.valid = false;
    tracker_.update(PlaneFrame(), samples_none_, samples_none_, tp);  // ages the models
    for (int i = 0; i < 2; ++i) sides[i]->found = false;
    return;
  }
  if (p.plane_smoothing > 0.0 && previous_plane_.valid) {
    const double w = p.plane_smoothing;
    const Eigen::Vector3d n = (1.0 - w) * plane.normal + w * previous_plane_.normal;
    if (n.norm() > 1e-9) {
      plane.normal = n.normalized();
      plane.distance = (1.0 - w) * plane.distance + w * previous_plane_.distance;
    }
  }
  // Evidence in this plane's coordinates (paint lies on the road: rays met with the plane),
  // then each side is reported as its model over the range of its recent evidence.
  const PlaneFrame frame = PlaneFrame::fromPlane(plane);
  for (int i = 0; i < 2; ++i)
    if (sides[i]->found) snapToPlane(plane, *sides[i]);
  tracker_.update(frame, result.left.found ? result.left.points : samples_none_,
                  result.right.found ? result.right.points : samples_none_, tp);
  for (int i = 0; i < 2; ++i) {
    MarkerTrace& m = *sides[i];
    tracker_.sample(i, frame, tp.sample_step, m.points);
    m.pixels.clear();
    m.scores.clear();
    m.num_valid_points = 0;
    for (const auto& q : m.points) {
      m.pixels.emplace_back(static_cast<float>(proc_K_.fx * q.x() / q.z() + proc_K_.cx),
                            static_cast<float>(proc_K_.fy * q.y() / q.z() + proc_K_.cy));
      m.scores.push_back(m.peak_score);
      ++m.num_valid_points;
    }
    m.found = m.num_valid_points >= p.min_marker_points;
  }
  if (!result.left.found || !result.right.found ||
      !laneWidthPlausible(plane, result.left, result.right)) {
    plane.valid = false;
    rejectIncomplete(result);
  }
}

void LaneDetector::rejectIncomplete(Result& result) const {
  if (!params_.report_only_complete) return;
  result.left.found = false;
  result.right.found = false;
}

}  // namespace rgbd_lane_detector
