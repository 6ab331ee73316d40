#include "rgbd_lane_detector_tools/real_labels.h"

#include <cmath>

#include "rgbd_lane_detector_tools/scoring.h"

namespace rgbd_lane_detector {
namespace tools {
namespace {

bool readSide(const cv::FileNode& node, const std::string& where, LabelledSide& side,
              std::string& error) {
  side = LabelledSide();
  if (node.empty() || node.isNone()) return true;
  const std::string kind = static_cast<std::string>(node["kind"]);
  if (kind == "none" || kind.empty()) return true;
  if (kind == "paint") {
    side.kind = BoundaryKind::kPaint;
  } else if (kind == "road_edge") {
    side.kind = BoundaryKind::kRoadEdge;
  } else {
    error = where + ": unknown kind '" + kind + "' (paint, road_edge or none)";
    return false;
  }
  const cv::FileNode pts = node["points"];
  if (!pts.isSeq() || pts.size() < 4 || pts.size() % 2 != 0) {
    error = where + ": points must be a list of at least two x, y pairs";
    return false;
  }
  for (size_t i = 0; i + 1 < pts.size(); i += 2)
    side.points.emplace_back(static_cast<double>(pts[static_cast<int>(i)]),
                             static_cast<double>(pts[static_cast<int>(i + 1)]));
  side.present = true;
  return true;
}

void scoreSide(const MarkerTrace& m, const LabelledSide& label, const std::vector<Eigen::Vector3d>& line,
               const Eigen::Vector3d& normal, double distance, const RealScoringRules& rules,
               RealSideScore& s) {
  s = RealSideScore();
  s.labelled = label.present;
  s.reported = m.found;
  s.reported_kind = m.kind;
  if (s.reported && s.labelled && !line.empty()) {
    for (const auto& p : m.points) {
      if (!p.allFinite()) continue;
      ++s.points;
      s.inliers += lateralDistance(p.cast<double>(), line, normal, distance) <= rules.max_lateral;
    }
    s.fraction = s.points ? static_cast<double>(s.inliers) / s.points : 0.0;
    s.on_line = s.points >= rules.min_points && s.fraction >= rules.min_fraction;
    s.correct = s.on_line && m.kind == label.kind;
  }
  s.wrong = s.reported && !s.correct;
  s.missed = s.labelled && !s.reported;
}

}  // namespace

bool readRealLabels(const std::string& path, std::vector<LabelledFrame>& labels,
                    std::string& error) {
  labels.clear();
  cv::FileStorage fs;
  try {
    if (!fs.open(path, cv::FileStorage::READ)) {
      error = "cannot read the label file " + path;
      return false;
    }
  } catch (const cv::Exception& e) {
    error = "malformed label file " + path + ": " + e.what();
    return false;
  }
  const cv::FileNode frames = fs["frames"];
  if (!frames.isSeq()) {
    error = path + ": no 'frames' list";
    return false;
  }
  for (const auto& node : frames) {
    LabelledFrame f;
    f.dataset = static_cast<std::string>(node["dataset"]);
    f.frame = static_cast<std::string>(node["frame"]);
    f.lane = static_cast<int>(node["lane"]) != 0;
    const std::string where = path + " (" + f.dataset + "/" + f.frame + ")";
    if (f.dataset.empty() || f.frame.empty()) {
      error = path + ": a frame without dataset or frame name";
      return false;
    }
    if (!readSide(node["left"], where + " left", f.left, error) ||
        !readSide(node["right"], where + " right", f.right, error))
      return false;
    if (f.lane && !f.left.present && !f.right.present) {
      error = where + ": lane: 1 but no side is labelled";
      return false;
    }
    labels.push_back(f);
  }
  return true;
}

const LabelledFrame* findRealLabel(const std::vector<LabelledFrame>& labels,
                                   const std::string& dataset, const std::string& frame) {
  for (const auto& l : labels)
    if (l.dataset == dataset && l.frame == frame) return &l;
  return nullptr;
}

void labelOnPlane(const LabelledSide& side, const Intrinsics& K, const Eigen::Vector3d& normal,
                  double distance, std::vector<Eigen::Vector3d>& line) {
  line.clear();
  for (const auto& q : side.points) {
    const Eigen::Vector3d ray((q.x - K.cx) / K.fx, (q.y - K.cy) / K.fy, 1.0);
    const double den = normal.dot(ray);
    if (!(den < -1e-9)) continue;
    line.push_back(ray * (-distance / den));
  }
}

RealFrameScore scoreRealFrame(const Result& result, const LabelledFrame& label, const Intrinsics& K,
                              const Eigen::Vector3d& normal, double distance,
                              const RealScoringRules& rules) {
  RealFrameScore score;
  std::vector<Eigen::Vector3d> line;
  const LabelledSide none;
  const bool ok = result.status == Status::kOk;
  const LabelledSide* sides[2] = {label.lane ? &label.left : &none,
                                  label.lane ? &label.right : &none};
  const MarkerTrace* traces[2] = {&result.left, &result.right};
  RealSideScore* out[2] = {&score.left, &score.right};
  for (int i = 0; i < 2; ++i) {
    if (sides[i]->present) labelOnPlane(*sides[i], K, normal, distance, line);
    else line.clear();
    MarkerTrace reported;
    if (ok) reported = *traces[i];
    else reported.found = false;
    scoreSide(reported, *sides[i], line, normal, distance, rules, *out[i]);
  }
  score.wrong = score.left.wrong || score.right.wrong;
  score.complete = !score.wrong && !score.left.missed && !score.right.missed;
  return score;
}

}  // namespace tools
}  // namespace rgbd_lane_detector
