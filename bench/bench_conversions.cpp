// The nodelet's per-frame message reading: conversions::frameFromMsgs (hand-written: layout
// checks, a cv::Mat header on msg.data, intrinsics from P else K) against the same job done by
// cv_bridge::toCvShare (passthrough encoding: zero copy) and image_geometry's
// PinholeCameraModel::fromCameraInfo. Heap allocations per frame are counted (allocs/frame).
// Results in docs/PERFORMANCE.md ("ROS conversions"). Run: bench_conversions.
#include <atomic>
#include <cstdlib>
#include <new>

#include <benchmark/benchmark.h>
#include <cv_bridge/cv_bridge.h>
#include <image_geometry/pinhole_camera_model.h>
#include <sensor_msgs/image_encodings.h>

#include "rgbd_lane_detector/ros/conversions.h"

namespace {
std::atomic<size_t> g_allocations{0};
}  // namespace

// malloc/free under operator new/delete (GCC cannot see that they pair through the counter)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace rgbd_lane_detector {
namespace {

namespace enc = sensor_msgs::image_encodings;

struct Messages {
  sensor_msgs::Image colour, depth;
  sensor_msgs::CameraInfo info;
  Messages(int width, int height, bool foreign_depth) {
    std_msgs::Header h;
    h.frame_id = "camera_color_optical_frame";  // a real driver's (longer than SSO)
    const auto image = [&](const std::string& encoding, int elem) {
      sensor_msgs::Image m;
      m.header = h;
      m.width = static_cast<uint32_t>(width);
      m.height = static_cast<uint32_t>(height);
      m.encoding = encoding;
      m.step = m.width * static_cast<uint32_t>(elem);
      m.data.assign(static_cast<size_t>(m.step) * m.height, 7);
      return m;
    };
    colour = image(enc::BGR8, 3);
    depth = image(enc::TYPE_16UC1, 2);
    depth.is_bigendian = foreign_depth != (__BYTE_ORDER__ == __ORDER_BIG_ENDIAN__);
    const Intrinsics K{0.83 * width, 0.83 * width, 0.5 * width, 0.5 * height};
    info = conversions::cameraInfoFromIntrinsics(K, width, height, h);
  }
};

void report(benchmark::State& state, size_t allocations) {
  state.counters["allocs/frame"] =
      static_cast<double>(allocations) / static_cast<double>(state.iterations());
}

void BM_FrameFromMsgs_HandWritten(benchmark::State& state) {
  const Messages m(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                   state.range(2) != 0);
  cv::Mat swap;
  Frame frame;
  conversions::frameFromMsgs(m.colour, m.depth, m.info, frame, swap);  // sizes the swap buffer
  const size_t before = g_allocations;
  for (auto _ : state) {
    Frame f;
    const char* problem = conversions::frameFromMsgs(m.colour, m.depth, m.info, f, swap);
    benchmark::DoNotOptimize(problem);
    benchmark::DoNotOptimize(f.depth.data);
  }
  report(state, g_allocations - before);
}

// cv_bridge for the images; the intrinsics from image_geometry (with_camera_model) or by hand.
void cvBridge(benchmark::State& state, bool with_camera_model) {
  const Messages m(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                   state.range(2) != 0);
  image_geometry::PinholeCameraModel camera;  // kept across frames, as a nodelet would
  camera.fromCameraInfo(m.info);
  const boost::shared_ptr<void const> tracked;  // the caller keeps the messages alive
  const size_t before = g_allocations;
  for (auto _ : state) {
    Frame f;
    cv_bridge::CvImageConstPtr colour = cv_bridge::toCvShare(m.colour, tracked);
    cv_bridge::CvImageConstPtr depth = cv_bridge::toCvShare(m.depth, tracked);
    conversions::pixelFormatFromEncoding(colour->encoding, f.format);
    f.colour = colour->image;
    f.depth = depth->image;
    f.depth_scale = depth->encoding == enc::TYPE_16UC1 ? 0.001 : 1.0;
    if (with_camera_model) {
      camera.fromCameraInfo(m.info);
      f.intrinsics = Intrinsics{camera.fx(), camera.fy(), camera.cx(), camera.cy()};
    } else {
      f.intrinsics = conversions::intrinsicsFromCameraInfo(m.info);
    }
    benchmark::DoNotOptimize(f.depth.data);
  }
  report(state, g_allocations - before);
}
void BM_FrameFromMsgs_CvBridge(benchmark::State& state) { cvBridge(state, false); }
void BM_FrameFromMsgs_CvBridgeImageGeometry(benchmark::State& state) { cvBridge(state, true); }

// width, height, depth in the other byte order
#define RLD_SIZES ->Args({640, 380, 0})->Args({1280, 760, 0})->Args({640, 380, 1})
BENCHMARK(BM_FrameFromMsgs_HandWritten) RLD_SIZES;
BENCHMARK(BM_FrameFromMsgs_CvBridge) RLD_SIZES;
BENCHMARK(BM_FrameFromMsgs_CvBridgeImageGeometry) RLD_SIZES;

}  // namespace
}  // namespace rgbd_lane_detector

BENCHMARK_MAIN();
