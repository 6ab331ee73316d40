#include "rgbd_lane_detector/ros/conversions.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include <boost/any.hpp>
#include <dynamic_reconfigure/config_tools.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include "rgbd_lane_detector/params_io.h"

namespace rgbd_lane_detector {
namespace conversions {
namespace enc = sensor_msgs::image_encodings;

namespace {

constexpr bool kHostBigEndian = __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__;

int colourType(PixelFormat format) {
  switch (format) {
    case PixelFormat::kBgr8:
    case PixelFormat::kRgb8:
      return CV_8UC3;
    case PixelFormat::kBgra8:
    case PixelFormat::kRgba8:
      return CV_8UC4;
    case PixelFormat::kMono8:
      return CV_8UC1;
  }
  return CV_8UC3;
}

// What the message layout says about reading it as rows of width * elem_size bytes, each row
// starting at a multiple of step. nullptr: readable (or empty, which the core reports).
const char* checkLayout(const sensor_msgs::Image& msg, size_t elem_size, size_t channel_size) {
  if (msg.width == 0 || msg.height == 0) return nullptr;
  if (msg.width > static_cast<uint32_t>(INT_MAX) / elem_size ||
      msg.height > static_cast<uint32_t>(INT_MAX))
    return "image dimensions are too large";
  if (static_cast<uint64_t>(msg.step) < static_cast<uint64_t>(msg.width) * elem_size)
    return "image step is smaller than width times the pixel size";
  if (msg.step % channel_size != 0) return "image step is not a multiple of the channel size";
  if (static_cast<uint64_t>(msg.step) * msg.height > msg.data.size())
    return "image data is shorter than step times height";
  return nullptr;
}

// Header onto the message data; the data is only read (the Mat API is not const-aware).
cv::Mat wrap(const sensor_msgs::Image& msg, int type) {
  if (msg.width == 0 || msg.height == 0) return cv::Mat();
  return cv::Mat(static_cast<int>(msg.height), static_cast<int>(msg.width), type,
                 const_cast<uint8_t*>(msg.data.data()), msg.step);
}

template <typename T>
void byteSwapRows(const cv::Mat& src, cv::Mat& dst) {
  dst.create(src.size(), src.type());
  for (int y = 0; y < src.rows; ++y) {
    const uint8_t* s = src.ptr<uint8_t>(y);
    uint8_t* d = dst.ptr<uint8_t>(y);
    for (int x = 0; x < src.cols; ++x, s += sizeof(T), d += sizeof(T))
      std::reverse_copy(s, s + sizeof(T), d);
  }
}

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
// Inputs

bool pixelFormatFromEncoding(const std::string& encoding, PixelFormat& format) {
  if (encoding == enc::BGR8) {
    format = PixelFormat::kBgr8;
  } else if (encoding == enc::RGB8) {
    format = PixelFormat::kRgb8;
  } else if (encoding == enc::BGRA8) {
    format = PixelFormat::kBgra8;
  } else if (encoding == enc::RGBA8) {
    format = PixelFormat::kRgba8;
  } else if (encoding == enc::MONO8) {
    format = PixelFormat::kMono8;
  } else {
    return false;
  }
  return true;
}

const char* colourFromMsg(const sensor_msgs::Image& msg, cv::Mat& colour, PixelFormat& format) {
  if (!pixelFormatFromEncoding(msg.encoding, format))
    return "unsupported colour encoding (expected rgb8, bgr8, rgba8, bgra8 or mono8)";
  const int type = colourType(format);
  if (const char* problem = checkLayout(msg, CV_ELEM_SIZE(type), 1)) return problem;
  colour = wrap(msg, type);
  return nullptr;
}

const char* depthFromMsg(const sensor_msgs::Image& msg, cv::Mat& depth, double& depth_scale,
                         cv::Mat& swap_buffer) {
  int type;
  if (msg.encoding == enc::TYPE_16UC1) {
    type = CV_16UC1;
    depth_scale = 0.001;  // REP-118: millimetres
  } else if (msg.encoding == enc::TYPE_32FC1) {
    type = CV_32FC1;
    depth_scale = 1.0;  // metres
  } else {
    return "unsupported depth encoding (expected 16UC1 millimetres or 32FC1 metres)";
  }
  const size_t elem = CV_ELEM_SIZE(type);
  if (const char* problem = checkLayout(msg, elem, elem)) return problem;
  depth = wrap(msg, type);
  if (!depth.empty() && static_cast<bool>(msg.is_bigendian) != kHostBigEndian) {
    if (type == CV_16UC1)
      byteSwapRows<uint16_t>(depth, swap_buffer);
    else
      byteSwapRows<float>(depth, swap_buffer);
    depth = swap_buffer;
  }
  return nullptr;
}

Intrinsics intrinsicsFromCameraInfo(const sensor_msgs::CameraInfo& info) {
  Intrinsics K;
  if (info.P[0] != 0.0) {
    K.fx = info.P[0];
    K.fy = info.P[5];
    K.cx = info.P[2];
    K.cy = info.P[6];
  } else {
    K.fx = info.K[0];
    K.fy = info.K[4];
    K.cx = info.K[2];
    K.cy = info.K[5];
  }
  return K;
}

bool hasDistortion(const sensor_msgs::CameraInfo& info) {
  for (double d : info.D)
    if (d != 0.0) return true;
  return false;
}

bool sameCamera(const Intrinsics& a, const Intrinsics& b, double tolerance) {
  if (!a.valid() || !b.valid()) return false;
  const double limit = tolerance * a.fx;
  return std::abs(a.fx - b.fx) <= limit && std::abs(a.fy - b.fy) <= limit &&
         std::abs(a.cx - b.cx) <= limit && std::abs(a.cy - b.cy) <= limit;
}

sensor_msgs::CameraInfo cameraInfoFromIntrinsics(const Intrinsics& K, int width, int height,
                                                 const std_msgs::Header& header) {
  sensor_msgs::CameraInfo info;
  info.header = header;
  info.width = static_cast<uint32_t>(std::max(0, width));
  info.height = static_cast<uint32_t>(std::max(0, height));
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  info.K = {K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {K.fx, 0, K.cx, 0, 0, K.fy, K.cy, 0, 0, 0, 1, 0};
  return info;
}

const char* frameFromMsgs(const sensor_msgs::Image& colour, const sensor_msgs::Image& depth,
                          const sensor_msgs::CameraInfo& info, Frame& frame,
                          cv::Mat& swap_buffer) {
  if (const char* problem = colourFromMsg(colour, frame.colour, frame.format)) return problem;
  if (const char* problem = depthFromMsg(depth, frame.depth, frame.depth_scale, swap_buffer))
    return problem;
  if (info.width != 0 && info.height != 0 &&
      (info.width != colour.width || info.height != colour.height))
    return "camera_info size differs from the colour image (binning and ROI are not supported)";
  frame.intrinsics = intrinsicsFromCameraInfo(info);
  return nullptr;
}

const char* disparityFromMsg(const stereo_msgs::DisparityImage& msg, cv::Mat& disparity,
                             DisparityModel& model, cv::Mat& swap_buffer) {
  const sensor_msgs::Image& image = msg.image;
  if (image.encoding != enc::TYPE_32FC1)
    return "unsupported disparity encoding (expected 32FC1, stereo_msgs/DisparityImage)";
  if (image.width == 0 || image.height == 0) return "empty disparity image";
  if (const char* problem = checkLayout(image, sizeof(float), sizeof(float))) return problem;
  DisparityModel m;
  m.focal = msg.f;
  m.baseline = msg.T;
  m.min_disparity = msg.min_disparity;
  m.max_disparity = msg.max_disparity;
  m.delta_d = msg.delta_d;
  const sensor_msgs::RegionOfInterest& w = msg.valid_window;
  if (w.width > 0 && w.height > 0) {  // else: the whole image
    // clipped to the image here, so that the int rectangle cannot overflow
    const uint32_t x0 = std::min(w.x_offset, image.width), y0 = std::min(w.y_offset, image.height);
    m.valid_window = cv::Rect(static_cast<int>(x0), static_cast<int>(y0),
                              static_cast<int>(std::min(w.width, image.width - x0)),
                              static_cast<int>(std::min(w.height, image.height - y0)));
    if (m.valid_window.empty()) return "disparity valid_window lies outside the image";
  }
  if (const char* problem = m.problem()) return problem;
  disparity = wrap(image, CV_32FC1);
  if (static_cast<bool>(image.is_bigendian) != kHostBigEndian) {
    byteSwapRows<float>(disparity, swap_buffer);
    disparity = swap_buffer;
  }
  model = m;
  return nullptr;
}

// ---------------------------------------------------------------------------
// Parameters

// By name: the cfg parameters are named after the Params fields (params_io.h keeps the table
// that the core's tests check against the .cfg), so a new parameter needs no code here.
int configToParams(const LaneDetectorConfig& config, Params& params) {
  int unmapped = 0;
  for (const auto& description : LaneDetectorConfig::__getParamDescriptions__()) {
    boost::any value;
    description->getValue(config, value);
    double v;
    if (description->type == "bool")
      v = boost::any_cast<bool>(value) ? 1.0 : 0.0;
    else if (description->type == "int")
      v = boost::any_cast<int>(value);  // enums: DepthTerm / PlaneFit values
    else if (description->type == "double")
      v = boost::any_cast<double>(value);
    else
      v = std::numeric_limits<double>::quiet_NaN();
    if (!std::isfinite(v) || !setParam(params, description->name, v)) ++unmapped;
  }
  return unmapped;
}

int paramsToConfig(const Params& params, LaneDetectorConfig& config) {
  int unmapped = 0;
  dynamic_reconfigure::Config msg;
  for (const auto& description : LaneDetectorConfig::__getParamDescriptions__()) {
    double v;
    if (!getParam(params, description->name, v)) {
      ++unmapped;
      continue;
    }
    if (description->type == "bool") {
      dynamic_reconfigure::BoolParameter b;
      b.name = description->name;
      b.value = v != 0.0;
      msg.bools.push_back(b);
    } else if (description->type == "int") {
      dynamic_reconfigure::IntParameter i;
      i.name = description->name;
      i.value = static_cast<int>(std::lround(v));
      msg.ints.push_back(i);
    } else if (description->type == "double") {
      dynamic_reconfigure::DoubleParameter d;
      d.name = description->name;
      d.value = v;
      msg.doubles.push_back(d);
    } else {
      ++unmapped;
    }
  }
  config.__fromMessage__(msg);
  return unmapped;
}

// ---------------------------------------------------------------------------
// Geometry

void transformPlane(const Eigen::Isometry3d& T, Eigen::Vector3d& normal, double& distance) {
  normal = T.linear() * normal;
  distance -= normal.dot(T.translation());
}

Eigen::Vector3d upAxisFromTransform(const Eigen::Isometry3d& T_optical_up) {
  return T_optical_up.linear() * Eigen::Vector3d::UnitZ();
}

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
  msg.lane_changes = model.lane_changes;
  if (!model.valid) {
    msg.width = msg.lateral_offset = msg.heading_error = msg.curvature = msg.curvature_rate = 0.0;
    return;
  }
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
  for (double x = model.x_min; x <= model.x_max + 1e-9 && step > 0.0; x += step) {
    geometry_msgs::PoseStamped pose;
    pose.header = header;
    pose.pose.position.x = x;
    pose.pose.position.y = c[0] + x * (c[1] + x * (c[2] + x * c[3]));
    const double yaw = std::atan(c[1] + x * (2.0 * c[2] + 3.0 * x * c[3]));
    pose.pose.orientation.z = std::sin(0.5 * yaw);
    pose.pose.orientation.w = std::cos(0.5 * yaw);
    msg.centre_line.poses.push_back(pose);
  }
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
      for (double x = b.x_min; x <= b.x_max + 1e-9; x += step) {
        geometry_msgs::Point p;
        p.x = x;
        p.y = b.lateral(x);
        line.points.push_back(p);
      }
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
