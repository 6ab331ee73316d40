#include "rgbd_lane_detector_tools/synth/sequence_writer.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

namespace rgbd_lane_detector {
namespace synth {
namespace fs = std::filesystem;

std::string SynthiaLayout::frameName(int index) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06d.png", index);
  return name;
}

void encodeDepthCentimetres(const cv::Mat& depth_m, cv::Mat& out) {
  CV_Assert(depth_m.type() == CV_32FC1);
  out.create(depth_m.size(), CV_16UC3);
  for (int y = 0; y < depth_m.rows; ++y) {
    const float* d = depth_m.ptr<float>(y);
    cv::Vec3w* o = out.ptr<cv::Vec3w>(y);
    for (int x = 0; x < depth_m.cols; ++x) {
      const float z = d[x];
      const uint16_t v =
          (std::isfinite(z) && z > 0.f) ? cv::saturate_cast<uint16_t>(std::lround(z * 100.0)) : 0;
      o[x] = cv::Vec3w(v, v, v);
    }
  }
}

void encodeLabels(const cv::Mat& labels, cv::Mat& out) {
  CV_Assert(labels.type() == CV_8UC1);
  out.create(labels.size(), CV_8UC3);
  for (int y = 0; y < labels.rows; ++y) {
    const uint8_t* l = labels.ptr<uint8_t>(y);
    cv::Vec3b* o = out.ptr<cv::Vec3b>(y);
    for (int x = 0; x < labels.cols; ++x) o[x] = cv::Vec3b(0, 0, l[x]);
  }
}

bool SequenceWriter::open(const std::string& dir, const SceneSettings& settings,
                          const Intrinsics& K, std::string& error) {
  dir_ = dir;
  settings_ = settings;
  K_ = K;
  truth_ = tools::SequenceTruth();
  truth_.has_mount = true;
  truth_.mount = nominalMount(settings);
  std::error_code ec;
  for (const char* sub : {SynthiaLayout::kRgb, SynthiaLayout::kDepth, SynthiaLayout::kLabels,
                          "GT/LANES", "CameraParams"}) {
    fs::create_directories(fs::path(dir) / sub, ec);
    if (ec) {
      error = "cannot create " + (fs::path(dir) / sub).string() + ": " + ec.message();
      return false;
    }
  }
  fs::remove(fs::path(dir) / SynthiaLayout::kScenario, ec);
  // frames of an earlier, longer run would be read as part of this sequence
  for (const char* sub : {SynthiaLayout::kRgb, SynthiaLayout::kDepth, SynthiaLayout::kLabels}) {
    for (const auto& entry : fs::directory_iterator(fs::path(dir) / sub, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.size() == 10 && name.compare(6, 4, ".png") == 0 &&
          name.find_first_not_of("0123456789") == 6)
        fs::remove(entry.path(), ec);
    }
  }
  return true;
}

bool SequenceWriter::write(int index, const RenderedFrame& frame, const tools::FrameTruth& truth,
                           std::string& error) {
  const std::string name = SynthiaLayout::frameName(index);
  const fs::path root(dir_);
  encodeDepthCentimetres(frame.depth, depth_buf_);
  encodeLabels(frame.labels, label_buf_);
  try {
    // OpenCV's default PNG settings are its fast ones (SUB filter, zlib level 1, RLE): twice as
    // fast as an explicit level 1, which leaves libpng's adaptive filtering on (lossless either way)
    if (!cv::imwrite((root / SynthiaLayout::kRgb / name).string(), frame.bgr) ||
        !cv::imwrite((root / SynthiaLayout::kDepth / name).string(), depth_buf_) ||
        !cv::imwrite((root / SynthiaLayout::kLabels / name).string(), label_buf_)) {
      error = "cannot write frame " + name + " under " + dir_;
      return false;
    }
  } catch (const cv::Exception& e) {
    error = "cannot write frame " + name + ": " + e.what();
    return false;
  }
  truth_.frames.push_back(truth);
  return true;
}

bool SequenceWriter::finish(std::string& error) {
  const fs::path root(dir_);
  if (!tools::writeGroundTruth((root / SynthiaLayout::kLanes).string(), truth_, error))
    return false;
  {
    std::ofstream f(root / SynthiaLayout::kIntrinsics);
    f.precision(10);
    f << K_.fx << "\n" << K_.cx << "\n" << K_.cy << "\n" << settings_.baseline << "\n";
    if (!f) {
      error = "cannot write " + (root / SynthiaLayout::kIntrinsics).string();
      return false;
    }
  }
  std::ofstream f(root / SynthiaLayout::kScenario);
  f << settingsToJson(settings_);
  if (!f) {
    error = "cannot write " + (root / SynthiaLayout::kScenario).string();
    return false;
  }
  return true;
}

bool sequenceUpToDate(const std::string& dir, const SceneSettings& settings) {
  const fs::path root(dir);
  std::ifstream f(root / SynthiaLayout::kScenario);
  if (!f) return false;
  std::stringstream text;
  text << f.rdbuf();
  if (text.str() != settingsToJson(settings)) return false;
  std::error_code ec;
  if (!fs::exists(root / SynthiaLayout::kLanes, ec)) return false;
  for (int i = 0; i < settings.frames; ++i) {
    const std::string name = SynthiaLayout::frameName(i);
    for (const char* sub : {SynthiaLayout::kRgb, SynthiaLayout::kDepth, SynthiaLayout::kLabels})
      if (!fs::exists(root / sub / name, ec)) return false;
  }
  return true;
}

}  // namespace synth
}  // namespace rgbd_lane_detector
