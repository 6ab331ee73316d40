#include "rgbd_lane_detector_tools/real_labels.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include <opencv2/calib3d.hpp>

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
  const std::string style = static_cast<std::string>(node["style"]);
  const std::string colour = static_cast<std::string>(node["colour"]);
  if (side.kind == BoundaryKind::kPaint) {
    if (style == "solid") side.style = rgbd_lane_detector::LineKind::kSolid;
    else if (style == "dashed") side.style = rgbd_lane_detector::LineKind::kDashed;
    else if (!style.empty()) {
      error = where + ": unknown style '" + style + "' (solid or dashed)";
      return false;
    }
    if (colour == "white") side.colour = rgbd_lane_detector::LineColour::kWhite;
    else if (colour == "yellow") side.colour = rgbd_lane_detector::LineColour::kYellow;
    else if (!colour.empty()) {
      error = where + ": unknown colour '" + colour + "' (white or yellow)";
      return false;
    }
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
  if (s.reported && m.kind == BoundaryKind::kPaint) {
    if (m.paint_coverage >= 0.0f)
      s.reported_style = m.paint_coverage < rules.dashed_coverage ? rgbd_lane_detector::LineKind::kDashed : rgbd_lane_detector::LineKind::kSolid;
    if (m.yellowness >= 0.0f)
      s.reported_colour = m.yellowness >= rules.yellowness ? rgbd_lane_detector::LineColour::kYellow : rgbd_lane_detector::LineColour::kWhite;
  }
  if (s.correct && label.kind == BoundaryKind::kPaint) {
    if (label.style != rgbd_lane_detector::LineKind::kUnknown) s.style_right = s.reported_style == label.style;
    if (label.colour != rgbd_lane_detector::LineColour::kUnknown) s.colour_right = s.reported_colour == label.colour;
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
    f.key = !node["key"].empty() && static_cast<int>(node["key"]) != 0;
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

double polylineXAt(const std::vector<cv::Point2d>& line, double y) {
  for (size_t i = 1; i < line.size(); ++i) {
    const cv::Point2d& a = line[i - 1];
    const cv::Point2d& b = line[i];
    if ((y - a.y) * (y - b.y) > 0.0) continue;  // not between the two rows
    if (a.y == b.y) return 0.5 * (a.x + b.x);
    return a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

namespace {

bool numbered(const std::string& s, long& n) {
  if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos) return false;
  n = std::strtol(s.c_str(), nullptr, 10);
  return true;
}

LabelledSide interpolateSide(const LabelledSide& a, const LabelledSide& b, double t) {
  if (!a.present || !b.present || a.kind != b.kind) return t < 0.5 ? a : b;
  std::vector<double> rows;
  for (const auto* s : {&a, &b})
    for (const auto& q : s->points) rows.push_back(q.y);
  std::sort(rows.begin(), rows.end(), std::greater<double>());  // near (bottom) to far
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  LabelledSide out = t < 0.5 ? a : b;
  out.points.clear();
  for (double y : rows) {
    const double xa = polylineXAt(a.points, y), xb = polylineXAt(b.points, y);
    if (std::isfinite(xa) && std::isfinite(xb)) out.points.emplace_back(xa + t * (xb - xa), y);
  }
  if (out.points.size() < 2) return t < 0.5 ? a : b;
  return out;
}

}  // namespace

bool realLabelOf(const std::vector<LabelledFrame>& labels, const std::string& dataset,
                 const std::string& frame, LabelledFrame& label) {
  if (const LabelledFrame* own = findRealLabel(labels, dataset, frame)) {
    label = *own;
    return true;
  }
  long n = 0;
  if (!numbered(frame, n)) return false;
  const LabelledFrame *before = nullptr, *after = nullptr;
  long nb = 0, na = 0;
  for (const auto& l : labels) {
    long k = 0;
    if (l.dataset != dataset || !l.key || !numbered(l.frame, k)) continue;
    if (k < n && (!before || k > nb)) before = &l, nb = k;
    if (k > n && (!after || k < na)) after = &l, na = k;
  }
  if (!before || !after) return false;
  const double t = static_cast<double>(n - nb) / static_cast<double>(na - nb);
  label = t < 0.5 ? *before : *after;
  label.frame = frame;
  label.key = false;
  label.lane = before->lane && after->lane;
  label.left = interpolateSide(before->left, after->left, t);
  label.right = interpolateSide(before->right, after->right, t);
  return true;
}

void undistortLabel(const Intrinsics& K, const cv::Mat& distortion, LabelledFrame& label) {
  if (distortion.empty()) return;
  const cv::Matx33d k(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1);
  for (LabelledSide* s : {&label.left, &label.right}) {
    if (s->points.empty()) continue;
    std::vector<cv::Point2d> out;
    cv::undistortPoints(s->points, out, k, distortion, cv::noArray(), k);
    s->points = out;
  }
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
