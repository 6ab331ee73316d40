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
  d.plane_valid = result.status == Status::kOk && result.plane.valid;
  d.normal = result.plane.normal;
  d.distance = result.plane.distance;
  d.left_reported = result.status == Status::kOk && result.left.found;
  d.right_reported = result.status == Status::kOk && result.right.found;
  if (d.left_reported) appendPoints(result.left, d.left);
  if (d.right_reported) appendPoints(result.right, d.right);
  return d;
}

const char* outcomeName(Outcome o) {
  switch (o) {
    case Outcome::kTruePositive:
      return "TP";
    case Outcome::kFalsePositive:
      return "FP";
    case Outcome::kMiss:
      return "miss";
  }
  return "?";
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

SideScore scoreSide(const std::vector<Eigen::Vector3d>& points,
                    const std::vector<Eigen::Vector3d>& line, const FrameTruth& truth,
                    const ScoringRules& rules) {
  SideScore s;
  double sum = 0.0;
  for (const auto& p : points) {
    if (!p.allFinite()) continue;
    ++s.points;
    const double d = lateralDistance(p, line, truth.normal, truth.distance);
    sum += d;
    if (d <= rules.max_lateral) ++s.inliers;
  }
  s.mean_lateral = s.points ? sum / s.points : kNaN;
  s.ok = !line.empty() && s.points >= rules.min_points &&
         s.inliers >= rules.min_inlier_fraction * s.points - 1e-9;
  return s;
}

FrameScore scoreFrame(const Detection& det, const FrameTruth& truth, const ScoringRules& rules) {
  FrameScore fs;
  fs.plane_valid = det.plane_valid && det.normal.allFinite() && std::isfinite(det.distance) &&
                   det.normal.norm() > 1e-9;
  const std::vector<Eigen::Vector3d> none;
  const std::vector<Eigen::Vector3d>& left = det.left_reported ? det.left : none;
  const std::vector<Eigen::Vector3d>& right = det.right_reported ? det.right : none;
  fs.reported = fs.plane_valid || !left.empty() || !right.empty();
  fs.angle_error_deg = fs.offset_error = kNaN;
  if (fs.plane_valid) {
    const double c = det.normal.normalized().dot(truth.normal.normalized());
    fs.angle_error_deg = std::acos(std::min(1.0, std::max(-1.0, c))) * 180.0 / M_PI;
    fs.offset_error = std::fabs(det.distance - truth.distance);
    fs.plane_ok = c > 0.0 && det.distance > 0.0 && fs.angle_error_deg <= rules.max_angle_deg &&
                  fs.offset_error <= rules.max_offset;
  }
  fs.left = scoreSide(left, truth.left, truth, rules);
  fs.right = scoreSide(right, truth.right, truth, rules);
  if (!fs.reported) {
    fs.outcome = Outcome::kMiss;
  } else if (truth.has_lane && fs.plane_ok && fs.left.ok && fs.right.ok) {
    fs.outcome = Outcome::kTruePositive;
  } else {
    fs.outcome = Outcome::kFalsePositive;
  }
  return fs;
}

void ScoreSummary::add(const FrameScore& s, double ms) {
  ++frames;
  sum_ms += ms;
  switch (s.outcome) {
    case Outcome::kTruePositive:
      ++tp;
      break;
    case Outcome::kFalsePositive:
      ++fp;
      break;
    case Outcome::kMiss:
      ++miss;
      break;
  }
  if (s.plane_valid && std::isfinite(s.angle_error_deg)) {
    ++plane_frames;
    sum_angle_error += s.angle_error_deg;
    sum_offset_error += s.offset_error;
  }
}

double ScoreSummary::meanAngleError() const {
  return plane_frames ? sum_angle_error / plane_frames : kNaN;
}
double ScoreSummary::meanOffsetError() const {
  return plane_frames ? sum_offset_error / plane_frames : kNaN;
}

}  // namespace tools
}  // namespace rgbd_lane_detector
