#include "frame_source.h"

#include <cmath>
#include <filesystem>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector_tools/synth/renderer.h"
#include "rgbd_lane_detector_tools/synth/scenario.h"

namespace rgbd_lane_detector {
namespace tools {

std::string defaultFrameSourcePath() {
#ifdef RLD_DEFAULT_REALDATA
  return std::string(RLD_DEFAULT_REALDATA) + "/sequences/radiate_fog";
#else
  return std::string();
#endif
}

namespace {

void resizeFrame(DatasetFrame& f, int width, int height) {
  if (width <= 0 || height <= 0) {
    width = f.colour.cols;
    height = f.colour.rows;
  }
  const cv::Size size(width, height);
  const double sx = static_cast<double>(width) / f.colour.cols;
  const double sy = static_cast<double>(height) / f.colour.rows;
  Intrinsics K = f.intrinsics;
  K.fx *= sx;
  K.fy *= sy;
  K.cx = (K.cx + 0.5) * sx - 0.5;
  K.cy = (K.cy + 0.5) * sy - 0.5;
  f.intrinsics = K;

  cv::Mat colour = f.colour;
  if (f.format == PixelFormat::kMono8) {
    cv::cvtColor(f.colour, colour, cv::COLOR_GRAY2BGR);
    f.format = PixelFormat::kBgr8;
  } else if (f.format == PixelFormat::kBgra8 || f.format == PixelFormat::kRgba8) {
    cv::cvtColor(f.colour, colour, cv::COLOR_BGRA2BGR);  // keeps the channel order
    f.format = f.format == PixelFormat::kBgra8 ? PixelFormat::kBgr8 : PixelFormat::kRgb8;
  }
  cv::Mat resized;
  if (colour.size() != size)
    cv::resize(colour, resized, size, 0, 0, cv::INTER_LINEAR);
  else
    resized = colour.clone();
  f.colour = resized;

  cv::Mat metres;  // CV_32FC1, NaN invalid
  if (f.depth.type() == CV_16UC1) {
    f.depth.convertTo(metres, CV_32F, f.depth_scale);
    metres.setTo(std::numeric_limits<float>::quiet_NaN(), f.depth == 0);
  } else {
    f.depth.convertTo(metres, CV_32F);
    metres.setTo(std::numeric_limits<float>::quiet_NaN(), metres <= 0);
  }
  cv::Mat depth;
  if (metres.size() != size)
    cv::resize(metres, depth, size, 0, 0, cv::INTER_NEAREST);
  else
    depth = metres;
  f.depth = depth;
  f.depth_scale = 1.0;
  f.lidar_depth.release();
}

}  // namespace

void loadFrameSource(const FrameSourceOptions& options, std::vector<DatasetFrame>& frames,
                     std::string& source, std::string& warning) {
  frames.clear();
  warning.clear();
  const int max_frames = std::max(1, options.max_frames);
  const std::string path = options.dataset.empty() ? defaultFrameSourcePath() : options.dataset;
  if (path.empty() || !std::filesystem::exists(path)) {
    warning = "no dataset at '" + path + "'";
  } else {
    DatasetOptions o;
    o.path = path;
    o.type = options.type;
    std::string error;
    auto reader = openDataset(o, error);
    if (!reader) {
      warning = "cannot open '" + path + "': " + error;
    } else {
      DatasetFrame f;
      while (static_cast<int>(frames.size()) < max_frames && reader->next(f)) {
        if (!options.filter.empty() && f.name.find(options.filter) == std::string::npos) continue;
        DatasetFrame g = f;  // next() may reuse the buffers
        g.colour = f.colour.clone();
        g.depth = f.depth.clone();
        resizeFrame(g, options.width, options.height);
        frames.push_back(std::move(g));
      }
      if (frames.empty())
        warning = "no frame read from '" + path + "' " + reader->error();
      else
        source = path;
    }
  }
  if (!frames.empty()) return;

  synth::SceneSettings s;
  s.frames = max_frames;
  s.width = 640;
  s.height = 380;
  s.seed = 1;
  synth::applyScenario("summer", s);
  synth::Renderer renderer(s);
  synth::RenderedFrame r;
  for (int i = 0; i < max_frames; ++i) {
    renderer.render(i, r);
    DatasetFrame f;
    f.index = i;
    f.name = std::to_string(i);
    f.colour = r.bgr.clone();
    f.format = PixelFormat::kBgr8;
    f.depth = r.depth.clone();
    f.depth_scale = 1.0;
    f.intrinsics = renderer.intrinsics();
    resizeFrame(f, options.width, options.height);
    frames.push_back(std::move(f));
  }
  source = "a generated road (summer)";
}

}  // namespace tools
}  // namespace rgbd_lane_detector
