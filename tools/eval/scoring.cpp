#include "rgbd_lane_detector_tools/scoring.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rgbd_lane_detector {
namespace tools {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void appendPoints(const MarkerTrace& m, std::vector<Eigen::Vector3d>& out) {
  out.clear();
  if (!m.found) return;
  out.reserve(m.points.size());
  for (const auto& p : m.points) out.push_back(p.cast<double>());
}

}  // namespace

Detection detectionFromResult(const Result& result) {
  Detection d;
  const bool ok = result.status == Status::kOk;
  d.plane_valid = ok && result.plane.valid;
  d.normal = result.plane.normal;
  d.distance = result.plane.distance;
  d.left_reported = ok && result.left.found;
  d.right_reported = ok && result.right.found;
  d.left_kind = result.left.kind;
  d.right_kind = result.right.kind;
  d.left_confidence = result.left.confidence;
  d.right_confidence = result.right.confidence;
  if (d.left_reported) appendPoints(result.left, d.left);
  if (d.right_reported) appendPoints(result.right, d.right);
  return d;
}

const char* outcomeName(Outcome o) {
  static const char* const kNames[] = {"TP", "partial", "FP", "miss"};
  const size_t i = static_cast<size_t>(o);
  return i < 4 ? kNames[i] : "?";
}

const char* sideOutcomeName(SideOutcome o) {
  static const char* const kNames[] = {"none",     "correct",  "wrong_kind",
                                       "off_line", "spurious", "missed"};
  const size_t i = static_cast<size_t>(o);
  return i < 6 ? kNames[i] : "?";
}

double lateralDistance(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& line,
                       const Eigen::Vector3d& normal, double distance) {
  if (line.empty()) return std::numeric_limits<double>::infinity();
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d q = p - (n.dot(p) + distance) * n;  // foot point on the road plane
  if (line.size() == 1) return (q - line[0]).norm();
  double best = std::numeric_limits<double>::infinity();
  const size_t last = line.size() - 2;
  for (size_t i = 0; i + 1 < line.size(); ++i) {
    const Eigen::Vector3d a = line[i] - n * (n.dot(line[i]) + distance);
    const Eigen::Vector3d b = line[i + 1] - n * (n.dot(line[i + 1]) + distance);
    const Eigen::Vector3d ab = b - a;
    const double len2 = ab.squaredNorm();
    double u = len2 > 0 ? (q - a).dot(ab) / len2 : 0.0;
    // the end segments extend beyond the sampled range (lateral distance, not to the end point)
    const double lo = i == 0 ? -std::numeric_limits<double>::infinity() : 0.0;
    const double hi = i == last ? std::numeric_limits<double>::infinity() : 1.0;
    u = std::min(std::max(u, lo), hi);
    best = std::min(best, (q - (a + u * ab)).norm());
  }
  return best;
}

LateralLine::LateralLine(const std::vector<Eigen::Vector3d>& points,
                         const Eigen::Isometry3d& base_from_optical) {
  xy_.reserve(points.size());
  for (const auto& p : points) {
    if (!p.allFinite()) continue;
    const Eigen::Vector3d b = base_from_optical * p;
    xy_.emplace_back(b.x(), b.y());
  }
  sort();
}

LateralLine::LateralLine(const std::vector<Eigen::Vector3d>& points_base, double max_gap)
    : max_gap_(max_gap) {
  xy_.reserve(points_base.size());
  for (const auto& p : points_base)
    if (p.allFinite()) xy_.emplace_back(p.x(), p.y());
  sort();
}

void LateralLine::sort() {
  std::sort(xy_.begin(), xy_.end(),
            [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() < b.x(); });
}

double LateralLine::length() const {
  double sum = 0.0;
  for (size_t i = 1; i < xy_.size(); ++i) {
    const double dx = xy_[i].x() - xy_[i - 1].x();
    if (dx <= max_gap_) sum += dx;
  }
  return sum;
}

double LateralLine::at(double x) const {
  if (empty() || !(x >= xy_.front().x() && x <= xy_.back().x())) return kNaN;
  // first point with x >= the query; its predecessor starts the segment
  const auto it = std::lower_bound(xy_.begin(), xy_.end(), x,
                                   [](const Eigen::Vector2d& p, double v) { return p.x() < v; });
  if (it == xy_.begin()) return it->y();
  const Eigen::Vector2d& a = *(it - 1);
  const Eigen::Vector2d& b = *it;
  const double dx = b.x() - a.x();
  if (dx > max_gap_) return kNaN;
  const double w = dx > 0 ? (x - a.x()) / dx : 0.0;
  return a.y() + w * (b.y() - a.y());
}

double lateralErrorAt(const std::vector<Eigen::Vector3d>& points, const TrueBoundary& truth,
                      const FrameTruth& frame, double x) {
  if (!frame.has_vehicle_frame) return kNaN;
  const LateralLine reported(points, frame.base_to_camera);
  const LateralLine line(truth.points, frame.base_to_camera);
  return std::fabs(reported.at(x) - line.at(x));
}

SideScore scoreSide(const std::vector<Eigen::Vector3d>& points, bool reported, BoundaryKind kind,
                    double confidence, const TrueBoundary* truth, const FrameTruth& frame,
                    const ScoringRules& rules) {
  SideScore s;
  std::fill(std::begin(s.lateral_error), std::end(s.lateral_error), kNaN);
  s.truth = truth != nullptr;
  if (truth) s.true_kind = truth->kind;
  s.reported = reported;
  s.mean_lateral = kNaN;
  if (!reported) {
    s.outcome = s.truth ? SideOutcome::kMissed : SideOutcome::kNone;
    return s;
  }
  s.reported_kind = kind;
  s.confidence = confidence;
  double sum = 0.0;
  for (const auto& p : points) {
    if (!p.allFinite()) continue;
    ++s.points;
    if (!truth) continue;
    const double d = lateralDistance(p, truth->points, frame.normal, frame.distance);
    sum += d;
    if (d <= rules.max_lateral) ++s.inliers;
  }
  if (truth && s.points) s.mean_lateral = sum / s.points;
  if (truth)
    for (int k = 0; k < kNumLateralDistances; ++k)
      s.lateral_error[k] = lateralErrorAt(points, *truth, frame, kLateralDistances[k]);
  s.on_line = truth && s.points >= rules.min_points &&
              s.inliers >= rules.min_inlier_fraction * s.points - 1e-9;
  if (!truth)
    s.outcome = SideOutcome::kSpurious;
  else if (!s.on_line)
    s.outcome = SideOutcome::kOffLine;
  else
    s.outcome = kind == truth->kind ? SideOutcome::kCorrect : SideOutcome::kWrongKind;
  return s;
}

FrameScore scoreFrame(const Detection& det, const FrameTruth& truth, const ScoringRules& rules) {
  FrameScore fs;
  fs.plane_valid = det.plane_valid && det.normal.allFinite() && std::isfinite(det.distance) &&
                   det.normal.norm() > 1e-9;
  fs.angle_error_deg = fs.offset_error = kNaN;
  if (fs.plane_valid) {
    const double c = det.normal.normalized().dot(truth.normal.normalized());
    fs.angle_error_deg = std::acos(std::min(1.0, std::max(-1.0, c))) * 180.0 / M_PI;
    fs.offset_error = std::fabs(det.distance - truth.distance);
    fs.plane_ok = c > 0.0 && det.distance > 0.0 && fs.angle_error_deg <= rules.max_angle_deg &&
                  fs.offset_error <= rules.max_offset;
  }
  fs.left = scoreSide(det.left, det.left_reported, det.left_kind, det.left_confidence,
                      truth.egoSide(true), truth, rules);
  fs.right = scoreSide(det.right, det.right_reported, det.right_kind, det.right_confidence,
                       truth.egoSide(false), truth, rules);
  fs.reported = fs.left.reported || fs.right.reported;
  fs.lane_required = truth.has_lane && !truth.lane_optional;
  const bool wrong = fs.left.wrong() || fs.right.wrong() || (fs.reported && !fs.plane_ok);
  // every true side correct (a side without truth is fine when not reported: not wrong)
  const bool complete = (!fs.left.truth || fs.left.correct()) &&
                        (!fs.right.truth || fs.right.correct()) && truth.has_lane;
  if (!fs.reported)
    fs.outcome = Outcome::kMiss;
  else if (wrong)
    fs.outcome = Outcome::kWrong;
  else if (complete)
    fs.outcome = Outcome::kTruePositive;
  else
    fs.outcome = Outcome::kPartial;
  return fs;
}

double ScoreSummary::percent(int a, int b) {
  return b > 0 ? 100.0 * a / b : kNaN;
}

void ScoreSummary::add(const FrameScore& s, double ms) {
  ++frames;
  sum_ms += ms;
  if (s.outcome == Outcome::kWrong) ++wrong;
  if (s.lane_required) {
    ++required;
    tp += s.outcome == Outcome::kTruePositive;
    partial += s.outcome == Outcome::kPartial;
    miss += s.outcome == Outcome::kMiss;
  }
  if (s.plane_valid && std::isfinite(s.angle_error_deg)) {
    ++plane_frames;
    plane_ok += s.plane_ok;
    sum_angle_error += s.angle_error_deg;
    sum_offset_error += s.offset_error;
  }
  for (const SideScore* side : {&s.left, &s.right}) {
    if (side->reported) {
      ++sides_reported;
      sides_correct += side->correct();
      const int t = side->truth ? static_cast<int>(side->true_kind) : 2;
      ++confusion[t][static_cast<int>(side->reported_kind)];
    }
    if (side->truth && s.lane_required) {
      ++sides_true;
      sides_true_correct += side->correct();
    }
    for (int k = 0; k < kNumLateralDistances; ++k)
      if (std::isfinite(side->lateral_error[k]))
        lateral_errors[k].push_back(side->lateral_error[k]);
  }
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return kNaN;
  const size_t rank = static_cast<size_t>(std::ceil(q / 100.0 * v.size()));
  const size_t i = std::min(v.size() - 1, rank > 0 ? rank - 1 : 0);
  std::nth_element(v.begin(), v.begin() + i, v.end());
  return v[i];
}

double ScoreSummary::lateralPercentile(int k, double q) const {
  return percentile(lateral_errors[k], q);
}

double ScoreSummary::meanAngleError() const {
  return plane_frames ? sum_angle_error / plane_frames : kNaN;
}
double ScoreSummary::meanOffsetError() const {
  return plane_frames ? sum_offset_error / plane_frames : kNaN;
}

}  // namespace tools
}  // namespace rgbd_lane_detector
