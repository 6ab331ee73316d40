// Google Benchmark of the detector core against the straightforward OpenCV pipeline, on
// generated road frames at 640x380 and 1280x760 and on real frames at their native sizes
// (bench_real_frames.cpp), single-threaded unless a name says otherwise.
// scripts/bench.sh runs it and writes docs/PERFORMANCE.md from its JSON output.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>

#include "bench_real_frames.h"
#include "opencv_pipeline.h"
#include "rgbd_lane_detector/depth_points.h"
#include "rgbd_lane_detector/fals_normals.h"
#include "rgbd_lane_detector/half_binary.h"
#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector/lane_grid.h"
#include "rgbd_lane_detector/response_map.h"
#include "rgbd_lane_detector/template_matching.h"
#include "road_frames.h"
#include "simd.h"

namespace rgbd_lane_detector {
namespace bench {
namespace {

constexpr int kFrames = 8;

// Frames and the detector's steady-state templates for one size, built once.
struct Data {
  int width = 0, height = 0;
  std::vector<RoadFrame> frames;
  Params params = Params::paper();  ///< the paper mode, the OpenCV pipeline's configuration
  LineTemplate left, right;         ///< templates detect() uses after warm-up (adapted angles)
  cv::Rect roi;
};

Data& data(int width) {
  static std::map<int, std::unique_ptr<Data>> cache;
  auto& d = cache[width];
  if (d) return *d;
  d = std::make_unique<Data>();
  d->width = width;
  d->height = width * 380 / 640;
  d->frames.resize(kFrames);
  for (int i = 0; i < kFrames; ++i) renderRoadFrame(d->width, d->height, i, d->frames[i]);
  LaneDetector det(d->params);
  Result r;
  for (int i = 0; i < kFrames; ++i) det.detect(d->frames[i].frame(), r);
  d->left = det.leftTemplate();
  d->right = det.rightTemplate();
  d->left.image = d->left.image.clone();
  d->right.image = d->right.image.clone();
  d->roi = r.roi;
  return *d;
}

cv::Range roiRows(const Data& d) {
  return cv::Range(d.roi.y, d.roi.br().y);
}

void setLabel(benchmark::State& state, const Data& d) {
  auto slope = [](const LineTemplate& t) {
    return std::to_string(t.slope_p) + "/" + std::to_string(t.slope_q);
  };
  state.SetLabel(std::to_string(d.width) + "x" + std::to_string(d.height) + " slopes " +
                 slope(d.left) + " " + slope(d.right));
}

// ---------------------------------------------------------------------------------------------
// Whole frame

void BM_Detect(benchmark::State& state) {
  Data& d = data(static_cast<int>(state.range(0)));
  LaneDetector det(d.params);
  Result r;
  for (int i = 0; i < kFrames; ++i) det.detect(d.frames[i].frame(), r);  // warm-up
  StageTimings sum;
  int i = 0;
  for (auto _ : state) {
    det.detect(d.frames[i++ % kFrames].frame(), r);
    benchmark::DoNotOptimize(r.plane.distance);
    sum += r.timings;
  }
  using C = benchmark::Counter;
  state.counters["preprocess_ms"] = C(sum.preprocess, C::kAvgIterations);
  state.counters["points_ms"] = C(sum.points, C::kAvgIterations);
  state.counters["normals_ms"] = C(sum.normals, C::kAvgIterations);
  state.counters["matching_ms"] = C(sum.matching, C::kAvgIterations);
  state.counters["response_ms"] = C(sum.response, C::kAvgIterations);
  state.counters["pca_ms"] = C(sum.pca, C::kAvgIterations);
  state.counters["tracing_ms"] = C(sum.tracing, C::kAvgIterations);
  state.counters["plane_ms"] = C(sum.plane, C::kAvgIterations);
  setLabel(state, d);
}

// Time detect() with @p params over the frames of @p d, after one warm-up pass.
void timeDetect(benchmark::State& state, Data& d, const Params& params, bool full_g = false) {
  LaneDetector det(params);
  det.setFullGeometricMap(full_g);
  Result r;
  for (int i = 0; i < kFrames; ++i) det.detect(d.frames[i].frame(), r);  // warm-up
  int i = 0;
  for (auto _ : state) {
    det.detect(d.frames[i++ % kFrames].frame(), r);
    benchmark::DoNotOptimize(r.plane.distance);
  }
  setLabel(state, d);
}

// detect() forced onto one SIMD target (simd.h), paper mode, single thread: every target of this
// machine against the OpenCV pipeline in the same run.
void BM_DetectOn(benchmark::State& state, simd::Target target) {
  Data& d = data(static_cast<int>(state.range(0)));
  simd::forceTarget(target);
  timeDetect(state, d, d.params);
  simd::forceTarget(simd::kBest);
}

// The same in the improved (default) mode: what a user's camera gets on each target (SSE4 has the
// width of the ARM target's NEON).
void BM_DetectImprovedOn(benchmark::State& state, simd::Target target) {
  Data& d = data(static_cast<int>(state.range(0)));
  simd::forceTarget(target);
  timeDetect(state, d, Params::improved());
  simd::forceTarget(simd::kBest);
}

// The first detect() of a new detector (a start; a resolution change is the same), with or
// without LaneDetector::prepare() on the camera's size and intrinsics before it (as the nodelet
// does on camera_info). Only detect() is timed; steady state is BM_Detect.
void BM_FirstFrame(benchmark::State& state, bool prepared) {
  Data& d = data(static_cast<int>(state.range(0)));
  const Frame f = d.frames[0].frame();
  for (auto _ : state) {
    auto det = std::make_unique<LaneDetector>(d.params);
    if (prepared) det->prepare(f.colour.size(), f.intrinsics, f.format);
    Result r;
    const auto t0 = std::chrono::steady_clock::now();  // manual time: detect() alone
    det->detect(f, r);
    state.SetIterationTime(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    benchmark::DoNotOptimize(r.plane.distance);
  }  // the detector's memory goes back: the next one starts cold
  setLabel(state, d);
}

// detect() in the package's recommended mode (Params::improved(): adaptive threshold, gates,
// lane model), single thread.
void BM_DetectImproved(benchmark::State& state) {
  Data& d = data(static_cast<int>(state.range(0)));
  timeDetect(state, d, Params::improved());
}

// detect() with G at every pixel (LaneDetector::setFullGeometricMap: what the nodelet does while
// response/geometric has a subscriber), one thread.
void BM_DetectFullG(benchmark::State& state) {
  Data& d = data(static_cast<int>(state.range(0)));
  timeDetect(state, d, d.params, true);
}

// The same with the second core (runPair: normals + G next to matching), wall time.
void BM_Detect2(benchmark::State& state) {
  Data& d = data(static_cast<int>(state.range(0)));
  cv::setNumThreads(2);
  timeDetect(state, d, d.params, true);
  cv::setNumThreads(1);
}

// LaneGrid::build() (lane_grid, issue 25) from the improved mode's lane model of the 640x380
// frames, at the default size (0.1 m, 40 m x 20 m: 400 x 200 cells) or @p resolution, with or
// without lane changes allowed. One thread; the grid's cells are reused (steady state).
void BM_LaneGrid(benchmark::State& state, double resolution, bool allow_lane_change) {
  Data& d = data(640);
  LaneDetector det(Params::improved());
  Result r;
  for (int i = 0; i < kFrames; ++i) det.detect(d.frames[i].frame(), r);
  if (!r.lane_model.valid) {
    state.SkipWithError("no lane model on the bench frames");
    return;
  }
  LaneGridSettings settings;
  settings.resolution = resolution;
  settings.allow_lane_change = allow_lane_change;
  LaneGrid grid;
  grid.build(r.lane_model, settings);  // sizes the cells
  for (auto _ : state) {
    grid.build(r.lane_model, settings);
    benchmark::DoNotOptimize(grid.cells().data());
    benchmark::ClobberMemory();
  }
  long free_cells = 0;
  for (int8_t v : grid.cells()) free_cells += v == LaneGrid::kFree;
  state.counters["cells"] = static_cast<double>(grid.cells().size());
  state.counters["free_cells"] = static_cast<double>(free_cells);
  state.SetLabel(std::to_string(grid.cols()) + "x" + std::to_string(grid.rows()) + " cells");
}

void BM_OpenCV_Pipeline(benchmark::State& state) {
  Data& d = data(static_cast<int>(state.range(0)));
  OpenCvPipeline cv_pipe;
  cv_pipe.configure(d.frames[0].frame(), d.params);
  int i = 0;
  for (auto _ : state) {
    cv_pipe.run(d.frames[i++ % kFrames].frame(), d.left, d.right);
    benchmark::DoNotOptimize(cv_pipe.response_left.data);
  }
  setLabel(state, d);
}

// ---------------------------------------------------------------------------------------------
// Stages of the core, called as detect() calls them, on frame 0

void BM_Stage_HalfBinary(benchmark::State& state) {
  Data& d = data(static_cast<int>(state.range(0)));
  const Frame f = d.frames[0].frame();
  cv::Mat hb;
  for (auto _ : state) {
    halfBinary(f.colour, f.format, d.params.tau_c, roiRows(d), hb);
    benchmark::ClobberMemory();
  }
  setLabel(state, d);
}

void BM_Stage_Points(benchmark::State& state) {
  Data& d = data(static_cast<int>(state.range(0)));
  const Frame f = d.frames[0].frame();
  DepthDecoder dec;
  dec.scale = f.depth_scale;
  dec.min_depth = d.params.min_depth;
  dec.max_depth = d.params.max_depth;
  const int h = d.params.normal_window / 2;
  const cv::Range rows(std::max(0, d.roi.y - h), std::min(d.height, d.roi.br().y + h));
  cv::Mat pts;
  DepthPointsTables tables;  // kept, as the detector keeps them
  for (auto _ : state) {
    depthToPoints(f.depth, dec, f.intrinsics, rows, pts, cv::Mat(), cv::Mat(), nullptr, &tables);
    benchmark::ClobberMemory();
  }
  setLabel(state, d);
}

struct Prepared {
  cv::Mat hb, pts, normals, G, ml, mr;
};

Prepared prepare(const Data& d) {
  Prepared p;
  const Frame f = d.frames[0].frame();
  halfBinary(f.colour, f.format, d.params.tau_c, cv::Range(0, d.height), p.hb);
  DepthDecoder dec;
  dec.scale = f.depth_scale;
  dec.min_depth = d.params.min_depth;
  dec.max_depth = d.params.max_depth;
  depthToPoints(f.depth, dec, f.intrinsics, cv::Range(0, d.height), p.pts);
  FalsNormals fals;
  fals.configure(p.pts.size(), f.intrinsics, d.params.normal_window);
  fals.computeGeometric(p.pts, roiRows(d), d.params, p.G);
  NccMatcher m;
  m.match(p.hb, d.roi, d.left, d.right, p.ml, p.mr);
  return p;
}

void BM_Stage_Normals(benchmark::State& state) {
  Data& d = data(static_cast<int>(state.range(0)));
  Prepared p = prepare(d);
  FalsNormals fals;
  fals.configure(p.pts.size(), d.frames[0].K, d.params.normal_window);
  for (auto _ : state) {  // as detect() runs it: G straight from the normals
    fals.computeGeometric(p.pts, roiRows(d), d.params, p.G);
    benchmark::ClobberMemory();
  }
  setLabel(state, d);
}

void BM_Stage_Matching(benchmark::State& state) {
  Data& d = data(static_cast<int>(state.range(0)));
  Prepared p = prepare(d);
  NccMatcher m;
  for (auto _ : state) {
    m.match(p.hb, d.roi, d.left, d.right, p.ml, p.mr);
    benchmark::ClobberMemory();
  }
  setLabel(state, d);
}

void BM_Stage_Response(benchmark::State& state) {
  Data& d = data(static_cast<int>(state.range(0)));
  Prepared p = prepare(d);
  const float tau = static_cast<float>(d.params.tau_g);
  for (auto _ : state) {  // G comes with the normals
    fuseResponse(p.ml, p.G, tau, roiRows(d), p.ml);
    fuseResponse(p.mr, p.G, tau, roiRows(d), p.mr);
    benchmark::ClobberMemory();
  }
  setLabel(state, d);
}

// ---------------------------------------------------------------------------------------------
// Stages of the OpenCV pipeline on frame 0

template <int kStage>
void BM_OpenCV_Stage(benchmark::State& state) {
  Data& d = data(static_cast<int>(state.range(0)));
  const Frame f = d.frames[0].frame();
  OpenCvPipeline cvp;
  cvp.configure(f, d.params);
  cvp.run(f, d.left, d.right);
  for (auto _ : state) {
    switch (kStage) {
      case 0:
        cvp.preprocess(f);
        break;
      case 1:
        cvp.points(f);
        break;
      case 2:
        cvp.normals();
        break;
      case 3:
        cvp.matching(d.left, d.right);
        break;
      default:
        cvp.response();
        break;
    }
    benchmark::ClobberMemory();
  }
  setLabel(state, d);
}

void sizes(benchmark::internal::Benchmark* b) {
  b->Arg(640)->Arg(1280)->Unit(benchmark::kMillisecond)->MinTime(0.5);
}

BENCHMARK(BM_Detect)->Apply(sizes);
BENCHMARK_CAPTURE(BM_FirstFrame, Unprepared, false)->Apply(sizes)->UseManualTime();
BENCHMARK_CAPTURE(BM_FirstFrame, Prepared, true)->Apply(sizes)->UseManualTime();
BENCHMARK(BM_DetectImproved)->Apply(sizes);
BENCHMARK(BM_DetectFullG)->Apply(sizes);
BENCHMARK(BM_Detect2)->Apply(sizes)->UseRealTime();
BENCHMARK(BM_OpenCV_Pipeline)->Apply(sizes);
BENCHMARK_CAPTURE(BM_LaneGrid, Default, 0.1, false)->Unit(benchmark::kMicrosecond)->MinTime(0.5);
BENCHMARK_CAPTURE(BM_LaneGrid, LaneChange, 0.1, true)->Unit(benchmark::kMicrosecond)->MinTime(0.5);
BENCHMARK_CAPTURE(BM_LaneGrid, Fine5cm, 0.05, false)->Unit(benchmark::kMicrosecond)->MinTime(0.5);
BENCHMARK(BM_Stage_HalfBinary)->Apply(sizes);
BENCHMARK(BM_Stage_Points)->Apply(sizes);
BENCHMARK(BM_Stage_Normals)->Apply(sizes);
BENCHMARK(BM_Stage_Matching)->Apply(sizes);
BENCHMARK(BM_Stage_Response)->Apply(sizes);
BENCHMARK_TEMPLATE(BM_OpenCV_Stage, 0)->Name("BM_OpenCV_Preprocess")->Apply(sizes);
BENCHMARK_TEMPLATE(BM_OpenCV_Stage, 1)->Name("BM_OpenCV_Points")->Apply(sizes);
BENCHMARK_TEMPLATE(BM_OpenCV_Stage, 2)->Name("BM_OpenCV_Normals")->Apply(sizes);
BENCHMARK_TEMPLATE(BM_OpenCV_Stage, 3)->Name("BM_OpenCV_Matching")->Apply(sizes);
BENCHMARK_TEMPLATE(BM_OpenCV_Stage, 4)->Name("BM_OpenCV_Response")->Apply(sizes);

// ---------------------------------------------------------------------------------------------
// Equality with the reference implementation, reported in the JSON context

double maxAbsDiff(const cv::Mat& a, const cv::Mat& b, const cv::Rect& roi) {
  return cv::norm(a(roi), b(roi), cv::NORM_INF);
}

// Detections are set-based (thresholded pixels, argmax): identical means equal seeds, traces,
// angles and planes; scores are R samples and may differ by R's float rounding.
bool sameDetections(const Result& a, const Result& b, double score_tol) {
  auto same_side = [&](const MarkerTrace& p, const MarkerTrace& q) {
    if (p.found != q.found || p.seed != q.seed || p.angle != q.angle ||
        p.angle_valid != q.angle_valid || p.pixels != q.pixels ||
        p.num_valid_points != q.num_valid_points || p.scores.size() != q.scores.size() ||
        std::fabs(p.peak_score - q.peak_score) > score_tol)
      return false;
    for (size_t i = 0; i < p.scores.size(); ++i)
      if (std::fabs(p.scores[i] - q.scores[i]) > score_tol) return false;
    for (size_t i = 0; i < p.points.size(); ++i)
      if (!(p.points[i].array() == q.points[i].array() ||
            (p.points[i].array().isNaN() && q.points[i].array().isNaN()))
               .all())
        return false;
    return true;
  };
  return a.status == b.status && same_side(a.left, b.left) && same_side(a.right, b.right) &&
         a.plane.valid == b.plane.valid && a.plane.normal == b.plane.normal &&
         a.plane.distance == b.plane.distance && a.template_angle_left == b.template_angle_left &&
         a.template_angle_right == b.template_angle_right;
}

void reportEquality(int width) {
  Data& d = data(width);
  const std::string key = std::to_string(d.width) + "x" + std::to_string(d.height);
  // 1. matcher against cv::matchTemplate, both templates, every frame
  double max_m = 0.0;
  // 2. detect() against detect() on the reference stages, frame by frame from the same start
  LaneDetector fast(d.params), ref(d.params);
  fast.setFullGeometricMap(true);  // G compared at every pixel
  ref.setFullGeometricMap(true);
  Result rf, rr;
  double max_r = 0.0, max_g = 0.0;
  int identical = 0, g_beyond = 0;
  for (int i = 0; i < kFrames; ++i) {
    const Frame f = d.frames[i].frame();
    fast.detect(f, rf);
    setReferenceStages(true);
    ref.detect(f, rr);
    setReferenceStages(false);
    cv::Mat ml, mr, rl, rrr;
    NccMatcher m;
    m.match(rf.half_binary, rf.roi, fast.leftTemplate(), fast.rightTemplate(), ml, mr);
    matchTemplateReference(rf.half_binary, rf.roi, fast.leftTemplate(), rl);
    matchTemplateReference(rf.half_binary, rf.roi, fast.rightTemplate(), rrr);
    max_m = std::max({max_m, maxAbsDiff(ml, rl, rf.roi), maxAbsDiff(mr, rrr, rf.roi)});
    max_g = std::max(max_g, maxAbsDiff(rf.geometric, rr.geometric, rf.roi));
    cv::Mat g_diff;
    cv::absdiff(rf.geometric(rf.roi), rr.geometric(rf.roi), g_diff);
    g_beyond += cv::countNonZero(g_diff > 1e-4);
    max_r = std::max({max_r, maxAbsDiff(rf.response_left, rr.response_left, rf.roi),
                      maxAbsDiff(rf.response_right, rr.response_right, rf.roi)});
    identical += sameDetections(rf, rr, 1e-4);
  }
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.3g", max_m);
  benchmark::AddCustomContext("equal " + key + " max |M - matchTemplate|", buf);
  std::snprintf(buf, sizeof(buf), "%.3g", max_g);
  benchmark::AddCustomContext("equal " + key + " max |G - G double FALS|", buf);
  std::snprintf(buf, sizeof(buf), "%.3g", max_r);
  benchmark::AddCustomContext("equal " + key + " max |R - R reference|", buf);
  benchmark::AddCustomContext(
      "equal " + key + " G pixels beyond 1e-4",
      std::to_string(g_beyond) + " of " + std::to_string(kFrames * d.roi.area()));
  benchmark::AddCustomContext("equal " + key + " identical detections",
                              std::to_string(identical) + "/" + std::to_string(kFrames));
}

}  // namespace
}  // namespace bench
}  // namespace rgbd_lane_detector

int main(int argc, char** argv) {
  cv::setNumThreads(1);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  using namespace rgbd_lane_detector;
  for (int width : {640, 1280}) bench::reportEquality(width);
  std::string names;
  for (simd::Target t : simd::availableTargets()) {
    const std::string name = simd::targetName(t);
    names += (names.empty() ? "" : " ") + name;
    benchmark::RegisterBenchmark(("BM_DetectOn_" + name).c_str(), bench::BM_DetectOn, t)
        ->Apply(bench::sizes);
    benchmark::RegisterBenchmark(("BM_DetectImprovedOn_" + name).c_str(),
                                 bench::BM_DetectImprovedOn, t)
        ->Apply(bench::sizes);
  }
  benchmark::AddCustomContext("simd targets", names);
  benchmark::AddCustomContext("real frames", std::to_string(bench::registerRealFrameBenchmarks()));
  benchmark::AddCustomContext("simd best target", simd::targetName(simd::currentTarget()));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
