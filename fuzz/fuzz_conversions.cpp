// libFuzzer target: raw sensor_msgs/Image + CameraInfo fields through the conversions
// (colourFromMsg, depthFromMsg, frameFromMsgs), then, when they accept the messages, the
// detector's validate()/detect() and every output filler on its result.
//
// As in fuzz_detect, index 0 of every choice is the canonical value: an empty input is a
// well-formed bgr8 + 32FC1 80x60 road frame with a camera_info, and mutations reach any
// width, height, step, encoding string (a dictionary of real encodings or arbitrary text),
// is_bigendian, data length, K / P values (NaN, huge, zero) and camera_info size.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <sensor_msgs/image_encodings.h>
#include <opencv2/core/utility.hpp>

#include "fuzz_common.h"
#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector/ros/conversions.h"

namespace rld = rgbd_lane_detector;
namespace conv = rgbd_lane_detector::conversions;
using rld::fuzz::interestingDepth;
using rld::fuzz::interestingDouble;

namespace {

constexpr uint32_t kWidth = 80, kHeight = 60;
constexpr size_t kMaxData = 1 << 17;

const char* const kEncodings[] = {
    "bgr8",  "rgb8",  "mono8", "bgra8", "rgba8",       "16UC1",  "32FC1", "mono16", "8UC3", "8UC1",
    "16SC1", "32SC1", "64FC1", "32FC3", "bayer_rggb8", "yuv422", "8UC4",  "16UC3",  "",
};

std::string makeEncoding(FuzzedDataProvider& fdp, const char* canonical) {
  const size_t n = sizeof(kEncodings) / sizeof(kEncodings[0]);
  const size_t pick = fdp.ConsumeIntegralInRange<size_t>(0, n + 1);
  if (pick == 0) return canonical;
  if (pick <= n) return kEncodings[pick - 1];
  return fdp.ConsumeRandomLengthString(16);
}

uint32_t makeDimension(FuzzedDataProvider& fdp, uint32_t canonical) {
  switch (fdp.ConsumeIntegralInRange<int>(0, 3)) {
    case 0:
      return canonical;
    case 1:
      return fdp.ConsumeIntegralInRange<uint32_t>(0, 300);
    case 2:
      return fdp.ConsumeIntegralInRange<uint32_t>(0, 3);
    default:
      return fdp.ConsumeIntegral<uint32_t>();
  }
}

/// Bytes per pixel the encoding would have (1 when unknown).
size_t pixelBytes(const std::string& encoding) {
  try {
    namespace enc = sensor_msgs::image_encodings;
    return static_cast<size_t>(enc::numChannels(encoding) * (enc::bitDepth(encoding) / 8));
  } catch (...) {
    return 1;
  }
}

/// The image's layout and data: canonical (tight rows, road rendering / ground plane), or
/// any step, data length and bytes.
void makeImage(FuzzedDataProvider& fdp, sensor_msgs::Image& msg, const char* canonical_encoding,
               bool depth) {
  msg.encoding = makeEncoding(fdp, canonical_encoding);
  msg.width = makeDimension(fdp, kWidth);
  msg.height = makeDimension(fdp, kHeight);
  msg.is_bigendian = fdp.ConsumeBool() ? fdp.ConsumeIntegral<uint8_t>() : 0;
  const size_t elem = std::max<size_t>(1, pixelBytes(msg.encoding));
  const uint64_t tight = static_cast<uint64_t>(msg.width) * elem;
  switch (fdp.ConsumeIntegralInRange<int>(0, 3)) {
    case 0:
      msg.step = static_cast<uint32_t>(tight);
      break;
    case 1:
      msg.step = static_cast<uint32_t>(tight + fdp.ConsumeIntegralInRange<int>(0, 16));
      break;
    case 2:
      msg.step = static_cast<uint32_t>(tight - fdp.ConsumeIntegralInRange<int>(0, 3));
      break;
    default:
      msg.step = fdp.ConsumeIntegral<uint32_t>();
  }
  const uint64_t full = static_cast<uint64_t>(msg.step) * msg.height;
  size_t length = full <= kMaxData ? static_cast<size_t>(full) : 0;
  if (fdp.ConsumeBool()) length = fdp.ConsumeIntegralInRange<size_t>(0, kMaxData);
  msg.data.assign(length, 0);
  if (length == 0) return;

  if (fdp.ConsumeBool()) {  // arbitrary bytes, repeated
    const std::vector<uint8_t> bytes =
        fdp.ConsumeBytes<uint8_t>(fdp.ConsumeIntegralInRange<size_t>(1, 2048));
    for (size_t i = 0; i < length && !bytes.empty(); ++i) msg.data[i] = bytes[i % bytes.size()];
    return;
  }
  // rendering by pixel, whatever the layout says
  const size_t step = msg.step ? msg.step : length;
  const bool swap = msg.is_bigendian != 0;
  for (size_t row = 0; row * step < length; ++row) {
    const double dv = row + 0.5 - msg.height / 2.0;
    for (size_t off = 0; off + elem <= step && row * step + off + elem <= length; off += elem) {
      uint8_t* px = &msg.data[row * step + off];
      const double x = static_cast<double>(off / elem);
      if (depth) {
        if (elem == 4) {
          float z = dv > 0.5 ? static_cast<float>(1.5 * kWidth / dv)
                             : std::numeric_limits<float>::quiet_NaN();
          if (dv > 0.5 && row % 7 == 3) z = interestingDepth(fdp);
          std::memcpy(px, &z, 4);
        } else if (elem == 2) {
          const uint16_t mm =
              dv > 0.5 ? static_cast<uint16_t>(std::min(65535.0, 1500.0 * kWidth / dv)) : 0;
          std::memcpy(px, &mm, 2);
        }
        if (swap) std::reverse(px, px + elem);
      } else {
        // a "/" marker on the left, a "\" marker on the right, below the horizon
        const double w = msg.width, h = msg.height, y = static_cast<double>(row);
        const double t = (y - 0.45 * h) / (0.55 * h);  // 0 at the horizon, 1 at the bottom
        const bool marker = t > 0 && (std::fabs(x - (0.45 - 0.35 * t) * w) < 3 ||
                                      std::fabs(x - (0.55 + 0.35 * t) * w) < 3);
        std::memset(px, marker ? 250 : 60, elem);
      }
    }
  }
}

void makeCameraInfo(FuzzedDataProvider& fdp, const sensor_msgs::Image& colour,
                    sensor_msgs::CameraInfo& info) {
  info.width = colour.width;
  info.height = colour.height;
  if (fdp.ConsumeBool()) {
    info.width = makeDimension(fdp, 0);
    info.height = makeDimension(fdp, 0);
  }
  const double f = kWidth, cx = colour.width / 2.0, cy = colour.height / 2.0;
  info.K = {f, 0, cx, 0, f, cy, 0, 0, 1};
  info.P = {f, 0, cx, 0, 0, f, cy, 0, 0, 0, 1, 0};
  if (fdp.ConsumeBool()) info.P[0] = 0.0;  // unset P: K is used
  const int edits = fdp.ConsumeIntegralInRange<int>(0, 6);
  for (int i = 0; i < edits; ++i) {
    if (fdp.ConsumeBool())
      info.K[fdp.ConsumeIntegralInRange<size_t>(0, 8)] = interestingDouble(fdp, f);
    else
      info.P[fdp.ConsumeIntegralInRange<size_t>(0, 11)] = interestingDouble(fdp, f);
  }
}

Eigen::Isometry3d makeTransform(FuzzedDataProvider& fdp) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (!fdp.ConsumeBool()) return T;
  Eigen::Quaterniond q(interestingDouble(fdp, 1.0), interestingDouble(fdp, 0.0),
                       interestingDouble(fdp, 0.0), interestingDouble(fdp, 0.0));
  if (fdp.ConsumeBool()) q.normalize();
  T.linear() = q.toRotationMatrix();
  T.translation() = Eigen::Vector3d(interestingDouble(fdp, 0.1), interestingDouble(fdp, 0.0),
                                    interestingDouble(fdp, 1.5));
  return T;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  cv::setNumThreads(0);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider fdp(data, size);
  rld::LaneDetector detector(fdp.ConsumeBool() ? rld::Params::improved() : rld::Params::paper());
  if (!fdp.ConsumeBool()) {
    rld::Params p = detector.params();
    p.template_size = 16;
    p.template_line_width = 4;
    detector.setParams(p);
  }
  rld::Result result;
  cv::Mat swap_buffer;
  const int frames = 1 + fdp.ConsumeIntegralInRange<int>(0, 2);
  for (int i = 0; i < frames; ++i) {
    sensor_msgs::Image colour, depth;
    sensor_msgs::CameraInfo info;
    makeImage(fdp, colour, "bgr8", false);
    makeImage(fdp, depth, fdp.ConsumeBool() ? "16UC1" : "32FC1", true);
    makeCameraInfo(fdp, colour, info);

    // the single-image conversions on their own, then the frame
    cv::Mat m;
    rld::PixelFormat format;
    double scale = 0.0;
    const char* colour_problem = conv::colourFromMsg(colour, m, format);
    const char* depth_problem = conv::depthFromMsg(depth, m, scale, swap_buffer);
    (void)conv::intrinsicsFromCameraInfo(info);
    rld::Frame frame;
    const char* problem = conv::frameFromMsgs(colour, depth, info, frame, swap_buffer);
    if (!problem && (colour_problem || depth_problem)) std::abort();  // frame accepts less
    if (problem) continue;

    const rld::Status checked = detector.validate(frame);
    const rld::Status status = detector.detect(frame, result);
    if (status != checked) std::abort();
    if (std::getenv("RLD_FUZZ_VERBOSE"))  // to see what a reproducer does
      std::fprintf(stderr, "frame %d: %s, left %d right %d plane %d\n", i,
                   rld::statusMessage(status), result.left.found, result.right.found,
                   result.plane.valid);
    if (status != rld::Status::kOk) continue;

    std_msgs::Header header;
    header.frame_id = "camera_color_optical_frame";
    const Eigen::Isometry3d T = makeTransform(fdp);
    rld::LanePlane plane;
    rld::LaneMarkings markings;
    sensor_msgs::PointCloud2 points;
    visualization_msgs::MarkerArray markers;
    sensor_msgs::Image map;
    conv::fillLanePlane(result, header, T, plane);
    conv::fillLaneMarkings(result, header, T, markings);
    conv::fillLanePoints(result, header, T, points);
    conv::fillLaneMarkers(result, header, T, markers);
    conv::floatMapToImage(result.response_left, header, map);
    if (map.data.size() != static_cast<size_t>(map.step) * map.height) std::abort();
    if (points.data.size() != static_cast<size_t>(points.row_step) * points.height) std::abort();
  }
  return 0;
}
