// Core results -> output messages (the other half of conversions.h; inputs and parameters are
// in conversions.cpp).
#include "rgbd_lane_detector/ros/conversions.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

namespace rgbd_lane_detector {
namespace conversions {
namespace enc = sensor_msgs::image_encodings;

namespace {

constexpr bool kHostBigEndian = __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__;

geometry_msgs::Point toPoint(const Eigen::Vector3d& p) {
  geometry_msgs::Point q;
  q.x = p.x();
  q.y = p.y();
  q.z = p.z();
  return q;
}

bool finite(const Eigen::Vector3f& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

bool reported(const MarkerTrace& m) { return m.found; }

void appendValidPoints(const MarkerTrace& m, const Eigen::Isometry3d& T,
                       std::vector<geometry_msgs::Point>& out) {
  out.clear();
  if (!reported(m)) return;
  out.reserve(m.points.size());
  for (const auto& p : m.points)
    if (finite(p)) out.push_back(toPoint(T * p.cast<double>()));
}

std_msgs::ColorRGBA rgba(float r, float g, float b, float a) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

visualization_msgs::Marker baseMarker(const std_msgs::Header& header, const char* ns, int id) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = ns;
  m.id = id;
  m.pose.orientation.w = 1.0;
  m.action = visualization_msgs::Marker::DELETE;
  return m;
}

// f(x) at x_min, x_min + step, ... and at x_max itself: a line drawn over its whole range (none
// for an empty range or a step that is not positive).
template <class F>
void alongRange(double x_min, double x_max, double step, F f) {
  if (!(step > 0.0) || !(x_max >= x_min)) return;
  for (double x = x_min; x < x_max - 1e-6; x += step) f(x);
  f(x_max);
}

// First and last valid point of a trace (near and far end); false when it has none.
bool ends(const MarkerTrace& m, Eigen::Vector3d& near_end, Eigen::Vector3d& far_end) {
  auto first = std::find_if(m.points.begin(), m.points.end(), finite);
  auto last = std::find_if(m.points.rbegin(), m.points.rend(), finite);
  if (first == m.points.end()) return false;
  near_end = first->cast<double>();
  far_end = last->cast<double>();
  return true;
}

}  // namespace

// ---------------------------------------------------------------------------
// Outputs

void fillLanePlane(const Result& result, const std_msgs::Header& header,
                   const Eigen::Isometry3d& T, LanePlane& msg) {
  const PlaneEstimate& plane = result.plane;
  msg.header = header;
  msg.valid = plane.valid;
  msg.left_score = reported(result.left) ? result.left.peak_score : 0.f;
  msg.right_score = reported(result.right) ? result.right.peak_score : 0.f;
  msg.fit_method = static_cast<uint8_t>(plane.fit_method);
  msg.support_points.clear();
  if (!plane.valid) {
    msg.normal = geometry_msgs::Vector3();
    msg.distance = 0.0;
    msg.rms_error = 0.f;
    msg.valid_range = 0.f;
    return;
  }
  msg.valid_range = static_cast<float>(plane.range);
  Eigen::Vector3d n = plane.normal;
  double d = plane.distance;
  transformPlane(T, n, d);
  msg.normal.x = n.x();
  msg.normal.y = n.y();
  msg.normal.z = n.z();
  msg.distance = d;
  msg.rms_error = static_cast<float>(plane.rms);
  msg.support_points.reserve(plane.support.size());
  for (const auto& p : plane.support)
    if (finite(p)) msg.support_points.push_back(toPoint(T * p.cast<double>()));
}

void fillLaneMarkings(const Result& result, const std_msgs::Header& header,
                      const Eigen::Isometry3d& T, LaneMarkings& msg) {
  msg.header = header;
  appendValidPoints(result.left, T, msg.left);
  appendValidPoints(result.right, T, msg.right);
  msg.left_score = reported(result.left) ? result.left.peak_score : 0.f;
  msg.right_score = reported(result.right) ? result.right.peak_score : 0.f;
  msg.left_angle = reported(result.left) ? static_cast<float>(result.left.angle) : 0.f;
  msg.right_angle = reported(result.right) ? static_cast<float>(result.right.angle) : 0.f;
  msg.left_kind = static_cast<uint8_t>(result.left.kind);
  msg.right_kind = static_cast<uint8_t>(result.right.kind);
  msg.left_confidence = reported(result.left) ? result.left.confidence : 0.f;
  msg.right_confidence = reported(result.right) ? result.right.confidence : 0.f;
}

void fillLanePoints(const Result& result, const std_msgs::Header& header,
                    const Eigen::Isometry3d& T, sensor_msgs::PointCloud2& msg) {
  const MarkerTrace* sides[2] = {&result.left, &result.right};
  size_t n = 0;
  for (const MarkerTrace* m : sides)
    if (reported(*m)) n += static_cast<size_t>(std::count_if(m->points.begin(), m->points.end(), finite));

  msg.header = header;
  msg.height = 1;
  sensor_msgs::PointCloud2Modifier modifier(msg);
  modifier.setPointCloud2Fields(6, "x", 1, sensor_msgs::PointField::FLOAT32,       //
                                "y", 1, sensor_msgs::PointField::FLOAT32,          //
                                "z", 1, sensor_msgs::PointField::FLOAT32,          //
                                "score", 1, sensor_msgs::PointField::FLOAT32,      //
                                "side", 1, sensor_msgs::PointField::UINT8,         //
                                "kind", 1, sensor_msgs::PointField::UINT8);
  msg.point_step = 20;  // 18 bytes of fields, padded so each point's floats stay aligned
  modifier.resize(n);
  msg.is_bigendian = kHostBigEndian;
  msg.is_dense = true;
  if (n == 0) return;

  sensor_msgs::PointCloud2Iterator<float> x(msg, "x"), y(msg, "y"), z(msg, "z"), score(msg, "score");
  sensor_msgs::PointCloud2Iterator<uint8_t> side(msg, "side"), kind(msg, "kind");
  for (int s = 0; s < 2; ++s) {
    const MarkerTrace& m = *sides[s];
    if (!reported(m)) continue;
    const uint8_t side_value = static_cast<uint8_t>(s == 0 ? Side::kLeft : Side::kRight);
    const uint8_t kind_value = static_cast<uint8_t>(m.kind);
    for (size_t i = 0; i < m.points.size(); ++i) {
      if (!finite(m.points[i])) continue;
      const Eigen::Vector3d q = T * m.points[i].cast<double>();
      *x = static_cast<float>(q.x());
      *y = static_cast<float>(q.y());
      *z = static_cast<float>(q.z());
      *score = i < m.scores.size() ? m.scores[i] : 0.f;
      *side = side_value;
      *kind = kind_value;
      ++x, ++y, ++z, ++score, ++side, ++kind;
    }
  }
}

void fillLaneMarkers(const Result& result, const std_msgs::Header& header,
                     const Eigen::Isometry3d& T, visualization_msgs::MarkerArray& msg) {
  msg.markers.clear();
  msg.markers.reserve(3);

  // ego-lane patch on the plane
  visualization_msgs::Marker patch = baseMarker(header, kPlaneNs, 0);
  Eigen::Vector3d ln, lf, rn, rf;
  if (result.plane.valid && reported(result.left) && reported(result.right) &&
      ends(result.left, ln, lf) && ends(result.right, rn, rf)) {
    const Eigen::Vector3d& n = result.plane.normal;
    const double d = result.plane.distance;
    auto onPlane = [&](const Eigen::Vector3d& p) { return toPoint(T * (p - (n.dot(p) + d) * n)); };
    patch.action = visualization_msgs::Marker::ADD;
    patch.type = visualization_msgs::Marker::TRIANGLE_LIST;
    patch.scale.x = patch.scale.y = patch.scale.z = 1.0;
    patch.color = rgba(0.2f, 0.45f, 1.0f, 0.35f);
    patch.points = {onPlane(ln), onPlane(lf), onPlane(rf), onPlane(ln), onPlane(rf), onPlane(rn)};
  }
  msg.markers.push_back(std::move(patch));

  // boundary polylines (paint: left green, right orange; road edges red, as in the debug overlay)
  const MarkerTrace* sides[2] = {&result.left, &result.right};
  for (int s = 0; s < 2; ++s) {
    visualization_msgs::Marker line = baseMarker(header, kMarkingsNs, s == 0 ? kLeftId : kRightId);
    appendValidPoints(*sides[s], T, line.points);
    if (line.points.size() >= 2) {
      line.action = visualization_msgs::Marker::ADD;
      line.type = visualization_msgs::Marker::LINE_STRIP;
      line.scale.x = 0.1;  // line width (m)
      line.color = sides[s]->kind == BoundaryKind::kRoadEdge ? rgba(1.f, 0.15f, 0.25f, 1.f)
                   : s == 0                                  ? rgba(0.f, 1.f, 0.f, 1.f)
                                                             : rgba(1.f, 0.55f, 0.f, 1.f);
    } else {
      line.points.clear();
    }
    msg.markers.push_back(std::move(line));
  }
}

void fillLaneModel(const LaneModelEstimate& model, const std_msgs::Header& header, LaneModel& msg,
                   double step) {
  msg.header = header;
  msg.valid = model.valid;
  msg.boundaries.clear();
  msg.centre_line.header = header;
  msg.centre_line.poses.clear();
  if (!model.valid) {
    msg.width = msg.lateral_offset = msg.heading_error = msg.curvature = msg.curvature_rate = 0.0;
    msg.lane_changes = 0;
    return;
  }
  msg.lane_changes = model.lane_changes;
  msg.width = model.width;
  msg.lateral_offset = model.offset;
  msg.heading_error = model.heading_error;
  msg.curvature = model.curvature;
  msg.curvature_rate = model.curvature_rate;
  for (const LaneBoundaryModel& b : model.boundaries) {
    if (!b.valid) continue;
    LaneBoundary m;
    m.position = static_cast<uint8_t>(b.position);
    m.kind = static_cast<uint8_t>(b.kind);
    m.colour = static_cast<uint8_t>(b.colour);
    m.c0 = b.c[0];
    m.c1 = b.c[1];
    m.c2 = b.c[2];
    m.c3 = b.c[3];
    m.x_min = b.x_min;
    m.x_max = b.x_max;
    m.confidence = b.confidence;
    m.lateral_std = b.lateral_std;
    msg.boundaries.push_back(m);
  }
  // the centre line as a path: poses along it, oriented along its tangent
  const auto& c = model.centre;
  alongRange(model.x_min, model.x_max, step, [&](double x) {
    geometry_msgs::PoseStamped pose;
    pose.header = header;
    pose.pose.position.x = x;
    pose.pose.position.y = c[0] + x * (c[1] + x * (c[2] + x * c[3]));
    const double yaw = std::atan(c[1] + x * (2.0 * c[2] + 3.0 * x * c[3]));
    pose.pose.orientation.z = std::sin(0.5 * yaw);
    pose.pose.orientation.w = std::cos(0.5 * yaw);
    msg.centre_line.poses.push_back(pose);
  });
}

void fillOccupancyGrid(const LaneGrid& grid, const std_msgs::Header& header,
                       nav_msgs::OccupancyGrid& msg) {
  msg.header = header;
  msg.info.map_load_time = header.stamp;
  msg.info.resolution = static_cast<float>(grid.resolution());
  msg.info.width = static_cast<uint32_t>(grid.cols());
  msg.info.height = static_cast<uint32_t>(grid.rows());
  msg.info.origin.position.x = grid.originX();
  msg.info.origin.position.y = grid.originY();
  msg.info.origin.position.z = 0.0;
  msg.info.origin.orientation.x = msg.info.origin.orientation.y = 0.0;
  msg.info.origin.orientation.z = 0.0;
  msg.info.origin.orientation.w = 1.0;
  msg.data.assign(grid.cells().begin(), grid.cells().end());
}

void appendLaneModelMarkers(const LaneModelEstimate& model, const std_msgs::Header& header,
                            visualization_msgs::MarkerArray& msg, double step) {
  for (const LaneBoundaryModel& b : model.boundaries) {
    visualization_msgs::Marker line =
        baseMarker(header, kModelNs, static_cast<int>(b.position));
    if (model.valid && b.valid && step > 0.0) {
      line.action = visualization_msgs::Marker::ADD;
      line.type = visualization_msgs::Marker::LINE_STRIP;
      line.scale.x = 0.12;
      const bool yellow = b.colour == LineColour::kYellow;
      switch (b.kind) {
        case LineKind::kSolid:
          line.color = yellow ? rgba(1.f, 0.85f, 0.f, 1.f) : rgba(1.f, 1.f, 1.f, 1.f);
          break;
        case LineKind::kDashed:
          line.color = yellow ? rgba(1.f, 0.9f, 0.5f, 0.8f) : rgba(0.75f, 0.75f, 0.75f, 0.8f);
          break;
        case LineKind::kRoadEdge:
          line.color = rgba(1.f, 0.15f, 0.25f, 1.f);
          break;
        default:
          line.color = rgba(0.5f, 0.5f, 0.5f, 0.8f);
          break;
      }
      alongRange(b.x_min, b.x_max, step, [&](double x) {
        geometry_msgs::Point p;
        p.x = x;
        p.y = b.lateral(x);
        line.points.push_back(p);
      });
      if (line.points.size() < 2) {
        line.action = visualization_msgs::Marker::DELETE;
        line.points.clear();
      }
    }
    msg.markers.push_back(std::move(line));
  }
}

void floatMapToImage(const cv::Mat& map, const std_msgs::Header& header, sensor_msgs::Image& msg) {
  cv::Mat out = prepareImage(map.rows, map.cols, CV_32FC1, enc::TYPE_32FC1, header, msg);
  if (map.type() == CV_32FC1)
    map.copyTo(out);
  else if (!map.empty())
    map.convertTo(out, CV_32F);
}

cv::Mat prepareImage(int rows, int cols, int type, const std::string& encoding,
                     const std_msgs::Header& header, sensor_msgs::Image& msg) {
  msg.header = header;
  msg.height = static_cast<uint32_t>(std::max(rows, 0));
  msg.width = static_cast<uint32_t>(std::max(cols, 0));
  msg.encoding = encoding;
  msg.is_bigendian = kHostBigEndian;
  msg.step = msg.width * static_cast<uint32_t>(CV_ELEM_SIZE(type));
  msg.data.resize(static_cast<size_t>(msg.step) * msg.height);
  if (msg.data.empty()) return cv::Mat();
  return cv::Mat(rows, cols, type, msg.data.data(), msg.step);
}

}  // namespace conversions
}  // namespace rgbd_lane_detector
