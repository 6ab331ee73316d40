#include "rgbd_lane_detector_tools/ground_truth.h"

#include <cmath>

#include <opencv2/core.hpp>

namespace rgbd_lane_detector {
namespace tools {
namespace {

void writeLine(cv::FileStorage& fs, const char* name, const std::vector<Eigen::Vector3d>& line) {
  fs << name << "[";
  for (const auto& p : line) {
    // float precision (micrometres) keeps the file small
    fs << "[" << static_cast<float>(p.x()) << static_cast<float>(p.y()) << static_cast<float>(p.z())
       << "]";
  }
  fs << "]";
}

bool readVector(const cv::FileNode& n, Eigen::Vector3d& v) {
  if (!n.isSeq() || n.size() != 3) return false;
  for (int i = 0; i < 3; ++i) {
    if (!n[i].isReal() && !n[i].isInt()) return false;
    v[i] = static_cast<double>(n[i]);
  }
  return v.allFinite();
}

bool readLine(const cv::FileNode& n, std::vector<Eigen::Vector3d>& line) {
  line.clear();
  if (n.empty() || n.isNone()) return true;
  if (!n.isSeq()) return false;
  line.reserve(n.size());
  for (const auto& item : n) {
    Eigen::Vector3d p;
    if (!readVector(item, p)) return false;
    line.push_back(p);
  }
  return true;
}

}  // namespace

const FrameTruth* SequenceTruth::find(int index) const {
  // frames are usually stored in index order: try the direct slot first
  if (index >= 0 && index < static_cast<int>(frames.size()) && frames[index].index == index)
    return &frames[index];
  for (const auto& f : frames)
    if (f.index == index) return &f;
  return nullptr;
}

bool writeGroundTruth(const std::string& path, const SequenceTruth& truth, std::string& error) {
  try {
    cv::FileStorage fs(path, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_JSON);
    if (!fs.isOpened()) {
      error = "cannot write " + path;
      return false;
    }
    fs << "frames"
       << "[";
    for (const auto& f : truth.frames) {
      fs << "{";
      fs << "index" << f.index;
      fs << "plane_normal"
         << "[" << f.normal.x() << f.normal.y() << f.normal.z() << "]";
      fs << "plane_distance" << f.distance;
      fs << "has_lane" << static_cast<int>(f.has_lane);
      writeLine(fs, "left", f.left);
      writeLine(fs, "right", f.right);
      fs << "}";
    }
    fs << "]";
  } catch (const cv::Exception& e) {
    error = "cannot write " + path + ": " + e.what();
    return false;
  }
  return true;
}

bool readGroundTruth(const std::string& path, SequenceTruth& truth, std::string& error) {
  truth.frames.clear();
  try {
    cv::FileStorage fs(path, cv::FileStorage::READ);
    if (!fs.isOpened()) {
      error = "cannot open ground truth " + path;
      return false;
    }
    const cv::FileNode frames = fs["frames"];
    if (!frames.isSeq()) {
      error = path + ": no \"frames\" list";
      return false;
    }
    truth.frames.reserve(frames.size());
    for (const auto& n : frames) {
      FrameTruth f;
      f.index = static_cast<int>(n["index"]);
      f.distance = static_cast<double>(n["plane_distance"]);
      f.has_lane = static_cast<int>(n["has_lane"]) != 0;
      if (!readVector(n["plane_normal"], f.normal) || !std::isfinite(f.distance) ||
          std::fabs(f.normal.norm() - 1.0) > 1e-3 || !readLine(n["left"], f.left) ||
          !readLine(n["right"], f.right)) {
        error = path + ": malformed frame " + std::to_string(truth.frames.size());
        truth.frames.clear();
        return false;
      }
      truth.frames.push_back(std::move(f));
    }
  } catch (const cv::Exception& e) {
    error = "cannot parse ground truth " + path + ": " + e.what();
    return false;
  }
  return true;
}

}  // namespace tools
}  // namespace rgbd_lane_detector
