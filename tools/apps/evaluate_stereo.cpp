// evaluate_stereo: depth from the colour stereo pair (StereoSGBM, as `--depth sgbm` computes it)
// against the LiDAR of KITTI folders: KITTI 2015 disparity errors (> 3 px, D1), density and the
// depth error over the road region, per frame and in total, as a Markdown table.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include <opencv2/core/utility.hpp>

#include "rgbd_lane_detector_tools/command_line.h"
#include "rgbd_lane_detector_tools/dataset/dataset.h"
#include "rgbd_lane_detector_tools/detector_setup.h"
#include "rgbd_lane_detector_tools/plane_check.h"
#include "rgbd_lane_detector_tools/stereo/stereo_check.h"

using namespace rgbd_lane_detector;

namespace {

std::string pct(double v) {
  if (!std::isfinite(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f%%", 100.0 * v);
  return buf;
}

std::string num(double v, const char* f = "%.2f") {
  if (!std::isfinite(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof(buf), f, v);
  return buf;
}

std::string row(const std::string& name, const tools::StereoCheck& c, double ms) {
  std::string r = "| " + name + " | " + std::to_string(c.reference()) + " | " +
                  pct(c.coverage()) + " | " + pct(c.outliers3px()) + " | " + pct(c.d1Matched()) +
                  " | " + pct(c.d1All()) + " | " + pct(c.density()) + " | " +
                  pct(c.roadCoverage()) + " | " + num(c.roadMeanError()) + " / " +
                  num(c.roadMedianError()) + " | " + num(c.roadBias(), "%+.2f") + " | " +
                  pct(c.roadRelativeError());
  for (size_t b = 0; b < tools::StereoCheck::kBins.size(); ++b)
    r += " | " + num(c.roadMeanError(static_cast<int>(b))) + " (" +
         std::to_string(c.roadPoints(static_cast<int>(b))) + ")";
  return r + " | " + num(ms, "%.0f") + " |";
}

}  // namespace

int main(int argc, char** argv) {
  tools::DatasetOptions data;
  data.depth = "sgbm";
  int threads = -1;
  tools::CommandLine cl(
      "evaluate_stereo",
      "Depth from the colour stereo pair (StereoSGBM, as run_dataset --depth sgbm computes it)\n"
      "against the LiDAR of a KITTI folder; prints a Markdown table (per frame and total).\n"
      "example: evaluate_stereo --dataset ../shared/realdata/kitti2015 --sgbm-param lr_check=0");
  cl.add("dataset", "KITTI folder with <id>_left.png, <id>_right.png and LiDAR (required)",
         &data.path);
  cl.add("max-frames", "stop after N frames", &data.max_frames);
  cl.add("threads", "OpenCV threads (default: OpenCV's choice; 1 for single-thread timing)",
         &threads);
  tools::addSgbmOptions(cl, data.sgbm);
  const auto parsed = cl.parse(argc, argv);
  if (parsed == tools::CommandLine::Parse::kHelp) return 0;
  if (parsed == tools::CommandLine::Parse::kError) return 2;
  if (data.path.empty()) {
    std::cerr << "evaluate_stereo: --dataset is required\n";
    return 2;
  }
  if (threads >= 0) cv::setNumThreads(threads);
  std::string error;
  auto reader = tools::openDataset(data, error);
  if (!reader) {
    std::cerr << "evaluate_stereo: " << error << "\n";
    return 1;
  }
  if (std::string(reader->kind()) != "kitti") {
    std::cerr << "evaluate_stereo: " << data.path << " is not a KITTI folder\n";
    return 1;
  }
  std::printf("StereoSGBM: %s; OpenCV threads: %d\n\n", tools::sgbmParamsText(data.sgbm).c_str(),
              cv::getNumThreads());
  std::string header =
      "| frame | LiDAR px | LiDAR px with SGBM | > 3 px | D1 | D1 (missing = error) | density | "
      "road coverage | road \\|dZ\\| mean / median (m) | road bias (m) | road \\|dZ\\|/Z";
  std::string rule = "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---:";
  double lo = 0.0;
  for (double hi : tools::StereoCheck::kBins) {
    header += " | \\|dZ\\| " + num(lo, "%.0f") + "-" + num(hi, "%.0f") + " m (px)";
    rule += " | ---:";
    lo = hi;
  }
  std::printf("%s | ms/frame |\n%s | ---: |\n", header.c_str(), rule.c_str());
  tools::StereoCheck total;
  tools::DatasetFrame f;
  double total_ms = 0;
  int frames = 0;
  using Clock = std::chrono::steady_clock;
  for (;;) {
    const Clock::time_point t0 = Clock::now();
    if (!reader->next(f)) break;
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (f.lidar_depth.empty()) {
      std::cerr << "evaluate_stereo: frame " << f.name << " has no LiDAR depth\n";
      return 1;
    }
    const double fb = f.intrinsics.fx * f.baseline;
    const cv::Rect road = tools::roadCheckRegion(f.depth.size(), f.intrinsics);
    tools::StereoCheck frame;
    if (!frame.add(f.depth, f.lidar_depth, f.lidar_depth_scale, fb, road) ||
        !total.add(f.depth, f.lidar_depth, f.lidar_depth_scale, fb, road)) {
      std::cerr << "evaluate_stereo: frame " << f.name << ": depth images do not fit\n";
      return 1;
    }
    std::printf("%s\n", row(f.name, frame, ms).c_str());
    total_ms += ms;
    ++frames;
  }
  if (!reader->error().empty()) {
    std::cerr << "evaluate_stereo: " << reader->error() << "\n";
    return 1;
  }
  if (frames == 0) {
    std::cerr << "evaluate_stereo: no frames\n";
    return 1;
  }
  std::printf("%s\n", row("all", total, total_ms / frames).c_str());
  return 0;
}
