// Folder datasets: SYNTHIA-SEQS, TUM RGB-D (associations or rgb/depth lists), numbered TUM
// frames (N.png + N_depth.png), KITTI stereo frames with LiDAR disparity or depth, or with
// depth from their colour stereo pair (StereoSGBM), the street corpus (one folder per frame with
// its own calibration) and RADIATE-style stereo + LiDAR sequences.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <yaml-cpp/yaml.h>

#include "readers_internal.h"

namespace rgbd_lane_detector {
namespace tools {
namespace internal {
namespace {
namespace fs = std::filesystem;

enum class DepthEncoding {
  kUint16,          // the reader's depth scale
  kKittiDisparity,  // KITTI 2015 disparity PNG: value / 256 px, 0 none
  kKittiDepth,      // KITTI depth PNG (projected LiDAR): value / 256 m, 0 none
};

struct FileEntry {
  std::string colour, depth, name;
  int index = 0;
  double stamp = 0.0;
  DepthEncoding encoding = DepthEncoding::kUint16;
  std::string right;  // right colour image of a stereo pair (KITTI), or empty
  // a frame with its own calibration (the street corpus): used instead of the reader's
  bool own_calibration = false;
  Intrinsics K;
  double baseline = 0.0;
  cv::Mat distortion;  // OpenCV k1, k2, p1, p2, k3 of a raw image (undistorted when read), or empty
  bool has_road_plane = false;  // the dataset's own road plane (n up, optical frame)
  Eigen::Vector3d road_normal = Eigen::Vector3d(0.0, -1.0, 0.0);
  double road_distance = 0.0;
};

bool allDigits(const std::string& s) {
  return !s.empty() && s.size() <= 9 && s.find_first_not_of("0123456789") == std::string::npos;
}

/// Reads listed colour/depth file pairs.
class FileSequenceReader : public DatasetReader {
 public:
  FileSequenceReader(const char* kind, std::vector<FileEntry> entries, const DatasetOptions& o,
                     const Intrinsics& K, double scale, double baseline, std::string gt)
      : kind_(kind), K_(K), scale_(scale), baseline_(baseline), gt_(std::move(gt)) {
    if (o.depth == "sgbm") stereo_ = std::make_unique<StereoMatcher>(o.sgbm);
    const int step = std::max(1, o.step);
    for (size_t i = std::max(0, o.first); i < entries.size(); i += step) {
      if (o.max_frames >= 0 && static_cast<int>(entries_.size()) >= o.max_frames) break;
      entries_.push_back(entries[i]);
    }
  }
  const char* kind() const override { return kind_; }
  int size() const override { return static_cast<int>(entries_.size()); }
  std::string groundTruthPath() const override { return gt_; }
  bool independentFrames() const override {
    const std::string k = kind_;
    return k == "kitti" || k == "tum_frames" || k == "streets";
  }

  bool next(DatasetFrame& f) override {
    if (pos_ >= entries_.size()) return false;
    const FileEntry& e = entries_[pos_++];
    const Intrinsics& K = e.own_calibration ? e.K : K_;
    const double baseline = e.own_calibration ? e.baseline : baseline_;
    try {
      f.colour = cv::imread(e.colour, cv::IMREAD_COLOR);
      if (f.colour.empty()) return fail("cannot read colour image " + e.colour);
      f.lidar_depth.release();
      if (!e.depth.empty() && !readDepth(e, K, baseline, f)) return false;
      if (stereo_) {
        const cv::Mat right = cv::imread(e.right, cv::IMREAD_COLOR);
        if (right.empty()) return fail("cannot read right image " + e.right);
        f.depth = cv::Mat();  // a new image: f.depth may share the LiDAR depth's pixels
        if (const char* problem = stereo_->depth(f.colour, right, K.fx, baseline, f.depth))
          return fail(std::string(problem) + ": " + e.colour + " / " + e.right);
        f.depth_scale = 1.0;
        f.depth_source = "sgbm";
      }
    } catch (const cv::Exception& ex) {
      return fail("cannot decode " + e.colour + ": " + ex.what());
    }
    if (f.colour.size() != f.depth.size())
      return fail("colour and depth differ in size: " + e.colour + " / " + e.depth);
    if (!f.lidar_depth.empty() && f.lidar_depth.size() != f.colour.size())
      return fail("colour and LiDAR depth differ in size: " + e.colour + " / " + e.depth);
    f.distortion = e.distortion;
    f.has_road_plane = e.has_road_plane;
    f.road_plane_normal = e.road_normal;
    f.road_plane_distance = e.road_distance;
    if (!e.distortion.empty()) undistortFrame(K, f);
    f.baseline = baseline;
    f.format = PixelFormat::kBgr8;
    f.intrinsics = K;
    f.index = e.index;
    f.name = e.name;
    f.stamp = e.stamp;
    return true;
  }

 private:
  // A raw image and the depth projected through its distortion, undistorted once to the
  // pinhole @p K (the detector reads rectified images): colour bilinear, depth nearest (the Z
  // of a point does not change; no depth is blended across an edge).
  static void undistortFrame(const Intrinsics& K, DatasetFrame& f) {
    const cv::Matx33d k(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1);
    cv::Mat map1, map2;
    cv::initUndistortRectifyMap(k, f.distortion, cv::noArray(), k, f.colour.size(), CV_32FC1,
                                map1, map2);
    auto undistortDepth = [&](cv::Mat& d) {
      cv::Mat out;
      cv::remap(d, out, map1, map2, cv::INTER_NEAREST, cv::BORDER_CONSTANT,
                cv::Scalar::all(d.depth() == CV_32F ? std::nan("") : 0.0));
      d = out;
    };
    cv::Mat colour;
    cv::remap(f.colour, colour, map1, map2, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    f.colour = colour;
    const bool shared = f.lidar_depth.data == f.depth.data;
    undistortDepth(f.depth);
    if (shared) f.lidar_depth = f.depth;
    else if (!f.lidar_depth.empty()) undistortDepth(f.lidar_depth);
  }

  // The entry's depth file into f.depth (and f.lidar_depth for KITTI's LiDAR).
  bool readDepth(const FileEntry& e, const Intrinsics& K, double baseline, DatasetFrame& f) {
    cv::Mat raw = cv::imread(e.depth, cv::IMREAD_UNCHANGED);
    if (raw.empty()) return fail("cannot read depth image " + e.depth);
    if (raw.depth() != CV_16U) return fail("depth image is not 16-bit: " + e.depth);
    if (raw.channels() > 1) cv::extractChannel(raw, raw, 0);  // SYNTHIA: same value in 3
    switch (e.encoding) {
      case DepthEncoding::kKittiDisparity:
        kittiDisparityToDepth(raw, K.fx, baseline, f.depth);
        f.depth_scale = 1.0;
        break;
      case DepthEncoding::kKittiDepth:
        f.depth = raw;
        f.depth_scale = 1.0 / 256.0;
        break;
      case DepthEncoding::kUint16:
        f.depth = raw;
        f.depth_scale = scale_;
        f.depth_source = "sensor";
        return true;
    }
    f.lidar_depth = f.depth;
    f.lidar_depth_scale = f.depth_scale;
    f.depth_source = "lidar";
    return true;
  }
  bool fail(const std::string& m) {
    error_ = m;
    pos_ = entries_.size();
    return false;
  }
  const char* kind_;
  std::vector<FileEntry> entries_;
  size_t pos_ = 0;
  Intrinsics K_;
  double scale_;
  double baseline_;
  std::string gt_;
  std::unique_ptr<StereoMatcher> stereo_;  // depth from the stereo pair (depth = "sgbm")
};

std::vector<fs::path> listFiles(const fs::path& dir, const std::string& suffix) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string n = e.path().filename().string();
    if (e.is_regular_file(ec) && n.size() > suffix.size() &&
        n.compare(n.size() - suffix.size(), suffix.size(), suffix) == 0)
      out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Numbered frames sort numerically ("2" before "10").
void sortEntries(std::vector<FileEntry>& entries) {
  std::stable_sort(entries.begin(), entries.end(), [](const FileEntry& a, const FileEntry& b) {
    const bool da = allDigits(a.name), db = allDigits(b.name);
    if (da && db) return std::stoll(a.name) < std::stoll(b.name);
    return a.name < b.name;
  });
}

double sequenceFps(const fs::path& root) {
  cv::FileStorage f;
  try {
    if (f.open((root / "scenario.json").string(), cv::FileStorage::READ)) {
      const double fps = static_cast<double>(f["fps"]);
      if (fps > 0 && std::isfinite(fps)) return fps;
    }
  } catch (const cv::Exception&) {
  }
  return 10.0;
}

bool readTumList(const fs::path& file, TumList& list, std::string& error) {
  std::ifstream in(file);
  if (!in) {
    error = "cannot open " + file.string();
    return false;
  }
  parseTumList(in, list);
  return true;
}

}  // namespace

std::unique_ptr<DatasetReader> openSynthia(const DatasetOptions& o, std::string& error) {
  const fs::path root(o.path);
  const fs::path rgb = root / "RGB/Stereo_Left/Omni_F", depth = root / "Depth/Stereo_Left/Omni_F";
  std::vector<FileEntry> entries;
  const double fps = sequenceFps(root);
  std::error_code ec;
  for (const auto& p : listFiles(rgb, ".png")) {
    FileEntry e;
    e.colour = p.string();
    e.depth = (depth / p.filename()).string();
    e.name = p.stem().string();
    if (!fs::exists(e.depth, ec)) {
      error = "SYNTHIA folder " + o.path + ": no depth image for " + e.colour;
      return nullptr;
    }
    entries.push_back(e);
  }
  if (entries.empty()) {
    error = "SYNTHIA folder " + o.path + ": no frames in " + rgb.string();
    return nullptr;
  }
  sortEntries(entries);
  for (size_t i = 0; i < entries.size(); ++i) {
    entries[i].index =
        allDigits(entries[i].name) ? std::stoi(entries[i].name) : static_cast<int>(i);
    entries[i].stamp = entries[i].index / fps;
  }
  Intrinsics K;
  if (o.camera_info.empty()) {
    if (!readSynthiaIntrinsics((root / "CameraParams/intrinsics.txt").string(), K, nullptr, error))
      return nullptr;
  } else if (!applyCameraInfo(o, K, error)) {
    return nullptr;
  }
  const fs::path gt = root / "GT/LANES/ground_truth.json";
  return std::make_unique<FileSequenceReader>(
      "synthia", entries, o, K, o.depth_scale > 0 ? o.depth_scale : 0.01, 0.0,
      fs::exists(gt, ec) ? gt.string() : std::string());
}

std::unique_ptr<DatasetReader> openTum(const DatasetOptions& o, std::string& error) {
  const fs::path root(o.path);
  std::vector<FileEntry> entries;
  std::error_code ec;
  std::vector<TumPair> pairs;
  if (fs::exists(root / "associations.txt", ec)) {
    std::ifstream in(root / "associations.txt");
    parseTumAssociations(in, pairs);
  } else {
    TumList rgb, depth;
    if (!readTumList(root / "rgb.txt", rgb, error) ||
        !readTumList(root / "depth.txt", depth, error))
      return nullptr;
    associateTumLists(rgb, depth, o.sync_tolerance, pairs);
  }
  for (const TumPair& p : pairs) {
    FileEntry e;
    e.colour = (root / p.colour).string();
    e.depth = (root / p.depth).string();
    e.stamp = p.stamp;
    entries.push_back(e);
  }
  if (entries.empty()) {
    error = "TUM folder " + o.path + ": no associated colour/depth pairs";
    return nullptr;
  }
  for (size_t i = 0; i < entries.size(); ++i) {
    entries[i].index = static_cast<int>(i);
    entries[i].name = fs::path(entries[i].colour).stem().string();
  }
  Intrinsics K{517.3, 516.5, 318.6, 255.3};  // TUM freiburg1 (ROS default set)
  if (!applyCameraInfo(o, K, error)) return nullptr;
  return std::make_unique<FileSequenceReader>("tum", entries, o, K,
                                              o.depth_scale > 0 ? o.depth_scale : 1.0 / 5000.0,
                                              0.0, std::string());
}

std::unique_ptr<DatasetReader> openTumFrames(const DatasetOptions& o, std::string& error) {
  const fs::path root(o.path);
  std::vector<FileEntry> entries;
  for (const auto& p : listFiles(root, "_depth.png")) {
    const std::string stem = p.filename().string().substr(0, p.filename().string().size() - 10);
    const fs::path colour = root / (stem + ".png");
    std::error_code ec;
    if (!fs::exists(colour, ec)) continue;
    FileEntry e;
    e.colour = colour.string();
    e.depth = p.string();
    e.name = stem;
    entries.push_back(e);
  }
  if (entries.empty()) {
    error = "frame folder " + o.path + ": no N.png + N_depth.png pairs";
    return nullptr;
  }
  sortEntries(entries);
  for (size_t i = 0; i < entries.size(); ++i) {
    entries[i].index =
        allDigits(entries[i].name) ? std::stoi(entries[i].name) : static_cast<int>(i);
    entries[i].stamp = i / 30.0;
  }
  Intrinsics K{520.9, 521.0, 325.1, 249.7};  // TUM office frames of ../shared/realdata
  if (!applyCameraInfo(o, K, error)) return nullptr;
  if (o.camera_info.empty() || o.depth_scale <= 0)  // another camera's frames would be misread
    std::fprintf(stderr,
                 "frame folder %s: %s%s%s\n", o.path.c_str(),
                 o.camera_info.empty() ? "no --camera-info: the TUM office camera (640x480, fx "
                                         "520.9, fy 521.0, cx 325.1, cy 249.7) is assumed"
                                       : "",
                 o.camera_info.empty() && o.depth_scale <= 0 ? "; " : "",
                 o.depth_scale <= 0 ? "no --depth-scale: depth PNG value / 5000 m (TUM) is "
                                      "assumed (0.001 for millimetres)"
                                    : "");
  return std::make_unique<FileSequenceReader>("tum_frames", entries, o, K,
                                              o.depth_scale > 0 ? o.depth_scale : 1.0 / 5000.0,
                                              0.0, std::string());
}

std::unique_ptr<DatasetReader> openKitti(const DatasetOptions& o, std::string& error) {
  const fs::path root(o.path);
  const bool sgbm = o.depth == "sgbm";
  std::vector<FileEntry> entries;
  std::error_code ec;
  auto existing = [&ec](const fs::path& p) { return fs::exists(p, ec) ? p.string() : ""; };
  // ../shared/realdata layout: <id>_left.png, <id>_right.png, and the LiDAR as
  // <id>_disparity.png (KITTI 2015) or <id>_lidar_depth.png (projected scan)
  for (const auto& p : listFiles(root, "_left.png")) {
    const std::string n = p.filename().string();
    const std::string id = n.substr(0, n.size() - 9);
    FileEntry e;
    e.colour = p.string();
    e.name = id;
    e.right = existing(root / (id + "_right.png"));
    e.depth = existing(root / (id + "_disparity.png"));
    e.encoding = DepthEncoding::kKittiDisparity;
    if (e.depth.empty()) {
      e.depth = existing(root / (id + "_lidar_depth.png"));
      e.encoding = DepthEncoding::kKittiDepth;
    }
    if (sgbm ? !e.right.empty() : !e.depth.empty()) entries.push_back(e);
  }
  for (const char* disp : {"disp_occ_0", "disp_noc_0"}) {  // KITTI 2015 training layout
    if (!entries.empty()) break;
    for (const auto& p : listFiles(root / "image_2", ".png")) {
      FileEntry e;
      e.colour = p.string();
      e.name = p.stem().string();
      e.right = existing(root / "image_3" / p.filename());
      e.depth = existing(root / disp / p.filename());
      e.encoding = DepthEncoding::kKittiDisparity;
      if (sgbm ? !e.right.empty() : !e.depth.empty()) entries.push_back(e);
    }
  }
  if (entries.empty()) {
    error = "KITTI folder " + o.path +
            (sgbm ? ": no <id>_left.png + <id>_right.png pairs (or image_2/ + image_3/)"
                  : ": no <id>_left.png + <id>_disparity.png or <id>_lidar_depth.png pairs "
                    "(or image_2/ + disp_occ_0/)");
    return nullptr;
  }
  sortEntries(entries);
  for (size_t i = 0; i < entries.size(); ++i) {
    entries[i].index = static_cast<int>(i);
    entries[i].stamp = i / 10.0;
  }
  // P_rect_02 of the 2011-09-26 calibration (../shared/realdata/README.md)
  Intrinsics K{721.5377, 721.5377, 609.5593, 172.854};
  double baseline = 0.53273;
  for (const char* name : {"calib_cam_to_cam.txt", "calib.txt"}) {
    const fs::path calib = root / name;
    if (!fs::exists(calib, ec)) continue;
    if (!readKittiCalibration(calib.string(), K, baseline, error)) return nullptr;
    break;
  }
  if (!applyCameraInfo(o, K, error)) return nullptr;
  return std::make_unique<FileSequenceReader>("kitti", entries, o, K, 1.0, baseline,
                                              std::string());
}

std::unique_ptr<DatasetReader> openStreets(const DatasetOptions& o, std::string& error) {
  // ../shared/realdata/streets: one folder per frame, each with image.png or image.jpg,
  // depth.png (uint16, value / 256 m, 0 none: LiDAR projected into the image), calib.yaml (its
  // own intrinsics, the distortion of a raw image, the baseline of a stereo rig) and, for a
  // stereo rig, right.png
  const fs::path root(o.path);
  const bool sgbm = o.depth == "sgbm";
  std::vector<FileEntry> entries;
  std::error_code ec;
  std::vector<fs::path> folders;
  for (const auto& d : fs::directory_iterator(root, ec))
    if (d.is_directory(ec) && fs::exists(d.path() / "calib.yaml", ec)) folders.push_back(d.path());
  std::sort(folders.begin(), folders.end());
  for (const fs::path& dir : folders) {
    FileEntry e;
    e.name = dir.filename().string();
    for (const char* n : {"image.png", "image.jpg"})
      if (fs::exists(dir / n, ec)) e.colour = (dir / n).string();
    e.depth = fs::exists(dir / "depth.png", ec) ? (dir / "depth.png").string() : "";
    e.right = fs::exists(dir / "right.png", ec) ? (dir / "right.png").string() : "";
    e.encoding = DepthEncoding::kKittiDepth;
    if (e.colour.empty() || e.depth.empty() || (sgbm && e.right.empty())) continue;
    try {
      const YAML::Node c = YAML::LoadFile((dir / "calib.yaml").string());
      e.K = Intrinsics{c["fx"].as<double>(), c["fy"].as<double>(), c["cx"].as<double>(),
                       c["cy"].as<double>()};
      e.baseline = c["baseline_m"] ? c["baseline_m"].as<double>() : 0.0;
      // distortion terms given (a raw image); "rectified: unknown" without terms is a pinhole
      if (c["distortion"] && c["distortion"]["D"]) {
        const auto D = c["distortion"]["D"].as<std::vector<double>>();
        if (std::any_of(D.begin(), D.end(), [](double v) { return v != 0.0; }))
          e.distortion = cv::Mat(D, true).reshape(1, 1);
      }
      if (c["road_plane"] && c["road_plane"]["n"] && c["road_plane"]["d"]) {
        const auto n = c["road_plane"]["n"].as<std::vector<double>>();
        if (n.size() == 3) {
          e.road_normal = Eigen::Vector3d(n[0], n[1], n[2]).normalized();
          e.road_distance = c["road_plane"]["d"].as<double>();
          e.has_road_plane = e.road_normal.allFinite() && std::isfinite(e.road_distance);
        }
      }
    } catch (const YAML::Exception& ex) {
      error = "street folder " + dir.string() + ": unreadable calib.yaml: " + ex.what();
      return nullptr;
    }
    if (!e.K.valid()) {
      error = "street folder " + dir.string() + ": calib.yaml has no valid fx, fy, cx, cy";
      return nullptr;
    }
    e.own_calibration = true;
    entries.push_back(e);
  }
  if (entries.empty()) {
    error = "street corpus " + o.path +
            (sgbm ? ": no frame folder with image, depth.png, right.png and calib.yaml"
                  : ": no frame folder with image.png/jpg, depth.png and calib.yaml");
    return nullptr;
  }
  for (size_t i = 0; i < entries.size(); ++i) {
    entries[i].index = static_cast<int>(i);
    entries[i].stamp = static_cast<double>(i);
  }
  return std::make_unique<FileSequenceReader>("streets", entries, o, Intrinsics(), 1.0, 0.0,
                                              std::string());
}

std::unique_ptr<DatasetReader> openStereoLidarSequence(const DatasetOptions& o,
                                                       std::string& error) {
  // RADIATE-style sequence: zed_left/NNNNNN.png, zed_right/NNNNNN.png (rectified),
  // lidar_depth/NNNNNN.png (value / 256 m, 0 none), rectification.yaml (P1, P2) and the camera
  // stamps in frame_to_lidar.txt (so the frames run at their own rate)
  const fs::path root(o.path);
  const bool sgbm = o.depth == "sgbm";
  cv::Mat P1, P2;
  try {
    cv::FileStorage fs((root / "rectification.yaml").string(), cv::FileStorage::READ);
    if (fs.isOpened()) {
      fs["P1"] >> P1;
      fs["P2"] >> P2;
    }
  } catch (const cv::Exception&) {
  }
  if (P1.rows != 3 || P1.cols != 4 || P2.rows != 3 || P2.cols != 4) {
    error = "stereo sequence " + o.path + ": rectification.yaml has no 3x4 P1 and P2";
    return nullptr;
  }
  P1.convertTo(P1, CV_64F);
  P2.convertTo(P2, CV_64F);
  const Intrinsics K{P1.at<double>(0, 0), P1.at<double>(1, 1), P1.at<double>(0, 2),
                     P1.at<double>(1, 2)};
  const double baseline = -P2.at<double>(0, 3) / P2.at<double>(0, 0);
  std::map<std::string, double> stamps;
  {
    std::ifstream in(root / "frame_to_lidar.txt");
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream ss(line);
      std::string name;
      double t;
      if (ss >> name >> t) stamps[name] = t;
    }
  }
  std::vector<FileEntry> entries;
  std::error_code ec;
  for (const auto& p : listFiles(root / "zed_left", ".png")) {
    FileEntry e;
    e.colour = p.string();
    e.name = p.stem().string();
    e.depth = (root / "lidar_depth" / p.filename()).string();
    e.right = (root / "zed_right" / p.filename()).string();
    e.encoding = DepthEncoding::kKittiDepth;
    if (!fs::exists(e.depth, ec) || (sgbm && !fs::exists(e.right, ec))) continue;
    entries.push_back(e);
  }
  if (entries.empty()) {
    error = "stereo sequence " + o.path + ": no zed_left/N.png with lidar_depth/N.png";
    return nullptr;
  }
  sortEntries(entries);
  const double fps = 15.0;  // when frame_to_lidar.txt does not give the stamps
  const double t0 = stamps.count(entries[0].name) ? stamps[entries[0].name] : 0.0;
  for (size_t i = 0; i < entries.size(); ++i) {
    entries[i].index =
        allDigits(entries[i].name) ? std::stoi(entries[i].name) : static_cast<int>(i);
    const auto it = stamps.find(entries[i].name);
    entries[i].stamp = it != stamps.end() ? it->second - t0 : i / fps;
  }
  Intrinsics Ko = K;
  if (!applyCameraInfo(o, Ko, error)) return nullptr;
  return std::make_unique<FileSequenceReader>("stereo_lidar", entries, o, Ko, 1.0, baseline,
                                              std::string());
}

}  // namespace internal

void parseTumList(std::istream& in, TumList& list) {
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    double t;
    std::string name;
    if (ss >> t >> name) list.emplace_back(t, name);
  }
}

void parseTumAssociations(std::istream& in, std::vector<TumPair>& pairs) {
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    double t1, t2;
    std::string f1, f2;
    if (!(ss >> t1 >> f1 >> t2 >> f2)) continue;
    if (f1.find("depth") != std::string::npos && f2.find("depth") == std::string::npos) {
      std::swap(t1, t2);
      std::swap(f1, f2);
    }
    TumPair p;
    p.stamp = t1;
    p.colour = f1;
    p.depth = f2;
    pairs.push_back(std::move(p));
  }
}

void associateTumLists(const TumList& rgb, const TumList& depth, double tolerance,
                       std::vector<TumPair>& pairs) {
  // nearest depth for each colour frame, one to one, within the tolerance
  size_t j = 0;
  for (const auto& c : rgb) {
    while (j + 1 < depth.size() &&
           std::fabs(depth[j + 1].first - c.first) <= std::fabs(depth[j].first - c.first))
      ++j;
    if (j < depth.size() && std::fabs(depth[j].first - c.first) <= tolerance) {
      TumPair p;
      p.stamp = c.first;
      p.colour = c.second;
      p.depth = depth[j].second;
      pairs.push_back(std::move(p));
      ++j;
    }
  }
}

}  // namespace tools
}  // namespace rgbd_lane_detector
