#include "rgbd_lane_detector_tools/ground_truth.h"

#include <cmath>
#include <cstdio>
#include <fstream>

#include <opencv2/core.hpp>

namespace rgbd_lane_detector {
namespace tools {
namespace {

constexpr int kFormat = 2;

// Names in the file, indexed by the enum value.
const char* const kLabelNames[] = {"ego_left",  "ego_right",      "next_left",
                                   "next_right", "road_edge_left", "road_edge_right"};
const char* const kStyleNames[] = {"unknown", "solid", "dashed", "double_solid", "road_edge"};
const char* const kColourNames[] = {"unknown", "none", "white", "yellow"};
const char* const kEdgeNames[] = {"none", "kerb", "rails", "asphalt_edge", "shoulder_edge"};
const char* const kKindNames[] = {"paint", "road_edge"};

template <typename E, size_t N>
const char* nameOf(E value, const char* const (&names)[N]) {
  const size_t i = static_cast<size_t>(value);
  return i < N ? names[i] : "?";
}

template <typename E, size_t N>
bool parseName(const cv::FileNode& n, const char* const (&names)[N], E& out) {
  if (!n.isString()) return false;
  const std::string text = static_cast<std::string>(n);
  for (size_t i = 0; i < N; ++i) {
    if (text == names[i]) {
      out = static_cast<E>(i);
      return true;
    }
  }
  return false;
}

// Compact JSON (cv::FileStorage would put every number on its own line): one frame per few
// lines, points at 0.1 mm.
void writeNumber(std::ostream& out, double v, const char* format) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), format, v);
  out << buf;
}

void writeLine(std::ostream& out, const std::vector<Eigen::Vector3d>& line) {
  out << "[";
  for (size_t i = 0; i < line.size(); ++i) {
    out << (i ? ",[" : "[");
    for (int c = 0; c < 3; ++c) {
      if (c) out << ",";
      writeNumber(out, line[i][c] == 0.0 ? 0.0 : line[i][c], "%.4f");
    }
    out << "]";
  }
  out << "]";
}

void writeTransform(std::ostream& out, const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  const Eigen::Vector3d t = T.translation();
  out << "{\"translation\": [";
  for (int c = 0; c < 3; ++c) {
    if (c) out << ", ";
    writeNumber(out, t[c], "%.17g");
  }
  out << "], \"rotation\": [";
  const double r[4] = {q.x(), q.y(), q.z(), q.w()};
  for (int c = 0; c < 4; ++c) {
    if (c) out << ", ";
    writeNumber(out, r[c], "%.17g");
  }
  out << "]}";
}

bool readNumbers(const cv::FileNode& n, double* out, int count) {
  if (!n.isSeq() || static_cast<int>(n.size()) != count) return false;
  for (int i = 0; i < count; ++i) {
    if (!n[i].isReal() && !n[i].isInt()) return false;
    out[i] = static_cast<double>(n[i]);
    if (!std::isfinite(out[i])) return false;
  }
  return true;
}

bool readVector(const cv::FileNode& n, Eigen::Vector3d& v) {
  return readNumbers(n, v.data(), 3);
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

bool readTransform(const cv::FileNode& n, Eigen::Isometry3d& T) {
  if (!n.isMap()) return false;
  Eigen::Vector3d t;
  double q[4];
  if (!readVector(n["translation"], t) || !readNumbers(n["rotation"], q, 4)) return false;
  const Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);
  if (std::fabs(quat.norm() - 1.0) > 1e-3) return false;
  T = Eigen::Isometry3d::Identity();
  T.linear() = quat.normalized().toRotationMatrix();
  T.translation() = t;
  return true;
}

bool readBoundary(const cv::FileNode& n, TrueBoundary& b) {
  return n.isMap() && parseName(n["label"], kLabelNames, b.label) &&
         parseName(n["kind"], kKindNames, b.kind) && parseName(n["style"], kStyleNames, b.style) &&
         parseName(n["colour"], kColourNames, b.colour) &&
         parseName(n["edge"], kEdgeNames, b.edge) && readLine(n["points"], b.points) &&
         !b.points.empty();
}

// Format 1: the ego lines were paint of unknown style and colour.
void legacyBoundaries(FrameTruth& f) {
  f.boundaries.clear();
  for (const bool left : {true, false}) {
    const auto& line = left ? f.left : f.right;
    if (line.empty()) continue;
    TrueBoundary b;
    b.label = left ? BoundaryLabel::kEgoLeft : BoundaryLabel::kEgoRight;
    b.points = line;
    f.boundaries.push_back(b);
  }
}

bool readFrame(const cv::FileNode& n, int format, FrameTruth& f) {
  f.index = static_cast<int>(n["index"]);
  f.distance = static_cast<double>(n["plane_distance"]);
  f.has_lane = static_cast<int>(n["has_lane"]) != 0;
  if (!readVector(n["plane_normal"], f.normal) || !std::isfinite(f.distance) ||
      std::fabs(f.normal.norm() - 1.0) > 1e-3 || !readLine(n["left"], f.left) ||
      !readLine(n["right"], f.right))
    return false;
  if (format < 2) {
    legacyBoundaries(f);
    return true;
  }
  f.plane_rms = static_cast<double>(n["plane_rms"]);
  f.lane_optional = static_cast<int>(n["lane_optional"]) != 0;
  const cv::FileNode list = n["boundaries"];
  if (!list.isSeq()) return false;
  bool seen[kNumBoundaryLabels] = {};
  for (const auto& item : list) {
    TrueBoundary b;
    if (!readBoundary(item, b) || seen[static_cast<int>(b.label)]) return false;
    seen[static_cast<int>(b.label)] = true;
    f.boundaries.push_back(std::move(b));
  }
  f.syncEgoLines();
  const cv::FileNode lane = n["lane"];
  f.has_vehicle_frame = !n["base_to_camera"].empty();
  if (f.has_vehicle_frame) {
    if (!readTransform(n["base_to_camera"], f.base_to_camera) || !lane.isMap()) return false;
    f.lane.valid = static_cast<int>(lane["valid"]) != 0;
    f.lane.width = static_cast<double>(lane["width"]);
    f.lane.offset = static_cast<double>(lane["offset"]);
    f.lane.heading = static_cast<double>(lane["heading"]);
    f.lane.curvature = static_cast<double>(lane["curvature"]);
    for (auto& b : f.boundaries) {
      b.points_base.clear();
      for (const auto& p : b.points) b.points_base.push_back(f.base_to_camera * p);
    }
  }
  return std::isfinite(f.plane_rms) && std::isfinite(f.lane.width) &&
         std::isfinite(f.lane.offset) && std::isfinite(f.lane.heading) &&
         std::isfinite(f.lane.curvature);
}

}  // namespace

const char* boundaryLabelName(BoundaryLabel label) {
  return nameOf(label, kLabelNames);
}
const char* lineStyleName(LineStyle style) {
  return nameOf(style, kStyleNames);
}
const char* lineColourName(LineColour colour) {
  return nameOf(colour, kColourNames);
}
const char* edgeTypeName(EdgeType edge) {
  return nameOf(edge, kEdgeNames);
}
const char* sideKindName(const TrueBoundary* side) {
  return side ? boundaryKindName(side->kind) : "none";
}

const TrueBoundary* FrameTruth::boundary(BoundaryLabel label) const {
  for (const auto& b : boundaries)
    if (b.label == label) return &b;
  return nullptr;
}

void FrameTruth::syncEgoLines() {
  const TrueBoundary* l = egoSide(true);
  const TrueBoundary* r = egoSide(false);
  left = l ? l->points : std::vector<Eigen::Vector3d>();
  right = r ? r->points : std::vector<Eigen::Vector3d>();
  has_lane = l || r;
}

const FrameTruth* SequenceTruth::find(int index) const {
  // frames are usually stored in index order: try the direct slot first
  if (index >= 0 && index < static_cast<int>(frames.size()) && frames[index].index == index)
    return &frames[index];
  for (const auto& f : frames)
    if (f.index == index) return &f;
  return nullptr;
}

bool writeGroundTruth(const std::string& path, const SequenceTruth& truth, std::string& error) {
  std::ofstream out(path);
  if (!out) {
    error = "cannot write " + path;
    return false;
  }
  const auto number = [&out](double v) { writeNumber(out, v, "%.17g"); };
  out << "{\n\"format\": " << kFormat << ",\n";
  if (truth.has_mount) {
    out << "\"mount\": ";
    writeTransform(out, truth.mount);
    out << ",\n";
  }
  out << "\"frames\": [";
  for (size_t i = 0; i < truth.frames.size(); ++i) {
    const FrameTruth& f = truth.frames[i];
    out << (i ? ",\n" : "\n") << "{\"index\": " << f.index << ", \"plane_normal\": [";
    number(f.normal.x());
    out << ", ";
    number(f.normal.y());
    out << ", ";
    number(f.normal.z());
    out << "], \"plane_distance\": ";
    number(f.distance);
    out << ", \"plane_rms\": ";
    number(f.plane_rms);
    out << ", \"has_lane\": " << static_cast<int>(f.has_lane)
        << ", \"lane_optional\": " << static_cast<int>(f.lane_optional);
    if (f.has_vehicle_frame) {
      out << ",\n \"base_to_camera\": ";
      writeTransform(out, f.base_to_camera);
      out << ",\n \"lane\": {\"valid\": " << static_cast<int>(f.lane.valid) << ", \"width\": ";
      number(f.lane.width);
      out << ", \"offset\": ";
      number(f.lane.offset);
      out << ", \"heading\": ";
      number(f.lane.heading);
      out << ", \"curvature\": ";
      number(f.lane.curvature);
      out << "}";
    }
    out << ",\n \"boundaries\": [";
    for (size_t j = 0; j < f.boundaries.size(); ++j) {
      const TrueBoundary& b = f.boundaries[j];
      out << (j ? ",\n  " : "\n  ") << "{\"label\": \"" << boundaryLabelName(b.label)
          << "\", \"kind\": \"" << boundaryKindName(b.kind) << "\", \"style\": \""
          << lineStyleName(b.style) << "\", \"colour\": \"" << lineColourName(b.colour)
          << "\", \"edge\": \"" << edgeTypeName(b.edge) << "\", \"points\": ";
      writeLine(out, b.points);
      out << "}";
    }
    out << "]}";
  }
  out << "\n]\n}\n";
  out.flush();
  if (!out) {
    error = "cannot write " + path;
    return false;
  }
  return true;
}

bool readGroundTruth(const std::string& path, SequenceTruth& truth, std::string& error) {
  truth = SequenceTruth();
  try {
    cv::FileStorage fs(path, cv::FileStorage::READ);
    if (!fs.isOpened()) {
      error = "cannot open ground truth " + path;
      return false;
    }
    const cv::FileNode format = fs["format"];
    truth.format = format.empty() ? 1 : static_cast<int>(format);
    if (truth.format < 1 || truth.format > kFormat) {
      error = path + ": unknown ground truth format " + std::to_string(truth.format);
      return false;
    }
    truth.has_mount = !fs["mount"].empty();
    if (truth.has_mount && !readTransform(fs["mount"], truth.mount)) {
      error = path + ": malformed \"mount\"";
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
      if (!readFrame(n, truth.format, f)) {
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
