// Google Benchmark of disparityToDepth() (Z = f T / d with stereo_msgs validity, as
// DisparityToDepthNodelet runs it per frame) against the straightforward OpenCV expression of
// the same conversion, single-threaded, on a KITTI-sized (1242x375) and a VGA disparity image
// with 1/16 px disparities, 30% of them invalid (-1, as stereo_image_proc marks them).
//   bench_disparity --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <limits>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>

#include "rgbd_lane_detector/disparity_depth.h"

namespace rgbd_lane_detector {
namespace {

DisparityModel kittiModel() {
  DisparityModel m;
  m.focal = 721.5377;
  m.baseline = 0.53273;
  m.min_disparity = 0.0;
  m.max_disparity = 127.0;
  m.delta_d = 1.0 / 16;
  return m;
}

cv::Mat disparities(int width, int height) {
  cv::Mat d(height, width, CV_32FC1);
  cv::RNG rng(1);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      d.at<float>(y, x) = rng.uniform(0.f, 1.f) < 0.3f ? -1.f : rng.uniform(1, 127 * 16) / 16.f;
  return d;
}

void BM_DisparityToDepth(benchmark::State& state) {
  cv::setNumThreads(1);
  const cv::Mat d = disparities(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const DisparityModel m = kittiModel();
  cv::Mat z;
  for (auto _ : state) {
    benchmark::DoNotOptimize(disparityToDepth(d, m, z));
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * d.total());
}

// The same result with OpenCV calls: Z = fT / d, then NaN outside [min, max] and below delta_d
// (d > 0 here, so |d| >= delta_d is d >= delta_d), and where fT / d is not finite.
void BM_OpenCV_DisparityToDepth(benchmark::State& state) {
  cv::setNumThreads(1);
  const cv::Mat d = disparities(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const DisparityModel m = kittiModel();
  cv::Mat z, valid;
  for (auto _ : state) {
    cv::divide(m.focal * m.baseline, d, z);
    cv::inRange(d, std::max(m.min_disparity, m.delta_d), m.max_disparity, valid);
    z.setTo(std::numeric_limits<float>::quiet_NaN(), ~valid);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * d.total());
}

BENCHMARK(BM_DisparityToDepth)->Args({1242, 375})->Args({640, 480});
BENCHMARK(BM_OpenCV_DisparityToDepth)->Args({1242, 375})->Args({640, 480});

}  // namespace
}  // namespace rgbd_lane_detector

BENCHMARK_MAIN();
