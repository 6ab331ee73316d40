// Messages -> core (images and camera_info read in place, stereo disparity), dynamic_reconfigure
// Config <-> core Params, tf geometry. The core results -> output messages half of
// conversions.h is result_messages.cpp.
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

std::string tfFrameId(const std::string& frame_id) {
  const size_t first = frame_id.find_first_not_of('/');
  return first == std::string::npos ? std::string() : frame_id.substr(first);
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

}  // namespace conversions
}  // namespace rgbd_lane_detector
