// Fixed-work driver for instruction-count profiling of one stage or the whole detect():
//   valgrind --tool=callgrind --toggle-collect='*measured*' profile_core matching 1280 10
// (Google Benchmark picks its own iteration counts, which makes callgrind totals hard to compare.)
// A real corpus frame (bench/real_inputs.h) in the default mode, CPU time and stage timings:
//   perf record -g profile_core real pandaset 300
// The frames measure_transport.sh plays (the real RADIATE drive, resized, in a loop) in the
// default mode: the spread of each frame's CPU time, which bounds a stream's latency tail:
//   profile_core sequence 1920x1080 600
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>

#include <sys/resource.h>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/depth_points.h"
#include "rgbd_lane_detector/fals_normals.h"
#include "rgbd_lane_detector/half_binary.h"
#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector/params_io.h"
#include "rgbd_lane_detector/response_map.h"
#include "rgbd_lane_detector/template_matching.h"
#ifdef RLD_PROFILE_REAL_FRAMES  // the catkin build: the tools' dataset readers
#include "real_inputs.h"
#include "frame_source.h"  // tools/ros: the frames FramePlayerNodelet publishes
#endif
#include "road_frames.h"
#include "simd.h"

using namespace rgbd_lane_detector;

// The measured work: profile with --toggle-collect='*measured*'.
template <typename F>
__attribute__((noinline)) void measured(int n, F&& f) {
  for (int i = 0; i < n; ++i) f(i);
}

void printStages(const StageTimings& sum, int n) {
  std::printf(
      "stages ms: preprocess %.3f points %.3f road %.3f normals %.3f matching %.3f response %.3f "
      "pca %.3f tracing %.3f classify %.3f plane %.3f model %.3f total %.3f\n",
      sum.preprocess / n, sum.points / n, sum.road / n, sum.normals / n, sum.matching / n,
      sum.response / n, sum.pca / n, sum.tracing / n, sum.classify / n, sum.plane / n,
      sum.model / n, sum.total / n);
}

// FNV-1a of a result's maps, traces and plane: equal bits give equal sums (SIMD targets, a change
// that must not change any detection).
[[maybe_unused]] uint64_t checksum(const Result& r, bool with_geometric = true) {
  uint64_t h = 1469598103934665603ull;
  auto add = [&h](const void* p, size_t n) {
    for (size_t i = 0; i < n; ++i) h = (h ^ static_cast<const uint8_t*>(p)[i]) * 1099511628211ull;
  };
  for (const cv::Mat* m : {&r.half_binary, &r.geometric, &r.response_left, &r.response_right}) {
    if (m == &r.geometric && !with_geometric) continue;
    for (int y = 0; y < m->rows; ++y) add(m->ptr(y), m->cols * m->elemSize());
  }
  for (const MarkerTrace* t : {&r.left, &r.right}) {
    add(&t->found, sizeof(t->found));
    add(&t->confidence, sizeof(t->confidence));
    add(t->pixels.data(), t->pixels.size() * sizeof(t->pixels[0]));
    add(t->points.data(), t->points.size() * sizeof(t->points[0]));
  }
  add(r.plane.normal.data(), 3 * sizeof(double));
  add(&r.plane.distance, sizeof(r.plane.distance));
  return h;
}

// The default mode on one real frame, again and again after a warm-up (the steady state of a
// drive, as BM_Real_Detect): CPU ms per call and the stages' wall ms.
template <typename Clock>
int profileReal(const std::string& label, int n, const Params& params, Clock cpu_ms) {
#ifndef RLD_PROFILE_REAL_FRAMES
  (void)n, (void)params, (void)cpu_ms;
  std::fprintf(stderr, "real frame %s: this build has no dataset readers (the catkin build has)\n",
               label.c_str());
  return 2;
#else
  const bench::RealInput* in = bench::realInput(label);
  tools::DatasetFrame data;
  std::string error;
  if (!in || !bench::loadRealFrame(*in, data, error)) {
    std::fprintf(stderr, "real frame %s: %s\n", label.c_str(), in ? error.c_str() : "unknown");
    return 2;
  }
  const Frame f = data.toFrame();
  LaneDetector det(params);
  Result r;
  for (int i = 0; i < 5; ++i) det.detect(f, r);
  StageTimings sum;
  const double start = cpu_ms();
  measured(n, [&](int) {
    det.detect(f, r);
    sum += r.timings;
  });
  const double ms = cpu_ms() - start;
  printStages(sum, n);
  // (G is computed where it enters R: a map that enters nowhere changes it, not the detections)
  std::printf("real %s %dx%d (scale %.3f) x%d on %s: %.3f ms CPU per call, result %016llx, "
              "without G %016llx\n",
              label.c_str(), f.colour.cols, f.colour.rows, r.scale, n,
              simd::targetName(simd::currentTarget()), ms / n,
              static_cast<unsigned long long>(checksum(r)),
              static_cast<unsigned long long>(checksum(r, false)));
  return 0;
#endif
}

// The default mode over the frames FramePlayerNodelet publishes (tools/ros/frame_source.h: the
// real RADIATE drive resized to @p size, in a loop, as measure_transport.sh plays it), one detector
// as in a stream: each frame's CPU time (this thread), after one pass of warm-up.
int profileSequence(const std::string& size, int n) {
#ifndef RLD_PROFILE_REAL_FRAMES
  (void)size, (void)n;
  std::fprintf(stderr, "sequence: this build has no dataset readers (the catkin build has)\n");
  return 2;
#else
  tools::FrameSourceOptions options;
  if (std::sscanf(size.c_str(), "%dx%d", &options.width, &options.height) != 2 ||
      options.width <= 0 || options.height <= 0 || n <= 0) {
    std::fprintf(stderr, "sequence: size WIDTHxHEIGHT and N > 0, not %s %d\n", size.c_str(), n);
    return 2;
  }
  std::vector<tools::DatasetFrame> data;
  std::string source, warning;
  tools::loadFrameSource(options, data, source, warning);
  if (data.empty()) {
    std::fprintf(stderr, "sequence: no frames (%s)\n", warning.c_str());
    return 2;
  }
  std::vector<Frame> frames;
  for (const tools::DatasetFrame& d : data) frames.push_back(d.toFrame());
  auto thread_ms = [] {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
  };
  LaneDetector det{Params()};
  Result r;
  const int m = static_cast<int>(frames.size());
  for (int i = 0; i < m; ++i) det.detect(frames[i], r);  // warm-up: one pass
  std::vector<double> ms(static_cast<size_t>(n));
  measured(n, [&](int i) {
    const double start = thread_ms();
    det.detect(frames[i % m], r);
    ms[static_cast<size_t>(i)] = thread_ms() - start;
  });
  double sum = 0.0;
  for (double v : ms) sum += v;
  const int worst = static_cast<int>(std::max_element(ms.begin(), ms.end()) - ms.begin());
  const double max = ms[static_cast<size_t>(worst)];
  std::vector<double> sorted = ms;
  std::sort(sorted.begin(), sorted.end());
  auto pct = [&](double q) {
    return sorted[std::min(sorted.size() - 1, static_cast<size_t>(q * (sorted.size() - 1) + 0.5))];
  };
  const double mean = sum / n;
  // the frames of the loop that cost most on every pass (the scene, not the machine's noise):
  // each position's median over the passes
  int costliest = 0;
  double costliest_ms = 0.0;
  for (int k = 0; k < m; ++k) {
    std::vector<double> at;
    for (int i = k; i < n; i += m) at.push_back(ms[static_cast<size_t>(i)]);
    if (at.empty()) continue;
    std::nth_element(at.begin(), at.begin() + at.size() / 2, at.end());
    if (at[at.size() / 2] > costliest_ms) {
      costliest_ms = at[at.size() / 2];
      costliest = k;
    }
  }
  std::printf("sequence %s (%s, %d frames in a loop, scale %.3f) x%d on %s: CPU ms per frame mean "
              "%.3f p50 %.3f p99 %.3f max %.3f (frame %d of the loop), p99/mean %.2f; costliest "
              "frame of the loop (median over the passes) %d: %.3f ms, %.2f x the mean\n",
              size.c_str(), source.c_str(), m, r.scale, n,
              simd::targetName(simd::currentTarget()), mean, pct(0.5), pct(0.99), max,
              worst % m, pct(0.99) / mean, costliest, costliest_ms, costliest_ms / mean);
  return 0;
#endif
}

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(
        stderr,
        "usage: %s detect|improved|halfbinary|points|normals|normals_only|matching|response|targets WIDTH N "
        "[TARGET (AVX3, AVX2, SSE4, NEON, scalar)]\n"
        "       %s real radiate_fog|kitti|nuscenes|pandaset|dgp N [TARGET] [param=value ...]\n"
        "       %s sequence WIDTHxHEIGHT N [TARGET]\n",
        argv[0], argv[0], argv[0]);
    return 2;
  }
  const std::string stage = argv[1];
  if (stage == "targets") {  // the SIMD targets of this machine, best first
    for (simd::Target t : simd::availableTargets()) std::printf("%s\n", simd::targetName(t));
    return 0;
  }
  const int n = std::atoi(argv[3]);
  // real: detector parameters name=value after N (the default mode's otherwise)
  Params real_params;
  int argn = argc;
  while (stage == "real" && argn > 4 && std::strchr(argv[argn - 1], '=')) {
    const std::string kv = argv[--argn];
    const size_t eq = kv.find('=');
    std::string error;
    if (!setParamText(real_params, kv.substr(0, eq), kv.substr(eq + 1), &error)) {
      std::fprintf(stderr, "%s: %s\n", kv.c_str(), error.c_str());
      return 2;
    }
  }
  if (argn > 4) {  // a SIMD target of this machine (simd.h), else the best
    const simd::Target t = simd::targetByName(argv[4]);
    if (t < 0) {
      std::fprintf(stderr, "target %s not available here\n", argv[4]);
      return 2;
    }
    simd::forceTarget(t);
  }
  cv::setNumThreads(1);
  // CPU time of this process: on a shared machine wall time also counts other jobs' slices
  auto cpu_ms = [] {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
  };
  if (stage == "real") return profileReal(argv[2], n, real_params, cpu_ms);
  if (stage == "sequence") return profileSequence(argv[2], n);
  const int width = std::atoi(argv[2]);
  std::vector<bench::RoadFrame> frames(4);
  for (int i = 0; i < 4; ++i) bench::renderRoadFrame(width, width * 380 / 640, i, frames[i]);
  const Params params = Params::paper();
  LaneDetector det(params);
  Result r;
  for (auto& f : frames) det.detect(f.frame(), r);  // steady-state templates
  const Frame f = frames[0].frame();
  const cv::Range rows(r.roi.y, r.roi.br().y);
  cv::Mat hb, pts, normals, G, ml, mr;
  halfBinary(f.colour, f.format, params.tau_c, cv::Range(0, f.colour.rows), hb);
  DepthDecoder dec;
  dec.scale = f.depth_scale;
  dec.min_depth = params.min_depth;
  dec.max_depth = params.max_depth;
  DepthPointsTables tables;  // kept, as the detector keeps them
  depthToPoints(f.depth, dec, f.intrinsics, cv::Range(0, f.colour.rows), pts, cv::Mat(), cv::Mat(),
                nullptr, &tables);
  FalsNormals fals;
  fals.configure(pts.size(), f.intrinsics, params.normal_window);
  fals.computeGeometric(pts, rows, params, G);
  NccMatcher matcher;
  matcher.match(hb, r.roi, det.leftTemplate(), det.rightTemplate(), ml, mr);
  bool ok = true;
  const double start = cpu_ms();
  LaneDetector improved(Params::improved());
  StageTimings sum;
  if (stage == "improved")
    for (auto& fr : frames) improved.detect(fr.frame(), r);  // steady state, as for detect
  measured(n, [&](int i) {
    if (stage == "detect") {
      det.detect(frames[i % 4].frame(), r);
    } else if (stage == "improved") {  // the recommended mode, with its stage timings
      improved.detect(frames[i % 4].frame(), r);
      const StageTimings& t = r.timings;
      for (auto m : {&StageTimings::preprocess, &StageTimings::points, &StageTimings::road,
                     &StageTimings::normals, &StageTimings::matching, &StageTimings::response,
                     &StageTimings::pca, &StageTimings::tracing, &StageTimings::classify,
                     &StageTimings::plane, &StageTimings::model, &StageTimings::total})
        sum.*m += t.*m;
    } else if (stage == "halfbinary") {
      halfBinary(f.colour, f.format, params.tau_c, rows, hb);
    } else if (stage == "points") {
      depthToPoints(f.depth, dec, f.intrinsics, rows, pts, cv::Mat(), cv::Mat(), nullptr, &tables);
    } else if (stage == "normals") {  // the whole map (detect() with setFullGeometricMap)
      fals.computeGeometric(pts, rows, params, G);
    } else if (stage == "normals_only") {
      fals.compute(pts, rows, normals);
    } else if (stage == "matching") {
      matcher.match(hb, r.roi, det.leftTemplate(), det.rightTemplate(), ml, mr);
    } else if (stage == "response") {
      fuseResponse(ml, G, static_cast<float>(params.tau_g), rows, ml);
      fuseResponse(mr, G, static_cast<float>(params.tau_g), rows, mr);
    } else {
      ok = false;
    }
  });
  if (!ok) {
    std::fprintf(stderr, "unknown stage %s\n", stage.c_str());
    return 2;
  }
  const double ms = cpu_ms() - start;
  rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  std::printf("peak RSS %ld kB\n", usage.ru_maxrss);
  if (stage == "improved") printStages(sum, n);  // wall time inside detect(), ms per frame
  std::printf("%s %d x%d on %s: %.3f ms CPU per call, slopes %d/%d %d/%d\n", stage.c_str(), width,
              n, simd::targetName(simd::currentTarget()), ms / n, det.leftTemplate().slope_p,
              det.leftTemplate().slope_q, det.rightTemplate().slope_p, det.rightTemplate().slope_q);
  return 0;
}
