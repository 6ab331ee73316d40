#include "synthetic_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rgbd_lane_detector {
namespace test {

Eigen::Vector3d RoadScene::planeNormal() const {
  return Eigen::Vector3d(0.0, -std::cos(pitch), -std::sin(pitch));
}

void RoadScene::render(cv::Mat& bgr, cv::Mat& depth_mm, cv::Mat* depth_m) const {
  bgr.create(height, width, CV_8UC3);
  depth_mm.create(height, width, CV_16UC1);
  if (depth_m) depth_m->create(height, width, CV_32FC1);
  const Eigen::Vector3d down(0.0, std::cos(pitch), std::sin(pitch));
  const Eigen::Vector3d forward(0.0, -std::sin(pitch), std::cos(pitch));
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const Eigen::Vector3d ray((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
      const double denom = down.dot(ray);
      int grey = sky;
      float z = 0.f;
      if (denom > 1e-9) {
        const Eigen::Vector3d p = ray * (camera_height / denom);
        if (p.z() <= max_range) {
          z = static_cast<float>(p.z());
          const double X = p.x(), F = forward.dot(p);
          grey = asphalt;
          auto on = [&](double centre, bool dashed) {
            if (std::fabs(X - centre) > 0.5 * marker_width) return false;
            if (!dashed) return true;
            return std::fmod(F + travelled, dash_period) < dash_length;
          };
          if ((left_painted && on(leftMarkerX(), left_dashed)) ||
              (right_painted && on(rightMarkerX(), right_dashed)))
            grey = paint;
          if (z < min_range) z = 0.f;
        }
      }
      bgr.at<cv::Vec3b>(v, u) = cv::Vec3b(grey, grey, grey);
      depth_mm.at<uint16_t>(v, u) = static_cast<uint16_t>(std::lround(z * 1000.0));
      if (depth_m) depth_m->at<float>(v, u) = z > 0.f ? z : std::numeric_limits<float>::quiet_NaN();
    }
  }
}

Eigen::Vector3d DepthScene::normal() const {
  return Eigen::Vector3d(0, -std::cos(pitch), -std::sin(pitch));
}

double DepthScene::hit(const Eigen::Vector3d& w) const {
  double best = INFINITY;
  if (w.y() > 1e-6) {
    double t = height / w.y();
    for (int it = 0; it < 50; ++it)  // smooth profiles
      t = (height + crest(t * w.z()) + camber(t * w.x())) / w.y();
    best = t;
  }
  for (const DepthBox& b : boxes) {
    const double top = height - b.h;
    auto inside = [&](double t, int skip) {
      const Eigen::Vector3d p = t * w;
      return t > 0 && (skip == 0 || (p.x() >= b.x0 && p.x() <= b.x1)) &&
             (skip == 1 || (p.z() >= b.z0 && p.z() <= b.z1)) && p.y() >= top - 1e-9 &&
             p.y() <= height + 1e-9;
    };
    if (w.y() > 1e-6 && inside(top / w.y(), 2)) best = std::min(best, top / w.y());
    for (double x : {b.x0, b.x1})
      if (std::fabs(w.x()) > 1e-9 && inside(x / w.x(), 0)) best = std::min(best, x / w.x());
    for (double z : {b.z0, b.z1})
      if (std::fabs(w.z()) > 1e-9 && inside(z / w.z(), 1)) best = std::min(best, z / w.z());
  }
  return best;
}

cv::Mat DepthScene::render() const {
  cv::Mat pts(image_height, image_width, CV_32FC3, cv::Scalar::all(std::nanf("")));
  cv::RNG rng(7);
  const double c = std::cos(pitch), s = std::sin(pitch);
  for (int v = 0; v < image_height; ++v) {
    for (int u = 0; u < image_width; ++u) {
      if (hole(u, v)) continue;
      const Eigen::Vector3d ray((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
      const Eigen::Vector3d w(ray.x(), c * ray.y() + s * ray.z(), -s * ray.y() + c * ray.z());
      const double t = hit(w);
      if (!(t * ray.z() <= 80.0)) continue;
      const double z = t * ray.z() + (noise > 0 ? rng.gaussian(noise) : 0.0);
      pts.at<cv::Vec3f>(v, u) = cv::Vec3f(static_cast<float>(ray.x() * z),
                                           static_cast<float>(ray.y() * z), static_cast<float>(z));
    }
  }
  return pts;
}

}  // namespace test
}  // namespace rgbd_lane_detector
