#include "synthetic_scene.h"

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

}  // namespace test
}  // namespace rgbd_lane_detector
