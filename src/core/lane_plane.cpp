#include "rgbd_lane_detector/lane_plane.h"

#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

namespace rgbd_lane_detector {
namespace {

bool finite(const Eigen::Vector3f& p) { return p.allFinite(); }

// Orient n . p + d = 0 so that the camera centre is on the positive side (d > 0).
bool orient(Eigen::Vector3d& n, double& d) {
  if (!n.allFinite() || !std::isfinite(d) || std::fabs(d) < 1e-6) return false;
  if (d < 0) {
    n = -n;
    d = -d;
  }
  return true;
}

void invalidate(PlaneEstimate& out) {
  out.valid = false;
  out.normal.setZero();
  out.distance = 0.0;
  out.rms = 0.0;
}

}  // namespace

bool planeFromThreePoints(const Eigen::Vector3f& a1, const Eigen::Vector3f& b,
                          const Eigen::Vector3f& a2, PlaneEstimate& out) {
  out.support.clear();
  out.fit_method = 0;
  invalidate(out);
  if (!finite(a1) || !finite(b) || !finite(a2)) return false;
  const Eigen::Vector3d e1 = (b - a1).cast<double>(), e2 = (a2 - a1).cast<double>();
  const double l1 = e1.norm(), l2 = e2.norm();
  if (l1 < 1e-6 || l2 < 1e-6) return false;
  Eigen::Vector3d n = e1.cross(e2);
  const double sin_angle = n.norm() / (l1 * l2);
  if (!(sin_angle > 1e-2)) return false;  // collinear within ~0.6 degrees
  n.normalize();
  double d = -n.dot(a1.cast<double>());
  if (!orient(n, d)) return false;
  out.valid = true;
  out.normal = n;
  out.distance = d;
  out.support = {a1, b, a2};
  return true;
}

bool fitPlaneLeastSquares(const std::vector<Eigen::Vector3f>& points, double inlier_distance,
                          int iterations, PlaneEstimate& out) {
  out.fit_method = 1;
  invalidate(out);
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  double d = 0.0;
  bool have = false;
  for (int it = 0; it <= iterations; ++it) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    int count = 0;
    for (const auto& p : points) {
      if (!finite(p)) continue;
      if (have && std::fabs(n.dot(p.cast<double>()) + d) > inlier_distance) continue;
      mean += p.cast<double>();
      ++count;
    }
    if (count < 3) break;
    mean /= count;
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    for (const auto& p : points) {
      if (!finite(p)) continue;
      if (have && std::fabs(n.dot(p.cast<double>()) + d) > inlier_distance) continue;
      const Eigen::Vector3d q = p.cast<double>() - mean;
      C.noalias() += q * q.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
    const Eigen::Vector3d ev = es.eigenvalues();  // ascending
    // Collinear (or coincident) points: the two smallest spreads are both ~0.
    if (!(ev[1] > 1e-8 * std::max(ev[2], 1e-12))) break;
    Eigen::Vector3d cand = es.eigenvectors().col(0);
    double cand_d = -cand.dot(mean);
    if (!orient(cand, cand_d)) break;
    n = cand;
    d = cand_d;
    have = true;
  }
  out.support.clear();
  if (!have) return false;
  double sq = 0.0;
  for (const auto& p : points) {
    if (!finite(p)) continue;
    const double r = n.dot(p.cast<double>()) + d;
    if (std::fabs(r) > inlier_distance) continue;
    out.support.push_back(p);
    sq += r * r;
  }
  if (out.support.size() < 3) {
    out.support.clear();
    return false;
  }
  out.valid = true;
  out.normal = n;
  out.distance = d;
  out.rms = std::sqrt(sq / out.support.size());
  return true;
}

}  // namespace rgbd_lane_detector
