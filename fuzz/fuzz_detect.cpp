// libFuzzer target: the core's LaneDetector::validate() + detect() on arbitrary frames.
//
// Each input drives one detector through 1-4 frames (carried state), with reset() and
// setParams() between frames. Every choice reads its index 0 as the canonical value, so an
// empty or short input is a plausible road frame (80x60, two markers, a ground-plane depth,
// valid intrinsics) and mutations move away from it: sizes 0, 1xN, Nx1, colour/depth size
// mismatches, every cv::Mat depth and channel count, non-continuous images, NaN / inf /
// negative / huge depth, zero / NaN / huge intrinsics, any parameter value by name.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "fuzz_common.h"
#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/params_io.h"

namespace rld = rgbd_lane_detector;
using rld::fuzz::interestingDepth;
using rld::fuzz::interestingDouble;

namespace {

constexpr int kMaxCols = 160;
constexpr int kMaxRows = 120;
constexpr int kCols = 80;  // canonical size: 4x faster than the largest under the sanitizers
constexpr int kRows = 60;

rld::Params makeParams(FuzzedDataProvider& fdp) {
  rld::Params p = fdp.ConsumeBool() ? rld::Params::improved() : rld::Params::paper();
  // template side: 16 (canonical), else anything from below the minimum to above the image
  const int t = fdp.ConsumeIntegralInRange<int>(0, 300);
  p.template_size = t == 0 ? 16 : t - 5;
  p.template_line_width = std::max(1, p.template_size / 4);
  p.normal_window = 5 + fdp.ConsumeIntegralInRange<int>(0, 10) * (fdp.ConsumeBool() ? -1 : 1);
  p.use_depth = !fdp.ConsumeBool();
  if (fdp.ConsumeBool()) p.processing_scale = interestingDouble(fdp, 0.5);
  if (fdp.ConsumeBool()) {
    p.roi_top = interestingDouble(fdp, 0.41);
    p.roi_bottom = interestingDouble(fdp, 1.0);
  }
  // any other field by name, with boundary values
  const std::vector<std::string>& names = rld::paramNames();
  const int extra = fdp.ConsumeIntegralInRange<int>(0, 6);
  for (int i = 0; i < extra; ++i) {
    const std::string& name = names[fdp.ConsumeIntegralInRange<size_t>(0, names.size() - 1)];
    double current = 0.0;
    rld::getParam(p, name, current);
    rld::setParam(p, name, interestingDouble(fdp, current));
  }
  return p;
}

const int kColourTypes[] = {CV_8UC3,  CV_8UC1,  CV_8UC4, CV_8UC2,  CV_16UC3,
                            CV_32FC3, CV_64FC1, CV_8SC3, CV_16UC1, CV_32FC1};
const int kDepthTypes[] = {CV_32FC1, CV_16UC1, CV_64FC1, CV_8UC1, CV_32FC3, CV_16SC1, CV_32SC1};

template <size_t N>
int pickType(FuzzedDataProvider& fdp, const int (&types)[N]) {
  return types[fdp.ConsumeIntegralInRange<size_t>(0, N - 1)];
}

/// An image of @p size and @p type, possibly a non-continuous view into a larger one.
cv::Mat allocate(FuzzedDataProvider& fdp, cv::Size size, int type) {
  if (size.width > 0 && size.height > 0 && fdp.ConsumeBool()) {
    const int pad = fdp.ConsumeIntegralInRange<int>(1, 7);
    cv::Mat big(size.height + pad, size.width + pad, type, cv::Scalar::all(0));
    return big(cv::Rect(pad / 2, pad - pad / 2, size.width, size.height));
  }
  return cv::Mat(size, type, cv::Scalar::all(0));
}

void fillBytes(FuzzedDataProvider& fdp, cv::Mat& m) {
  const std::vector<uint8_t> bytes =
      fdp.ConsumeBytes<uint8_t>(fdp.ConsumeIntegralInRange<size_t>(1, 4096));
  if (bytes.empty()) return;
  const size_t row_bytes = m.cols * m.elemSize();
  size_t k = 0;
  for (int y = 0; y < m.rows; ++y) {
    uint8_t* row = m.ptr<uint8_t>(y);
    for (size_t x = 0; x < row_bytes; ++x) row[x] = bytes[k++ % bytes.size()];
  }
}

/// Colour: canonical dark road with a left "/" and right "\\" marker; else other contents.
cv::Mat makeColour(FuzzedDataProvider& fdp, cv::Size size) {
  const int type = pickType(fdp, kColourTypes);
  cv::Mat c = allocate(fdp, size, type);
  if (c.empty()) return c;
  switch (fdp.ConsumeIntegralInRange<int>(0, 3)) {
    case 0: {  // road scene, endpoints perturbed
      c.setTo(cv::Scalar::all(60 + fdp.ConsumeIntegralInRange<int>(0, 195)));
      const int w = c.cols, h = c.rows;
      const int dx = fdp.ConsumeIntegralInRange<int>(0, 40) - 20;
      const int thickness = 1 + (4 + fdp.ConsumeIntegralInRange<int>(0, 12)) * w / kMaxCols;
      const cv::Scalar white = cv::Scalar::all(255 - fdp.ConsumeIntegralInRange<int>(0, 255));
      cv::line(c, cv::Point(w / 10 + dx, h - 1), cv::Point(w * 45 / 100, h * 45 / 100), white,
               thickness);
      cv::line(c, cv::Point(w * 9 / 10 - dx, h - 1), cv::Point(w * 55 / 100, h * 45 / 100), white,
               thickness);
      break;
    }
    case 1:
      fillBytes(fdp, c);
      break;
    case 2:
      c.setTo(cv::Scalar::all(fdp.ConsumeIntegral<uint8_t>()));
      break;
    default:
      break;  // zeros
  }
  return c;
}

/// Depth: canonical ground plane 1.5 m below the camera (NaN above the horizon); else
/// special values, raw bytes, constants.
cv::Mat makeDepth(FuzzedDataProvider& fdp, cv::Size size, const rld::Intrinsics& K) {
  const int type = pickType(fdp, kDepthTypes);
  cv::Mat d = allocate(fdp, size, type);
  if (d.empty()) return d;
  const int mode = fdp.ConsumeIntegralInRange<int>(0, 4);
  if (mode == 0 || mode == 1) {  // plane, in metres (32F/64F) or millimetres (integers)
    const double height = 1.5 * (1 + fdp.ConsumeIntegralInRange<int>(0, 8));
    const double unit = d.depth() == CV_32F || d.depth() == CV_64F ? 1.0 : 1000.0;
    cv::Mat plane(d.size(), CV_64FC1);
    for (int y = 0; y < d.rows; ++y) {
      const double dv = y + 0.5 - K.cy;
      for (int x = 0; x < d.cols; ++x)
        plane.at<double>(y, x) = dv > 0.5 ? height * K.fy / dv * unit : 0.0;
    }
    cv::Mat converted;
    plane.convertTo(converted, d.depth());  // saturating for integer types
    if (d.channels() > 1) {
      std::vector<cv::Mat> planes(d.channels(), converted);
      cv::merge(planes, converted);
    }
    converted.copyTo(d);
    if (d.type() == CV_32FC1) {
      const float nan = std::numeric_limits<float>::quiet_NaN();
      for (int y = 0; y < d.rows; ++y)
        for (int x = 0; x < d.cols; ++x)
          if (d.at<float>(y, x) == 0.0f) d.at<float>(y, x) = nan;
      if (mode == 1) {  // sprinkle special values
        const int n = fdp.ConsumeIntegralInRange<int>(0, 64);
        for (int i = 0; i < n; ++i) {
          const int y = fdp.ConsumeIntegralInRange<int>(0, d.rows - 1);
          const int x = fdp.ConsumeIntegralInRange<int>(0, d.cols - 1);
          d.at<float>(y, x) = interestingDepth(fdp);
        }
      }
    }
  } else if (mode == 2) {
    fillBytes(fdp, d);
  } else if (mode == 3 && d.type() == CV_32FC1) {
    d.setTo(interestingDepth(fdp));
  }
  return d;
}

rld::Intrinsics makeIntrinsics(FuzzedDataProvider& fdp, cv::Size size) {
  rld::Intrinsics K{static_cast<double>(kMaxCols), static_cast<double>(kMaxCols), size.width / 2.0,
                    size.height / 2.0};
  if (fdp.ConsumeBool()) {
    K.fx = interestingDouble(fdp, K.fx);
    K.fy = fdp.ConsumeBool() ? K.fx : interestingDouble(fdp, K.fy);
    K.cx = interestingDouble(fdp, K.cx);
    K.cy = interestingDouble(fdp, K.cy);
  }
  return K;
}

/// The contract of test/core/test_bad_input.cpp: an invalid result, never NaN / inf output.
void checkResult(const rld::Result& r) {
  for (const cv::Mat* m : {&r.response_left, &r.response_right, &r.geometric}) {
    if (m->size() != r.response_left.size()) std::abort();
    if (!m->empty() && !cv::checkRange(*m)) std::abort();
  }
  if (r.plane.valid && (!r.plane.normal.allFinite() || !std::isfinite(r.plane.distance)))
    std::abort();
  for (const rld::MarkerTrace* m : {&r.left, &r.right}) {
    for (const cv::Point2f& p : m->pixels)
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) std::abort();
    if (m->found && (!std::isfinite(m->seed.x) || !std::isfinite(m->seed.y))) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  cv::setNumThreads(0);  // OpenCV sequential: reproducible, no pool threads for the sanitizers
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider fdp(data, size);
  rld::LaneDetector detector(makeParams(fdp));
  rld::Result result;
  const int frames = 1 + fdp.ConsumeIntegralInRange<int>(0, 3);
  for (int i = 0; i < frames; ++i) {
    switch (fdp.ConsumeIntegralInRange<int>(0, 5)) {
      case 1:
        detector.reset();
        break;
      case 2:
        detector.setParams(makeParams(fdp));
        break;
      case 3:
        detector.setParams(detector.params());
        break;
      default:
        break;
    }
    // size: canonical 80x60, else anything up to 160x120 (0, 1xN, Nx1 included)
    cv::Size size(kCols, kRows);
    if (fdp.ConsumeBool()) {
      size.width = fdp.ConsumeIntegralInRange<int>(0, kMaxCols);
      size.height = fdp.ConsumeIntegralInRange<int>(0, kMaxRows);
    }
    rld::Frame frame;
    frame.intrinsics = makeIntrinsics(fdp, size);
    frame.colour = makeColour(fdp, size);
    frame.format = static_cast<rld::PixelFormat>(fdp.ConsumeIntegralInRange<int>(0, 5));
    cv::Size depth_size = size;
    if (fdp.ConsumeIntegralInRange<int>(0, 7) == 7) {
      depth_size.width = fdp.ConsumeIntegralInRange<int>(0, kMaxCols);
      depth_size.height = fdp.ConsumeIntegralInRange<int>(0, kMaxRows);
    }
    frame.depth = makeDepth(fdp, depth_size, frame.intrinsics);
    frame.depth_scale = fdp.ConsumeBool() ? interestingDouble(fdp, 0.001)
                                          : (frame.depth.depth() == CV_32F ? 1.0 : 0.001);

    const rld::Status checked = detector.validate(frame);
    const rld::Status status = detector.detect(frame, result);
    // detect() reports exactly what validate() found (one check, two entry points)
    if (status != checked || status != result.status) std::abort();
    if (std::getenv("RLD_FUZZ_VERBOSE"))  // to see what a reproducer does
      std::fprintf(stderr, "frame %d: %s, left %d right %d plane %d\n", i,
                   rld::statusMessage(status), result.left.found, result.right.found,
                   result.plane.valid);
    if (status == rld::Status::kOk) checkResult(result);
  }
  return 0;
}
