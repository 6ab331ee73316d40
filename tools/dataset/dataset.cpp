#include "rgbd_lane_detector_tools/dataset/dataset.h"
#include "rgbd_lane_detector_tools/plane_check.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <camera_calibration_parsers/parse_ini.h>
#include <camera_calibration_parsers/parse_yml.h>
#include <sensor_msgs/CameraInfo.h>
#include <yaml-cpp/yaml.h>

#include "readers_internal.h"
#include "rgbd_lane_detector/disparity_depth.h"

namespace rgbd_lane_detector {
namespace tools {
namespace fs = std::filesystem;

Frame DatasetFrame::toFrame() const {
  Frame f;
  f.colour = colour;
  f.format = format;
  f.depth = depth;
  f.depth_scale = depth_scale;
  f.intrinsics = intrinsics;
  return f;
}

void DatasetFrame::referenceDepth(cv::Mat& reference, double& scale) const {
  const bool lidar = !lidar_depth.empty();
  reference = lidar ? lidar_depth : depth;
  scale = lidar ? lidar_depth_scale : depth_scale;
}

void DatasetFrame::referenceRoadPoints(std::vector<Eigen::Vector3d>& points) const {
  cv::Mat reference;
  double scale = 1.0;
  referenceDepth(reference, scale);
  regionPoints(reference, scale, intrinsics, roadCheckRegion(reference.size(), intrinsics), 40.0,
               points);
}

bool DatasetFrame::referenceRoadPlane(Eigen::Vector3d& normal, double& distance) const {
  if (has_road_plane) {
    normal = road_plane_normal;
    distance = road_plane_distance;
    return true;
  }
  std::vector<Eigen::Vector3d> points;
  referenceRoadPoints(points);
  return ransacPlane(points, 0.05, normal, distance);
}

std::string detectDatasetType(const std::string& path) {
  std::error_code ec;
  const fs::path p(path);
  if (fs::is_regular_file(p, ec)) return p.extension() == ".bag" ? "bag" : "";
  if (!fs::is_directory(p, ec)) return "";
  if (fs::is_directory(p / "RGB/Stereo_Left/Omni_F", ec)) return "synthia";
  if (fs::is_directory(p / "zed_left", ec) && fs::is_directory(p / "lidar_depth", ec))
    return "stereo_lidar";
  if (fs::exists(p / "associations.txt", ec) ||
      (fs::exists(p / "rgb.txt", ec) && fs::exists(p / "depth.txt", ec)))
    return "tum";
  bool depth_frames = false, stereo_frames = false;
  for (const auto& e : fs::directory_iterator(p, ec)) {
    const std::string n = e.path().filename().string();
    auto ends = [&n](const std::string& s) {
      return n.size() > s.size() && n.compare(n.size() - s.size(), s.size(), s) == 0;
    };
    if (ends("_disparity.png") || ends("_lidar_depth.png")) return "kitti";
    if (ends("_depth.png")) depth_frames = true;
    if (ends("_right.png")) stereo_frames = true;  // a KITTI pair without LiDAR (depth sgbm)
  }
  if (fs::is_directory(p / "image_2", ec) &&
      (fs::is_directory(p / "disp_occ_0", ec) || fs::is_directory(p / "disp_noc_0", ec) ||
       fs::is_directory(p / "image_3", ec)))
    return "kitti";
  if (depth_frames) return "tum_frames";
  if (stereo_frames) return "kitti";
  for (const auto& e : fs::directory_iterator(p, ec))  // a folder of frame folders
    if (e.is_directory(ec) && fs::exists(e.path() / "calib.yaml", ec)) return "streets";
  return "";
}

std::unique_ptr<DatasetReader> openDataset(const DatasetOptions& options, std::string& error) {
  std::error_code ec;
  if (options.path.empty()) {
    error = "no dataset path given";
    return nullptr;
  }
  if (!fs::exists(options.path, ec)) {
    error = "dataset not found: " + options.path;
    return nullptr;
  }
  if (options.depth != "dataset" && options.depth != "sgbm") {
    error = "unknown depth source '" + options.depth + "' (dataset, sgbm)";
    return nullptr;
  }
  std::string type = options.type;
  if (type.empty() || type == "auto") {
    type = detectDatasetType(options.path);
    if (type.empty()) {
      error = "cannot tell the format of " + options.path +
              " (expected a SYNTHIA-SEQS, TUM or KITTI folder, numbered N.png + N_depth.png "
              "frames, a folder of street frame folders (calib.yaml each), a stereo_lidar "
              "sequence (zed_left/, lidar_depth/), or a .bag file); use --type";
      return nullptr;
    }
  }
  if (options.depth == "sgbm" && type != "kitti" && type != "streets" && type != "stereo_lidar") {
    error = "depth sgbm needs a colour stereo pair: a KITTI folder (<id>_left.png + "
            "<id>_right.png, or image_2/ + image_3/), street frames with right.png or a "
            "stereo_lidar sequence, not a " + type + " dataset";
    return nullptr;
  }
  if (type == "synthia") return internal::openSynthia(options, error);
  if (type == "tum") return internal::openTum(options, error);
  if (type == "tum_frames") return internal::openTumFrames(options, error);
  if (type == "kitti") return internal::openKitti(options, error);
  if (type == "streets") return internal::openStreets(options, error);
  if (type == "stereo_lidar") return internal::openStereoLidarSequence(options, error);
  if (type == "bag") return internal::openBag(options, error);
  error = "unknown dataset type '" + type +
          "' (auto, synthia, tum, tum_frames, kitti, streets, stereo_lidar, bag)";
  return nullptr;
}

bool readCameraInfoYaml(const std::string& path, Intrinsics& K, cv::Size* size,
                        std::string& error) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    error = "camera_info file not found: " + path;
    return false;
  }
  // the format by extension, as camera_calibration_parsers::readCalibration() chooses it
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in || (ext != ".yaml" && ext != ".yml" && ext != ".ini")) {
    error = "cannot parse camera_info file " + path;
    return false;
  }
  return parseCameraInfo(text.str(), ext.substr(1), path, K, size, error);
}

namespace {

// camera_calibration_parsers' YAML reader asserts (abort) on a matrix whose rows/cols differ from
// 3x3 (K, R) / 3x4 (P), and sizes D by rows * cols unchecked (int overflow, std::length_error out
// of its YAML::Exception handler). Check those fields first, with the same yaml-cpp reads it
// makes; false: the reader would fail or crash on this text.
bool calibrationYamlReadable(const std::string& text, std::string& problem) {
  try {
    const YAML::Node doc = YAML::Load(text);
    const struct {
      const char* name;
      int rows, cols;
    } matrices[] = {
        {"camera_matrix", 3, 3}, {"rectification_matrix", 3, 3}, {"projection_matrix", 3, 4}};
    for (const auto& m : matrices) {
      const int rows = doc[m.name]["rows"].as<int>(), cols = doc[m.name]["cols"].as<int>();
      if (rows != m.rows || cols != m.cols) {
        problem = std::string(m.name) + " is " + std::to_string(rows) + "x" + std::to_string(cols) +
                  ", expected " + std::to_string(m.rows) + "x" + std::to_string(m.cols);
        return false;
      }
    }
    const YAML::Node d = doc["distortion_coefficients"];
    const long long d_rows = d["rows"].as<int>(), d_cols = d["cols"].as<int>();
    if (d_rows < 0 || d_cols < 0 || d_rows * d_cols > 64) {
      problem = "distortion_coefficients size out of range";
      return false;
    }
  } catch (const YAML::Exception& e) {
    problem = e.what();
    return false;
  }
  return true;
}

}  // namespace

bool parseCameraInfo(const std::string& text, const std::string& format, const std::string& source,
                     Intrinsics& K, cv::Size* size, std::string& error) {
  sensor_msgs::CameraInfo info;
  std::string name;
  // the stream readers of camera_calibration_parsers (its parseCalibration() knows ini only)
  std::istringstream in(text);
  bool parsed = false;
  std::string problem;
  if (format == "yaml" || format == "yml") {
    if (!calibrationYamlReadable(text, problem)) {
      error = "cannot parse camera_info file " + source + ": " + problem;
      return false;
    }
    parsed = camera_calibration_parsers::readCalibrationYml(in, name, info);
  } else if (format == "ini") {
    parsed = camera_calibration_parsers::readCalibrationIni(in, name, info);
  }
  if (!parsed) {
    error = "cannot parse camera_info file " + source;
    return false;
  }
  Intrinsics k;
  if (info.P[0] > 0 && info.P[5] > 0) {
    k = Intrinsics{info.P[0], info.P[5], info.P[2], info.P[6]};
  } else {
    k = Intrinsics{info.K[0], info.K[4], info.K[2], info.K[5]};
  }
  if (!k.valid()) {
    error = "camera_info file " + source + " holds invalid intrinsics";
    return false;
  }
  K = k;
  if (size) *size = cv::Size(static_cast<int>(info.width), static_cast<int>(info.height));
  return true;
}

bool readSynthiaIntrinsics(const std::string& path, Intrinsics& K, double* baseline,
                           std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = "cannot open intrinsics file " + path;
    return false;
  }
  return parseSynthiaIntrinsics(in, path, K, baseline, error);
}

bool parseSynthiaIntrinsics(std::istream& in, const std::string& source, Intrinsics& K,
                            double* baseline, std::string& error) {
  double f, cx, cy, b = std::numeric_limits<double>::quiet_NaN();
  if (!(in >> f >> cx >> cy)) {
    error = "intrinsics file " + source + " must hold f, cx, cy";
    return false;
  }
  in >> b;
  const Intrinsics k{f, f, cx, cy};
  if (!k.valid()) {
    error = "intrinsics file " + source + " holds invalid values";
    return false;
  }
  K = k;
  if (baseline) *baseline = b;
  return true;
}

bool readKittiCalibration(const std::string& path, Intrinsics& K, double& baseline,
                          std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = "cannot open KITTI calibration " + path;
    return false;
  }
  return parseKittiCalibration(in, path, K, baseline, error);
}

bool parseKittiCalibration(std::istream& in, const std::string& source, Intrinsics& K,
                           double& baseline, std::string& error) {
  std::map<std::string, std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::istringstream ss(line.substr(colon + 1));
    std::vector<double> v;
    double x;
    while (ss >> x) v.push_back(x);
    rows[line.substr(0, colon)] = v;
  }
  // raw data (calib_cam_to_cam.txt) or object / odometry format (calib.txt)
  auto p2 = rows.find("P_rect_02"), p3 = rows.find("P_rect_03");
  if (p2 == rows.end() && p3 == rows.end()) {
    p2 = rows.find("P2");
    p3 = rows.find("P3");
  }
  if (p2 == rows.end() || p2->second.size() != 12 || p3 == rows.end() || p3->second.size() != 12) {
    error = "KITTI calibration " + source + " lacks P_rect_02 / P_rect_03 (or P2 / P3)";
    return false;
  }
  const std::vector<double>& a = p2->second;
  const Intrinsics k{a[0], a[5], a[2], a[6]};
  const double b = (a[3] - p3->second[3]) / a[0];  // P(0,3) = -fx * (camera x offset)
  if (!k.valid() || !(b > 0)) {
    error = "KITTI calibration " + source + " holds invalid values";
    return false;
  }
  K = k;
  baseline = b;
  return true;
}

void kittiDisparityToDepth(const cv::Mat& disparity, double fx, double baseline, cv::Mat& depth) {
  CV_Assert(disparity.type() == CV_16UC1);
  disparity.convertTo(depth, CV_32F, 1.0 / 256.0);  // 0 (no data) stays 0: invalid below
  DisparityModel model;
  model.focal = fx;
  model.baseline = baseline;
  model.delta_d = 1.0 / 256.0;
  const char* problem = disparityToDepth(depth, model, depth);  // in place
  CV_Assert(problem == nullptr);
}

namespace internal {

bool applyCameraInfo(const DatasetOptions& o, Intrinsics& K, std::string& error) {
  if (o.camera_info.empty()) return true;
  return readCameraInfoYaml(o.camera_info, K, nullptr, error);
}

}  // namespace internal
}  // namespace tools
}  // namespace rgbd_lane_detector
