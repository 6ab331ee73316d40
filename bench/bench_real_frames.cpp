#include "bench_real_frames.h"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "opencv_pipeline.h"
#include "real_inputs.h"
#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector_tools/dataset/dataset.h"

namespace rgbd_lane_detector {
namespace bench {
namespace {

namespace fs = std::filesystem;

constexpr int kWarmUp = 5;  // detect() calls before timing: adapted templates, tracked lane model

struct RealData {
  tools::DatasetFrame frame;
  LineTemplate left, right;  ///< the paper mode's steady-state templates (the OpenCV pipeline's)
};

bool load(const RealInput& in, RealData& out, std::string& error) {
  if (!loadRealFrame(in, out.frame, error)) return false;
  LaneDetector det(Params::paper());
  Result r;
  for (int i = 0; i < kWarmUp; ++i) det.detect(out.frame.toFrame(), r);
  out.left = det.leftTemplate();
  out.right = det.rightTemplate();
  out.left.image = out.left.image.clone();
  out.right.image = out.right.image.clone();
  return true;
}

void setSize(benchmark::State& state, const RealData& d, double scale) {
  const cv::Size s = d.frame.colour.size();
  const double px = static_cast<double>(s.area());
  // ns per native pixel: the average CPU time per iteration is divided by this in the report
  state.counters["pixels"] = px;
  state.counters["scale"] = scale;
  state.SetLabel(std::to_string(s.width) + "x" + std::to_string(s.height));
}

// detect() in the default mode (or at full scale) on the frame again and again, as a camera
// would deliver it: the steady state of a drive; per-stage milliseconds as counters.
void BM_Real_Detect(benchmark::State& state, std::shared_ptr<RealData> d, bool full_scale) {
  Params p;  // the default (improved) mode
  if (full_scale) p.processing_scale = 1.0;
  LaneDetector det(p);
  const Frame f = d->frame.toFrame();
  Result r;
  for (int i = 0; i < kWarmUp; ++i) det.detect(f, r);
  StageTimings sum;
  for (auto _ : state) {
    det.detect(f, r);
    benchmark::DoNotOptimize(r.plane.distance);
    sum += r.timings;
  }
  using C = benchmark::Counter;
  const std::pair<const char*, double> stages[] = {
      {"preprocess_ms", sum.preprocess}, {"points_ms", sum.points},
      {"normals_ms", sum.normals},       {"matching_ms", sum.matching},
      {"response_ms", sum.response},     {"road_ms", sum.road},
      {"pca_ms", sum.pca},               {"tracing_ms", sum.tracing},
      {"classify_ms", sum.classify},     {"plane_ms", sum.plane},
      {"model_ms", sum.model}};
  for (const auto& [name, ms] : stages) state.counters[name] = C(ms, C::kAvgIterations);
  setSize(state, *d, processingScale(p, f.colour.size(), f.intrinsics));
}

// The straightforward OpenCV pipeline (the paper's stages) on the same frame at its native size.
void BM_Real_OpenCV(benchmark::State& state, std::shared_ptr<RealData> d) {
  OpenCvPipeline pipe;
  const Frame f = d->frame.toFrame();
  pipe.configure(f, Params::paper());
  for (auto _ : state) {
    pipe.run(f, d->left, d->right);
    benchmark::DoNotOptimize(pipe.response_left.data);
  }
  setSize(state, *d, 1.0);
}

}  // namespace

int registerRealFrameBenchmarks() {
  const std::string root = realdataRoot();
  if (!fs::is_directory(root)) {
    std::fprintf(stderr, "bench: real frames skipped: %s not found (set RLD_REALDATA)\n",
                 root.c_str());
    return 0;
  }
  int n = 0;
  for (const RealInput& in : kRealInputs) {
    auto d = std::make_shared<RealData>();
    std::string error;
    if (!load(in, *d, error)) {
      std::fprintf(stderr, "bench: real frame %s skipped: %s\n", in.label, error.c_str());
      continue;
    }
    const std::string name = std::string("/") + in.label;
    benchmark::RegisterBenchmark(("BM_Real_Detect" + name).c_str(), BM_Real_Detect, d, false)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_Real_DetectFullScale" + name).c_str(), BM_Real_Detect, d,
                                 true)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_Real_OpenCV" + name).c_str(), BM_Real_OpenCV, d)
        ->Unit(benchmark::kMillisecond);
    ++n;
  }
  return n;
}

}  // namespace bench
}  // namespace rgbd_lane_detector
