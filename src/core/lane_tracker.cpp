#include "rgbd_lane_detector/lane_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

namespace rgbd_lane_detector {
namespace {

constexpr double kForwardScale = 20.0;  // m; keeps the normal equations well conditioned
// Ridge on the curvature term: a short, straight stretch of evidence must not yield a
// strongly curved model when extrapolated.
constexpr double kCurvatureRidge = 0.5;
// An established model whose evidence is this many frames old may be replaced at once by
// measurements that disagree with it (lane change, or a track that was wrong).
constexpr int kStaleAge = 3;
// Measurements nearer than this (m) get full weight.
constexpr double kNearRange = 10.0;
// Upper bound of the reported points per side.
constexpr int kMaxSamples = 40;

}  // namespace

PlaneFrame PlaneFrame::fromPlane(const PlaneEstimate& plane) {
  PlaneFrame f;
  if (!plane.valid) return f;
  const Eigen::Vector3d n = plane.normal;
  Eigen::Vector3d fwd = Eigen::Vector3d::UnitZ() - n * n.z();
  if (fwd.norm() < 1e-6) return f;
  f.forward = fwd.normalized();
  f.lateral = f.forward.cross(n).normalized();
  f.origin = -plane.distance * n;
  f.valid = true;
  return f;
}

void SideModel::reset() {
  A_.setZero();
  b_.setZero();
  coef_.setZero();
  num_extents_ = next_extent_ = 0;
  age_ = 0;
  frames_with_evidence_ = 0;
  valid_ = false;
}

Eigen::Vector3d SideModel::basis(double f) {
  const double s = f / kForwardScale;
  return Eigen::Vector3d(1.0, s, s * s);
}

double SideModel::lateral(double f) const { return coef_.dot(basis(f)); }

double SideModel::nearest() const {
  double v = std::numeric_limits<double>::infinity();
  for (int i = 0; i < num_extents_; ++i) v = std::min(v, extents_[i].x());
  return v;
}

double SideModel::farthest() const {
  double v = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < num_extents_; ++i) v = std::max(v, extents_[i].y());
  return v;
}

void SideModel::solve() {
  Eigen::Matrix3d M = A_;
  M(0, 0) += 1e-9;
  M(1, 1) += 1e-9;
  M(2, 2) += kCurvatureRidge;
  coef_ = M.ldlt().solve(b_);
  if (!coef_.allFinite()) reset();
}

int SideModel::update(const std::vector<Eigen::Vector2d>& m, const TrackerParams& params) {
  A_ *= params.memory;
  b_ *= params.memory;
  int accepted = 0;
  double near = std::numeric_limits<double>::infinity(), far = -near;
  if (static_cast<int>(m.size()) >= params.min_points) {
    bool use_gate = valid_ && frames_with_evidence_ >= 2;
    if (use_gate) {
      int inliers = 0;
      for (const auto& q : m) inliers += std::fabs(q.y() - lateral(q.x())) <= params.gate;
      if (2 * inliers < static_cast<int>(m.size())) {
        if (age_ >= kStaleAge) {
          reset();  // the evidence moved for good: start over from this frame
          use_gate = false;
        } else {
          use_gate = true;  // a stray frame: its disagreeing points are rejected below
        }
      }
    }
    for (const auto& q : m) {
      if (use_gate && std::fabs(q.y() - lateral(q.x())) > params.gate) continue;
      // a pixel's lateral extent grows with distance: weight 1/f^2 beyond kNearRange
      const double r = std::max(q.x(), kNearRange) / kNearRange;
      const double w = 1.0 / (r * r);
      const Eigen::Vector3d phi = basis(q.x());
      A_.noalias() += w * phi * phi.transpose();
      b_.noalias() += w * phi * q.y();
      near = std::min(near, q.x());
      far = std::max(far, q.x());
      ++accepted;
    }
  }
  if (accepted >= params.min_points) {
    extents_[next_extent_] = Eigen::Vector2d(near, far);
    next_extent_ = (next_extent_ + 1) % static_cast<int>(extents_.size());
    num_extents_ = std::min(num_extents_ + 1, static_cast<int>(extents_.size()));
    age_ = 0;
    ++frames_with_evidence_;
    valid_ = true;
    solve();
  } else if (valid_ && ++age_ > params.max_age) {
    reset();
  }
  return accepted;
}

void LaneTracker::reset() {
  for (auto& s : sides_) s.reset();
}

int LaneTracker::update(int i, const PlaneFrame& frame, const std::vector<Eigen::Vector3f>& points,
                        const TrackerParams& params, std::vector<Eigen::Vector2d>& scratch) {
  scratch.clear();
  if (frame.valid) {
    for (const auto& p : points)
      if (p.allFinite()) scratch.push_back(frame.toPlane(p.cast<double>()));
  }
  return sides_[i].update(scratch, params);
}

void LaneTracker::sample(int i, const PlaneFrame& frame, double step,
                         std::vector<Eigen::Vector3f>& out) const {
  out.clear();
  const SideModel& s = sides_[i];
  if (!s.valid() || !frame.valid || !(step > 0.0)) return;
  double near = s.nearest(), far = s.farthest();
  const SideModel& other = sides_[1 - i];
  if (other.valid()) {
    near = std::min(near, other.nearest());
    far = std::max(far, other.farthest());
  }
  near = std::max(near, 0.5);
  if (!(far >= near)) return;
  // Uniform in 1/f, i.e. about uniform in image rows like the traced centroids: the far range,
  // where a pixel spans decimetres, does not dominate the reported points.
  const int count = std::max(2, static_cast<int>(std::ceil((far - near) / step)));
  const int n = std::min(count, kMaxSamples);
  const double a = 1.0 / near, b = 1.0 / far;
  for (int k = 0; k < n; ++k) {
    const double f = 1.0 / (a + (b - a) * k / (n - 1));
    out.push_back(frame.toCamera(f, s.lateral(f)).cast<float>());
  }
}

}  // namespace rgbd_lane_detector
