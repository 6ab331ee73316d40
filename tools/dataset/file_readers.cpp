// Folder datasets: SYNTHIA-SEQS, TUM RGB-D (associations or rgb/depth lists), numbered TUM
// frames (N.png + N_depth.png) and KITTI stereo frames with disparity.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "readers_internal.h"

namespace rgbd_lane_detector {
namespace tools {
namespace internal {
namespace {
namespace fs = std::filesystem;

struct FileEntry {
  std::string colour, depth, name;
  int index = 0;
  double stamp = 0.0;
};

enum class DepthEncoding { kUint16, kKittiDisparity };

bool allDigits(const std::string& s) {
  return !s.empty() && s.size() <= 9 && s.find_first_not_of("0123456789") == std::string::npos;
}

/// Reads listed colour/depth file pairs.
class FileSequenceReader : public DatasetReader {
 public:
  FileSequenceReader(const char* kind, std::vector<FileEntry> entries, const DatasetOptions& o,
                     const Intrinsics& K, double scale, DepthEncoding enc, double baseline,
                     std::string gt)
      : kind_(kind), K_(K), scale_(scale), encoding_(enc), baseline_(baseline), gt_(std::move(gt)) {
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
    return std::string(kind_) == "kitti" || std::string(kind_) == "tum_frames";
  }

  bool next(DatasetFrame& f) override {
    if (pos_ >= entries_.size()) return false;
    const FileEntry& e = entries_[pos_++];
    try {
      f.colour = cv::imread(e.colour, cv::IMREAD_COLOR);
      if (f.colour.empty()) return fail("cannot read colour image " + e.colour);
      cv::Mat raw = cv::imread(e.depth, cv::IMREAD_UNCHANGED);
      if (raw.empty()) return fail("cannot read depth image " + e.depth);
      if (raw.depth() != CV_16U) return fail("depth image is not 16-bit: " + e.depth);
      if (raw.channels() > 1) cv::extractChannel(raw, raw, 0);  // SYNTHIA: same value in 3
      if (encoding_ == DepthEncoding::kKittiDisparity) {
        kittiDisparityToDepth(raw, K_.fx, baseline_, f.depth);
        f.depth_scale = 1.0;
      } else {
        f.depth = raw;
        f.depth_scale = scale_;
      }
    } catch (const cv::Exception& ex) {
      return fail("cannot decode " + e.colour + ": " + ex.what());
    }
    if (f.colour.size() != f.depth.size())
      return fail("colour and depth differ in size: " + e.colour + " / " + e.depth);
    f.format = PixelFormat::kBgr8;
    f.intrinsics = K_;
    f.index = e.index;
    f.name = e.name;
    f.stamp = e.stamp;
    return true;
  }

 private:
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
  DepthEncoding encoding_;
  double baseline_;
  std::string gt_;
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
      "synthia", entries, o, K, o.depth_scale > 0 ? o.depth_scale : 0.01, DepthEncoding::kUint16,
      0.0, fs::exists(gt, ec) ? gt.string() : std::string());
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
                                              DepthEncoding::kUint16, 0.0, std::string());
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
  return std::make_unique<FileSequenceReader>("tum_frames", entries, o, K,
                                              o.depth_scale > 0 ? o.depth_scale : 1.0 / 5000.0,
                                              DepthEncoding::kUint16, 0.0, std::string());
}

std::unique_ptr<DatasetReader> openKitti(const DatasetOptions& o, std::string& error) {
  const fs::path root(o.path);
  std::vector<FileEntry> entries;
  std::error_code ec;
  for (const auto& p : listFiles(root, "_disparity.png")) {
    const std::string n = p.filename().string();
    const std::string id = n.substr(0, n.size() - 14);
    const fs::path colour = root / (id + "_left.png");
    if (!fs::exists(colour, ec)) continue;
    entries.push_back({colour.string(), p.string(), id, 0, 0.0});
  }
  for (const char* disp : {"disp_occ_0", "disp_noc_0"}) {  // KITTI 2015 training layout
    if (!entries.empty()) break;
    for (const auto& p : listFiles(root / disp, ".png")) {
      const fs::path colour = root / "image_2" / p.filename();
      if (fs::exists(colour, ec))
        entries.push_back({colour.string(), p.string(), p.stem().string(), 0, 0.0});
    }
  }
  if (entries.empty()) {
    error = "KITTI folder " + o.path + ": no <id>_left.png + <id>_disparity.png pairs";
    return nullptr;
  }
  sortEntries(entries);
  for (size_t i = 0; i < entries.size(); ++i) {
    entries[i].index = static_cast<int>(i);
    entries[i].stamp = i / 10.0;
  }
  // P_rect_02 of the 2011-09-26 calibration (../shared/realdata/kitti2015/README)
  Intrinsics K{721.5377, 721.5377, 609.5593, 172.854};
  double baseline = 0.53273;
  const fs::path calib = root / "calib_cam_to_cam.txt";
  if (fs::exists(calib, ec) && !readKittiCalibration(calib.string(), K, baseline, error))
    return nullptr;
  if (!applyCameraInfo(o, K, error)) return nullptr;
  return std::make_unique<FileSequenceReader>(
      "kitti", entries, o, K, 1.0, DepthEncoding::kKittiDisparity, baseline, std::string());
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
