#include "rgbd_lane_detector_tools/plane_check.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>

namespace rgbd_lane_detector {
namespace tools {

cv::Rect roadCheckRegion(const cv::Size& size, const Intrinsics& K, int horizon_margin,
                         double width_fraction) {
  const int top = std::min(size.height - 1, std::max(0, static_cast<int>(K.cy) + horizon_margin));
  const int w = std::max(1, static_cast<int>(size.width * width_fraction));
  const int left = std::max(0, static_cast<int>(K.cx) - w / 2);
  return cv::Rect(left, top, std::min(w, size.width - left), size.height - top);
}

void regionPoints(const cv::Mat& depth, double scale, const Intrinsics& K, const cv::Rect& region,
                  double max_depth, std::vector<Eigen::Vector3d>& points) {
  points.clear();
  const cv::Rect r = region & cv::Rect(0, 0, depth.cols, depth.rows);
  for (int v = r.y; v < r.y + r.height; ++v) {
    for (int u = r.x; u < r.x + r.width; ++u) {
      double z;
      if (depth.type() == CV_16UC1) {
        const uint16_t raw = depth.at<uint16_t>(v, u);
        if (raw == 0) continue;
        z = raw * scale;
      } else if (depth.type() == CV_32FC1) {
        z = depth.at<float>(v, u);
      } else {
        return;
      }
      if (!std::isfinite(z) || z <= 0.0 || z > max_depth) continue;
      points.emplace_back((u - K.cx) / K.fx * z, (v - K.cy) / K.fy * z, z);
    }
  }
}

PlaneResiduals planeResiduals(const std::vector<Eigen::Vector3d>& points,
                              const Eigen::Vector3d& normal, double distance) {
  PlaneResiduals r;
  if (points.empty()) return r;
  std::vector<double> res;
  res.reserve(points.size());
  for (const auto& p : points) res.push_back(std::fabs(normal.dot(p) + distance));
  r.points = static_cast<int>(res.size());
  double sum = 0;
  int near = 0;
  for (double v : res) {
    sum += v;
    near += v <= 0.10;
  }
  r.mean_abs = sum / res.size();
  r.within_10cm = static_cast<double>(near) / res.size();
  std::nth_element(res.begin(), res.begin() + res.size() / 2, res.end());
  r.median_abs = res[res.size() / 2];
  return r;
}

bool ransacPlane(const std::vector<Eigen::Vector3d>& points, double inlier_distance,
                 Eigen::Vector3d& normal, double& distance, double min_spread) {
  const size_t n = points.size();
  if (n < 50) return false;
  std::mt19937 rng(12345u);
  std::uniform_int_distribution<size_t> pick(0, n - 1);
  size_t best_count = 0;
  Eigen::Vector3d best_n = Eigen::Vector3d::UnitY();
  double best_d = 0;
  for (int it = 0; it < 300; ++it) {
    const Eigen::Vector3d& a = points[pick(rng)];
    const Eigen::Vector3d& b = points[pick(rng)];
    const Eigen::Vector3d& c = points[pick(rng)];
    Eigen::Vector3d nn = (b - a).cross(c - a);
    if (nn.norm() < 1e-9) continue;
    nn.normalize();
    const double d = -nn.dot(a);
    size_t count = 0;
    for (const auto& p : points) count += std::fabs(nn.dot(p) + d) <= inlier_distance;
    if (count > best_count) {
      best_count = count;
      best_n = nn;
      best_d = d;
    }
  }
  if (best_count < 0.3 * n) return false;
  // least-squares refit on the inliers
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::vector<const Eigen::Vector3d*> in;
  for (const auto& p : points)
    if (std::fabs(best_n.dot(p) + best_d) <= inlier_distance) in.push_back(&p);
  for (const auto* p : in) mean += *p;
  mean /= static_cast<double>(in.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto* p : in) cov += (*p - mean) * (*p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  // inliers along one line (a wet road returning only from one painted line) leave the plane
  // free to turn about that line: the spread across it must fix the plane
  if (std::sqrt(std::max(0.0, es.eigenvalues()(1) / static_cast<double>(in.size()))) <
      min_spread)
    return false;
  normal = es.eigenvectors().col(0).normalized();
  distance = -normal.dot(mean);
  if (distance < 0) {  // toward the camera: the origin lies on the positive side
    normal = -normal;
    distance = -distance;
  }
  return true;
}

}  // namespace tools
}  // namespace rgbd_lane_detector
