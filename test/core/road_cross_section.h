// Rendered cross-sections of a level road for the boundary classifier's tests: a camera kHeight
// above the road looking along it, the road's colour a function of the lateral position and the
// distance, boxes along the road (kerbs, sidewalks, a truck's top), and the classifier's input
// views on the rendered images.
#pragma once

#include <cmath>
#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/classifier_input.h"
#include "rgbd_lane_detector/half_binary.h"

namespace rgbd_lane_detector {
namespace test {

constexpr int kW = 640, kH = 380;
inline const Intrinsics kK{266.37, 266.37, 320.0, 190.0};
constexpr double kHeight = 1.5;

// A level road seen from kHeight, camera looking along the road (no pitch), with boxes running
// along the road (kerbs, sidewalks, a truck's top): the surface's colour (RGB) depends on the
// lateral position x (right) and the distance z.
struct Box {
  double x0, x1, height;  ///< lateral extent (m) and height above the road
};

struct CrossSection {
  std::function<cv::Vec3b(double x, double z)> colour = [](double, double) {
    return cv::Vec3b(90, 90, 90);
  };
  std::vector<Box> boxes;

  // the nearest surface along a pixel's ray (z = 1 units): road, box tops and box sides
  double hit(double rx, double ry) const {
    double best = ry > 1e-6 ? kHeight / ry : INFINITY;
    for (const Box& b : boxes) {
      const double top = kHeight - b.height;  // y of the top below the camera
      if (ry > 1e-6) {
        const double z = top / ry;
        if (rx * z >= b.x0 && rx * z <= b.x1) best = std::min(best, z);
      }
      for (double x : {b.x0, b.x1}) {
        if (std::fabs(rx) < 1e-9 || !std::isfinite(x)) continue;
        const double z = x / rx;
        if (z > 0 && ry * z >= top && ry * z <= kHeight) best = std::min(best, z);
      }
    }
    return best;
  }

  void render(cv::Mat& bgr, cv::Mat& points) const {
    bgr.create(kH, kW, CV_8UC3);
    bgr.setTo(cv::Scalar(200, 180, 160));  // sky
    points.create(kH, kW, CV_32FC3);
    points.setTo(cv::Scalar::all(std::nanf("")));
    for (int v = 0; v < kH; ++v) {
      for (int u = 0; u < kW; ++u) {
        const double rx = (u - kK.cx) / kK.fx, ry = (v - kK.cy) / kK.fy;
        const double z = hit(rx, ry);
        if (!(z <= 80.0)) continue;
        const cv::Vec3b rgb = colour(rx * z, z);
        bgr.at<cv::Vec3b>(v, u) = cv::Vec3b(rgb[2], rgb[1], rgb[0]);
        points.at<cv::Vec3f>(v, u) = cv::Vec3f(static_cast<float>(rx * z),
                                               static_cast<float>(ry * z), static_cast<float>(z));
      }
    }
  }
};

inline PlaneEstimate level() {
  PlaneEstimate p;
  p.valid = true;
  p.normal = Eigen::Vector3d(0, -1, 0);
  p.distance = kHeight;
  return p;
}

// Pixels of a line at lateral x on the road (height h), 4-25 m ahead, near to far.
inline std::vector<cv::Point2f> linePixels(double x, double h = 0.0) {
  std::vector<cv::Point2f> px;
  for (double z = 4.0; z <= 25.0; z *= 1.08)
    px.emplace_back(static_cast<float>(kK.fx * x / z + kK.cx),
                    static_cast<float>(kK.fy * (kHeight - h) / z + kK.cy));
  return px;
}

inline cv::Vec3b grey(int g) {
  return cv::Vec3b(g, g, g);
}

// Lateral position (m, right) on the level road of an input pixel.
inline double roadLateral(const cv::Point2f& c) {
  const double z = kK.fy * kHeight / (c.y - kK.cy);
  return (c.x - kK.cx) / kK.fx * z;
}
inline double roadForward(const cv::Point2f& c) {
  return kK.fy * kHeight / (c.y - kK.cy);
}

// The classifier's input views on a colour image @p bgr (its grey made into @p grey), its
// @p points and road @p plane, seen with @p K.
inline ClassifierInput classifierInput(const cv::Mat& bgr, cv::Mat& grey, const cv::Mat& points,
                                       const PlaneEstimate& plane, const Intrinsics& K) {
  halfBinary(bgr, PixelFormat::kBgr8, 0, cv::Range(0, bgr.rows), grey);  // threshold 0: grey
  ClassifierInput in;
  in.colour = &bgr;
  in.format = PixelFormat::kBgr8;
  in.grey = &grey;
  in.grey_rows = cv::Range(0, bgr.rows);
  in.K = K;
  in.points = &points;
  in.plane = &plane;
  in.frame = RoadFrame::fromPlane(plane);
  return in;
}

// A rendered road and the classifier's input views on it.
struct RenderedRoad {
  cv::Mat bgr, grey, points;
  PlaneEstimate plane = level();
  ClassifierInput in;

  void render(const CrossSection& cs) {
    cs.render(bgr, points);
    in = classifierInput(bgr, grey, points, plane, kK);
  }
};

}  // namespace test
}  // namespace rgbd_lane_detector
