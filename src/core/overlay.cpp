#include "rgbd_lane_detector/overlay.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

namespace rgbd_lane_detector {
namespace {

const cv::Scalar kLeftColour(60, 220, 60);     // green: left paint
const cv::Scalar kRightColour(0, 150, 255);    // orange: right paint
const cv::Scalar kEdgeColour(60, 40, 255);     // red: a road edge (kerb, rail, unpainted edge)
const cv::Scalar kPlaneColour(255, 200, 0);    // cyan-blue
const cv::Scalar kRoiColour(200, 200, 200);

bool project(const Intrinsics& K, const Eigen::Vector3d& p, cv::Point& out) {
  if (!(p.z() > 0.1)) return false;
  const cv::Point2d q = K.project(p);
  out = cv::Point(static_cast<int>(std::lround(q.x)), static_cast<int>(std::lround(q.y)));
  return true;
}

void drawMarker(cv::Mat& out, const MarkerTrace& m, const cv::Scalar& paint_colour, int box) {
  if (m.seed.x < 0) return;
  const bool edge = m.found && m.kind == BoundaryKind::kRoadEdge;
  const cv::Scalar colour = edge ? kEdgeColour : paint_colour;
  for (size_t i = 1; i < m.pixels.size(); ++i)
    cv::line(out, m.pixels[i - 1], m.pixels[i], colour, edge ? 3 : 2, cv::LINE_AA);
  for (const auto& p : m.pixels) {
    if (edge) {  // road edges: squares
      cv::rectangle(out, p - cv::Point2f(3, 3), p + cv::Point2f(3, 3), colour, -1);
    } else {
      cv::circle(out, p, 3, colour, m.found ? -1 : 1, cv::LINE_AA);
    }
  }
  const cv::Point2f half(0.5f * box, 0.5f * box);
  cv::rectangle(out, m.seed - half, m.seed + half, colour, 1);
  const cv::Point2f dir(static_cast<float>(std::cos(m.angle)), static_cast<float>(std::sin(m.angle)));
  cv::arrowedLine(out, m.seed - dir * (0.5f * box), m.seed + dir * (0.5f * box), colour, 1,
                  cv::LINE_AA, 0, 0.3);
}

void drawPlaneGrid(cv::Mat& out, const Intrinsics& K, const PlaneEstimate& plane) {
  if (!plane.valid || !K.valid()) return;
  // Orthonormal basis of the plane: "forward" is the optical axis projected into the plane.
  const Eigen::Vector3d n = plane.normal;
  Eigen::Vector3d fwd = Eigen::Vector3d::UnitZ() - n * n.z();
  if (fwd.norm() < 1e-6) return;
  fwd.normalize();
  const Eigen::Vector3d side = fwd.cross(n).normalized();
  const Eigen::Vector3d origin = -plane.distance * n;  // foot of the camera on the plane
  for (int i = -3; i <= 3; ++i) {       // lines along the road every 1.8 m
    for (int k = 2; k < 40; k += 2) {
      cv::Point a, b;
      const Eigen::Vector3d pa = origin + side * (1.8 * i) + fwd * k;
      const Eigen::Vector3d pb = origin + side * (1.8 * i) + fwd * (k + 2);
      if (project(K, pa, a) && project(K, pb, b)) cv::line(out, a, b, kPlaneColour, 1, cv::LINE_AA);
    }
  }
  for (int k = 4; k <= 40; k += 4) {    // cross lines every 4 m
    cv::Point a, b;
    if (project(K, origin + fwd * k - side * 5.4, a) && project(K, origin + fwd * k + side * 5.4, b))
      cv::line(out, a, b, kPlaneColour, 1, cv::LINE_AA);
  }
}

}  // namespace

void drawOverlay(const cv::Mat& colour, PixelFormat format, const Intrinsics& K,
                 const Result& result, const Params& params, cv::Mat& out) {
  // to bgr8 from the format's layout (types.h)
  const PixelLayout layout = pixelLayout(format);
  if (layout.channels == 3 && layout.b == 0)
    colour.copyTo(out);
  else if (layout.channels != 0)
    cv::cvtColor(colour, out,
                 layout.channels == 1   ? cv::COLOR_GRAY2BGR
                 : layout.channels == 3 ? cv::COLOR_RGB2BGR
                 : layout.b == 0        ? cv::COLOR_BGRA2BGR
                                        : cv::COLOR_RGBA2BGR);
  if (out.empty()) return;
  if (result.status != Status::kOk) {
    cv::putText(out, statusMessage(result.status), cv::Point(10, 20), cv::FONT_HERSHEY_SIMPLEX,
                0.5, cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
    return;
  }
  const double inv = result.scale > 0 ? 1.0 / result.scale : 1.0;
  const int top = static_cast<int>(std::lround(result.roi.y * inv));
  cv::line(out, cv::Point(0, top), cv::Point(out.cols - 1, top), kRoiColour, 1);
  drawPlaneGrid(out, K, result.plane);
  const int box = static_cast<int>(std::lround(params.template_size * inv));
  drawMarker(out, result.left, kLeftColour, box);
  drawMarker(out, result.right, kRightColour, box);

  char text[200];
  auto sideText = [](const MarkerTrace& m) {
    return !m.found ? "-" : m.kind == BoundaryKind::kRoadEdge ? "road edge" : "paint";
  };
  std::snprintf(text, sizeof(text), "L %s %.2f (%d pts)  R %s %.2f (%d pts)  %.1f ms",
                sideText(result.left), result.left.confidence, result.left.num_valid_points,
                sideText(result.right), result.right.confidence, result.right.num_valid_points,
                result.timings.total);
  cv::putText(out, text, cv::Point(10, 20), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255),
              1, cv::LINE_AA);
  if (result.plane.valid) {
    std::snprintf(text, sizeof(text), "plane n=(%.3f %.3f %.3f) d=%.2f m", result.plane.normal.x(),
                  result.plane.normal.y(), result.plane.normal.z(), result.plane.distance);
  } else {
    std::snprintf(text, sizeof(text), "no plane");
  }
  cv::putText(out, text, cv::Point(10, 40), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255),
              1, cv::LINE_AA);
}

void drawCandidates(const BoundaryCandidate* candidates, int count, cv::Mat& out) {
  for (int k = 0; k < count; ++k) {
    const BoundaryCandidate& c = candidates[k];
    const std::vector<cv::Point2f>& px = c.trace.pixels;
    if (px.empty()) continue;
    const BoundaryEvidence& ev = c.evidence;
    const cv::Scalar colour = !ev.boundary                            ? cv::Scalar(160, 160, 160)
                              : ev.kind == BoundaryKind::kRoadEdge ? cv::Scalar(255, 0, 255)
                                                                   : cv::Scalar(255, 255, 0);
    for (size_t i = 1; i < px.size(); ++i) cv::line(out, px[i - 1], px[i], colour, 1, cv::LINE_AA);
    char text[160];
    std::snprintf(text, sizeof(text), "%d %s%s w%.0f h%.0f/%.0f/%.0f r%.0f o%.2f n%d/%d", k,
                  ev.reason, c.usable ? "" : " (x)", 100.0 * ev.width, 100.0 * ev.inner_height,
                  100.0 * ev.line_height, 100.0 * ev.outer_height, ev.ridge_contrast, c.offset,
                  static_cast<int>(c.road.size()), static_cast<int>(px.size()));
    const cv::Point2f at = px[px.size() / 2] + cv::Point2f(6.f, 0.f);
    cv::putText(out, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.35, colour, 1, cv::LINE_AA);
  }
}

void drawLaneGridInset(const LaneGrid& grid, cv::Mat& out) {
  const int h = static_cast<int>(0.45 * out.rows);
  const int w = grid.cols() > 0 ? h * grid.rows() / grid.cols() : 0;
  const int margin = 8;
  if (out.type() != CV_8UC3 || h < 16 || w < 4 || w + 2 * margin > out.cols ||
      h + 2 * margin > out.rows)
    return;
  const int u0 = out.cols - margin - w, v0 = out.rows - margin - h;
  auto rank = [](int8_t v) {  // what an inset pixel shows of the cells it covers
    return v == LaneGrid::kOccupied ? 3 : v == LaneGrid::kCrossable ? 2 : v == LaneGrid::kFree ? 1 : 0;
  };
  const cv::Vec3b colours[4] = {cv::Vec3b(0, 0, 0), cv::Vec3b(60, 200, 60), cv::Vec3b(0, 220, 255),
                                cv::Vec3b(40, 40, 255)};
  for (int v = 0; v < h; ++v) {
    // rows of the picture: x from the far end (top) to the vehicle (bottom)
    const int c_lo = (h - 1 - v) * grid.cols() / h;
    const int c_hi = std::max(c_lo, (h - v) * grid.cols() / h - 1);
    cv::Vec3b* px = out.ptr<cv::Vec3b>(v0 + v) + u0;
    for (int u = 0; u < w; ++u, ++px) {
      // columns of the picture: y from the left end (left) to the right end (right)
      const int r_lo = (w - 1 - u) * grid.rows() / w;
      const int r_hi = std::max(r_lo, (w - u) * grid.rows() / w - 1);
      int best = 0;
      for (int c = c_lo; c <= c_hi && best < 3; ++c)
        for (int r = r_lo; r <= r_hi; ++r) best = std::max(best, rank(grid.at(r, c)));
      if (best == 0) {
        *px = cv::Vec3b((*px)[0] / 3, (*px)[1] / 3, (*px)[2] / 3);
      } else {
        const cv::Vec3b& c = colours[best];
        *px = cv::Vec3b(static_cast<uchar>(((*px)[0] + 3 * c[0]) / 4),
                        static_cast<uchar>(((*px)[1] + 3 * c[1]) / 4),
                        static_cast<uchar>(((*px)[2] + 3 * c[2]) / 4));
      }
    }
  }
  cv::rectangle(out, cv::Rect(u0 - 1, v0 - 1, w + 2, h + 2), kRoiColour, 1);
  const double length = grid.cols() * grid.resolution();
  for (double x = 10.0; x < length; x += 10.0) {  // a tick every 10 m
    const int v = v0 + h - 1 - static_cast<int>(std::lround(x / length * h));
    cv::line(out, cv::Point(u0 - 5, v), cv::Point(u0 - 1, v), kRoiColour, 1);
  }
  // the vehicle at y = 0 (the grid's middle when it is centred), x = 0
  const int uc = u0 + static_cast<int>(std::lround(w * (grid.originY() + grid.rows() * grid.resolution()) /
                                                   (grid.rows() * grid.resolution())));
  const cv::Point tip(uc, v0 + h - 7), l(uc - 4, v0 + h + 1), r(uc + 4, v0 + h + 1);
  cv::line(out, l, tip, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  cv::line(out, tip, r, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
}

}  // namespace rgbd_lane_detector
