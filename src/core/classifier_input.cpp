#include "rgbd_lane_detector/classifier_input.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rgbd_lane_detector/geometry.h"

namespace rgbd_lane_detector {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr int kHeightSearch = 3;  // rows up and down a height is sought (sparse depth)

}  // namespace

bool ClassifierInput::roadAt(double u, double v, double& f, double& ppm) const {
  const Eigen::Vector3d ray = K.ray(u, v);
  double t;
  if (!rayPlaneDepth(*plane, ray, t)) return false;
  f = frame.toRoad(ray * t).x();
  ppm = K.fx / t;
  return true;
}

float ClassifierInput::heightAt(int u, int v) const {
  const cv::Mat& P = *points;
  const int x = static_cast<int>((u + 0.5) * scale_x);
  const int y = static_cast<int>((v + 0.5) * scale_y);
  if (x < 0 || y < 0 || x >= P.cols || y >= P.rows) return kNaN;
  // the pixel's own depth, else the nearest in its column within kHeightSearch rows (a LiDAR's
  // scan lines leave rows between them empty); filled road points are no measurement
  // (the column's point and mask addresses once, row by row from them)
  const uint8_t* column = P.data + 3 * sizeof(float) * x;
  const size_t step = P.step[0];
  const uint8_t* fill = filled != nullptr ? filled->data + x : nullptr;
  const size_t fill_step = filled != nullptr ? filled->step[0] : 0;
  auto height = [&](int yy, float& h) {
    if (fill != nullptr && fill[yy * fill_step] != 0) return false;
    const float* q = reinterpret_cast<const float*>(column + yy * step);
    if (!std::isfinite(q[2])) return false;
    h = static_cast<float>(planeDistance(*plane, Eigen::Vector3f(q[0], q[1], q[2])));
    return true;
  };
  float h = kNaN;
  if (height(y, h)) return h;
  for (int k = 1; k <= kHeightSearch; ++k) {
    if (y + k < P.rows && height(y + k, h)) return h;
    if (y - k >= 0 && height(y - k, h)) return h;
  }
  return kNaN;
}

Eigen::Vector3f ClassifierInput::pointAt(int u, int v) const {
  const cv::Mat& P = *points;
  const int x = static_cast<int>((u + 0.5) * scale_x);
  const int y = static_cast<int>((v + 0.5) * scale_y);
  if (x < 0 || y < 0 || x >= P.cols || y >= P.rows) return Eigen::Vector3f::Constant(kNaN);
  const float* q = P.ptr<float>(y) + 3 * x;
  return Eigen::Vector3f(q[0], q[1], q[2]);
}

double ClassifierInput::cosHeading(const std::vector<cv::Point2f>& pixels) const {
  // the line's heading in the road plane (profiles are read along image rows, i.e. across the
  // road: a band's width is its extent there times cos(heading))
  Eigen::Vector2d a(0, 0), b(0, 0);
  bool have_a = false;
  for (const auto& c : pixels) {
    const Eigen::Vector3d ray = K.ray(c.x, c.y);
    double depth;
    if (!rayPlaneDepth(*plane, ray, depth)) continue;
    const Eigen::Vector2d q = frame.toRoad(ray * depth);
    if (!have_a) {
      a = q;
      have_a = true;
    }
    b = q;
  }
  const Eigen::Vector2d t = b - a;
  return t.norm() > 0.5 ? std::max(0.5, std::fabs(t.x()) / t.norm()) : 1.0;
}

}  // namespace rgbd_lane_detector
