// Fixed-work driver for instruction-count profiling of one stage or the whole detect():
//   valgrind --tool=callgrind --toggle-collect='*measured*' profile_core matching 1280 10
// (Google Benchmark picks its own iteration counts, which makes callgrind totals hard to compare.)
#include <cstdio>
#include <cstdlib>
#include <ctime>

#include <sys/resource.h>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/depth_points.h"
#include "rgbd_lane_detector/fals_normals.h"
#include "rgbd_lane_detector/half_binary.h"
#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector/response_map.h"
#include "rgbd_lane_detector/template_matching.h"
#include "road_frames.h"

using namespace rgbd_lane_detector;

// The measured work: profile with --toggle-collect='*measured*'.
template <typename F>
__attribute__((noinline)) void measured(int n, F&& f) {
  for (int i = 0; i < n; ++i) f(i);
}

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(
        stderr,
        "usage: %s detect|halfbinary|points|normals|normals_only|matching|response WIDTH N "
        "[SIMD_LEVEL]\n",
        argv[0]);
    return 2;
  }
  const std::string stage = argv[1];
  const int width = std::atoi(argv[2]), n = std::atoi(argv[3]);
  if (argc > 4) setMaxSimdLevel(std::atoi(argv[4]));  // 0 baseline, 1 AVX2, 2 AVX-512
  cv::setNumThreads(1);
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
  depthToPoints(f.depth, dec, f.intrinsics, cv::Range(0, f.colour.rows), pts);
  FalsNormals fals;
  fals.configure(pts.size(), f.intrinsics, params.normal_window);
  fals.computeGeometric(pts, rows, params, G);
  NccMatcher matcher;
  matcher.match(hb, r.roi, det.leftTemplate(), det.rightTemplate(), ml, mr);
  bool ok = true;
  // CPU time of this process: on a shared machine wall time also counts other jobs' slices
  auto cpu_ms = [] {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
  };
  const double start = cpu_ms();
  measured(n, [&](int i) {
    if (stage == "detect") {
      det.detect(frames[i % 4].frame(), r);
    } else if (stage == "halfbinary") {
      halfBinary(f.colour, f.format, params.tau_c, rows, hb);
    } else if (stage == "points") {
      depthToPoints(f.depth, dec, f.intrinsics, rows, pts);
    } else if (stage == "normals") {  // as detect() runs it: G from the normals
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
  std::printf("%s %d x%d: %.3f ms CPU per call, slopes %d/%d %d/%d\n", stage.c_str(), width, n,
              ms / n, det.leftTemplate().slope_p, det.leftTemplate().slope_q,
              det.rightTemplate().slope_p, det.rightTemplate().slope_q);
  return 0;
}
