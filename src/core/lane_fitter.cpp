// The lane fit: each frame's mode, and the improved mode's boundaries (each side's candidates
// measured on the road plane, the boundary chosen, tracked and reported with its kind and
// confidence; the lines beyond). The lane plane and paper mode: lane_fitter_plane.cpp.
#include "rgbd_lane_detector/lane_fitter.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "rgbd_lane_detector/lane_plane.h"

namespace rgbd_lane_detector {
namespace {

constexpr double kMaxHeading = 0.35;     // rad: a lane boundary runs along the road (~20 deg)
constexpr double kNearestForward = 0.5;  // m: points closer ahead are not used
constexpr double kEdgeDepthHeight = 0.3; // m: depth of a road edge up to this high is its own
constexpr float kKindMemory = 0.8f;      // decay per frame of a side's kind vote
// A tracked side's reported confidence (MarkerTrace::confidence, the detector's own): frames of
// evidence for 1 - 1/e, and its factor per frame without evidence. Not the lane model's evidence
// score (lane_model.cpp), which has its own decay and is calibrated on its own.
constexpr double kConfidenceFrames = 3.0;
constexpr double kConfidenceAgeDecay = 0.8;
constexpr double kWidthProbe = 8.0;      // m ahead where two sides' lane width is checked
constexpr int kMinEdgePoints = 5;       // own points a road edge is reported on
constexpr int kMaxEdgeSamples = 40;     // reported points of a road edge at most
constexpr double kEdgeSpike = 0.1;      // m off its robust curve: not the edge
constexpr int kSwitchFrames = 3;         // frames a nearer line must persist to replace a track
constexpr int kCarryFrames = 3;          // frames a tracked side is carried before another line replaces it
// m ahead where a marker's side of the vehicle is told: at the vehicle (the road under the
// camera), where the lane model relabels its lanes and the vehicle is in one lane or the other;
// not where it heads (1.5 m ahead of a vehicle turning 0.1 rad is 0.15 m to the side)
constexpr double kCrossProbe = 0.0;
constexpr double kNextLaneMin = 1.5;     // m: an outer line at least this far beyond the ego one
constexpr double kLineGate = 0.3;        // m: a candidate's points this near its line are its own

// Not reported: no points, no confidence (the buffers keep their capacity).
void clearTrace(MarkerTrace& m) {
  m.found = false;
  m.confidence = 0.0f;
  m.pixels.clear();
  m.points.clear();
  m.scores.clear();
  m.measured.clear();
  m.num_valid_points = 0;
}

}  // namespace

LaneFitter::LaneFitter() { reset(); }

void LaneFitter::reset() {
  previous_plane_.valid = false;
  tracker_.reset();
  kind_score_ = {0.f, 0.f};
  evidence_margin_ = {0.f, 0.f};
  disagree_ = {0, 0};
}

void LaneFitter::fit(const LaneFitInput& in, Result& result) {
  result.plane.valid = false;
  result.plane.support.clear();
  for (MarkerTrace& m : result.outer) clearTrace(m);
  if (params_.track_lanes) {
    fitBoundaries(in, result);
  } else {
    for (int i = 0; i < 2; ++i) {
      MarkerTrace& side = i == 0 ? result.left : result.right;
      if (in.counts[i] > 0) copyTrace((*in.candidates)[i][0].trace, side);
      side.kind = BoundaryKind::kPaint;
    }
    fitMarkerPlane(in, result);
    for (MarkerTrace* m : {&result.left, &result.right})
      m->confidence = m->found ? static_cast<float>(std::min(1.0, 0.5 * m->peak_score)) : 0.0f;
  }
  previous_plane_.valid = result.plane.valid;
  if (result.plane.valid) {
    previous_plane_.normal = result.plane.normal;
    previous_plane_.distance = result.plane.distance;
  }
}

void LaneFitter::measure(const Intrinsics& K, const PlaneEstimate& plane, const RoadFrame& frame,
                         double road_range, bool left, BoundaryCandidate& c) const {
  c.road.clear();
  c.usable = false;
  c.offset = c.heading = c.lateral = std::numeric_limits<double>::quiet_NaN();
  if (!c.evidence.boundary || !frame.valid()) return;
  const bool edge = c.evidence.kind == BoundaryKind::kRoadEdge;
  const MarkerTrace& t = c.trace;
  for (size_t k = 0; k < t.pixels.size(); ++k) {
    // Paint lies on the road: its pixel's ray met with the plane, where the plane holds; a
    // road edge (a kerb's face) is where its depth stands on the road. Beyond the plane's
    // range, the depth.
    const Eigen::Vector3f& q = t.points[k];
    const bool depth = q.allFinite() && std::fabs(planeDistance(plane, q)) <= kEdgeDepthHeight;
    Eigen::Vector3d P;
    const Eigen::Vector3d ray = K.ray(t.pixels[k].x, t.pixels[k].y);
    double z = 0.0;
    const bool on_plane = rayPlaneDepth(plane, ray, z) && z <= road_range;
    if (edge && depth)
      P = q.cast<double>();
    else if (on_plane)
      P = ray * z;
    else if (depth)
      P = q.cast<double>();
    else
      continue;
    const Eigen::Vector2d fl = frame.toRoad(P);
    if (fl.x() >= kNearestForward) c.road.push_back(fl);
  }
  if (static_cast<int>(c.road.size()) < params_.min_marker_points) return;
  double a = 0.0, b = 0.0;
  if (!fitRobustLine(c.road, kLineGate, a, b)) return;
  c.offset = a;
  c.heading = std::atan(b);
  // where it is: the median lateral position of its own points (the offset extrapolates the
  // line to the vehicle, and two lines seen at different headings would compare there); of an
  // even count the lower one, the one nearer the right (as when the lateral axis pointed right)
  laterals_.clear();
  for (const auto& q : c.road) laterals_.push_back(q.y());
  const size_t mid = (laterals_.size() - 1) / 2;
  std::nth_element(laterals_.begin(), laterals_.begin() + mid, laterals_.end());
  c.lateral = laterals_[mid];
  const double side = left ? a : -a;
  c.usable = side >= params_.boundary_offset_min && side <= params_.boundary_offset_max &&
             std::fabs(c.heading) <= kMaxHeading;
}

int LaneFitter::choose(int i, const LaneFitInput& in) {
  const std::vector<BoundaryCandidate>& cands = (*in.candidates)[i];
  int nearest = -1, consistent = -1;
  for (int k = 0; k < in.counts[i]; ++k) {
    const BoundaryCandidate& c = cands[k];
    if (!c.usable) continue;
    if (nearest < 0 || std::fabs(c.lateral) < std::fabs(cands[nearest].lateral)) nearest = k;
    if (!tracker_.established(i)) continue;
    // agrees with the tracked boundary: most of its points within the gate
    int inliers = 0;
    for (const auto& q : c.road)
      inliers += std::fabs(q.y() - tracker_.lateral(i, q.x())) <= params_.track_gate;
    if (2 * inliers < static_cast<int>(c.road.size())) continue;
    if (consistent < 0 || std::fabs(c.lateral) < std::fabs(cands[consistent].lateral))
      consistent = k;
  }
  // A line nearer the vehicle than the tracked one, seen in the same place kSwitchFrames frames
  // in a row, becomes this side's boundary (a lane change: the crossed line is the new nearest
  // one; or the track had followed the next lane's line). One frame of it (an arrow, a patch of
  // paint) does not.
  if (consistent >= 0 && nearest >= 0 &&
      std::fabs(cands[nearest].lateral) < std::fabs(cands[consistent].lateral) - params_.track_gate) {
    const double off = cands[nearest].lateral;
    disagree_[i] = disagree_[i] > 0 && std::fabs(off - disagree_offset_[i]) <= params_.track_gate
                       ? disagree_[i] + 1
                       : 1;
    disagree_offset_[i] = off;
    if (disagree_[i] >= kSwitchFrames) {
      disagree_[i] = 0;
      tracker_.resetSide(i);
      return nearest;
    }
  } else {
    disagree_[i] = 0;
  }
  // Nothing where the tracked boundary is: the model carries it for a few frames (a dash gap, a
  // patch of worn paint) rather than take another line farther out (a kerb, a truck's side)
  if (consistent < 0 && tracker_.established(i) && tracker_.age(i) < kCarryFrames) return -1;
  return consistent >= 0 ? consistent : nearest;
}

void LaneFitter::fitBoundaries(const LaneFitInput& in, Result& result) {
  TrackerParams tp;
  tp.memory = params_.track_memory;
  tp.max_age = params_.track_max_age;
  tp.gate = params_.track_gate;
  tp.min_points = params_.min_marker_points;
  PlaneEstimate& plane = result.plane;
  double road_range = in.road_range;
  boundaryPlane(in, plane, road_range);
  takeSeedMeasurements(in, result);
  if (!plane.valid) {
    tracker_.update(RoadFrame(), none_, none_, tp);  // ages the lane model
    return;
  }
  smoothPlane(plane);
  const RoadFrame frame = RoadFrame::fromPlane(plane);
  std::array<int, 2> chosen = chooseBoundaries(in, plane, frame, road_range);
  tracker_.update(frame, evidence_[0], evidence_[1], tp);
  handOverCrossedSide(chosen);
  reportSide(0, in, frame, road_range, chosen[0], tp.sample_step, result.left);
  reportSide(1, in, frame, road_range, chosen[1], tp.sample_step, result.right);
  reportOuterLines(in, frame, chosen, result);
  dropImplausibleWidth(result);
  requirePaint(result);
  if (!result.left.found || !result.right.found) rejectIncomplete(result);
}

void LaneFitter::boundaryPlane(const LaneFitInput& in, PlaneEstimate& plane,
                               double& road_range) {
  // The road surface from depth, else (marker plane modes) the plane of the best seeds' depth;
  // while the depth shows no road, the last plane for as long as a side lives.
  const Params& p = params_;
  const bool any_track = tracker_.valid(0) || tracker_.valid(1);
  if (p.plane_fit == PlaneFit::kRoadSurface) {
    // (RoadSurface checked it against the up axis it was fitted with: the vehicle's, when the
    // frame gives the camera's pose)
    if (in.road != nullptr && in.road->valid) {
      plane.valid = true;
      plane.normal = in.road->normal;
      plane.distance = in.road->distance;
      plane.rms = in.road->rms;
      plane.fit_method = in.road->fit_method;
      plane.range = in.road->range;
      plane.support.assign(in.road->support.begin(), in.road->support.end());
    }
  } else {
    fit_points_.clear();
    for (int i = 0; i < 2; ++i)
      if (in.counts[i] > 0)
        for (const auto& q : (*in.candidates)[i][0].trace.points)
          if (q.allFinite()) fit_points_.push_back(q);
    if (fitPlaneLeastSquares(fit_points_, 0.1, 3, plane) && !planePlausible(plane))
      plane.valid = false;
    road_range = p.max_depth;
  }
  if (!plane.valid && previous_plane_.valid && any_track) {
    plane.valid = true;
    plane.normal = previous_plane_.normal;
    plane.distance = previous_plane_.distance;
    plane.rms = 0.0;
    plane.range = 0.0;
    plane.fit_method = static_cast<int>(p.plane_fit);
    road_range = std::max(road_range, 20.0);
  }
}

void LaneFitter::takeSeedMeasurements(const LaneFitInput& in, Result& result) const {
  MarkerTrace* sides[2] = {&result.left, &result.right};
  for (int i = 0; i < 2; ++i) {
    MarkerTrace& m = *sides[i];
    clearTrace(m);
    if (in.counts[i] > 0) {  // the best seed's image measurements, for templates and overlays
      const MarkerTrace& best = (*in.candidates)[i][0].trace;
      m.peak_score = best.peak_score;
      m.seed = best.seed;
      m.seed_point = best.seed_point;
      m.angle = best.angle;
      m.angle_valid = best.angle_valid;
    }
  }
}

std::array<int, 2> LaneFitter::chooseBoundaries(const LaneFitInput& in, const PlaneEstimate& plane,
                                                const RoadFrame& frame, double road_range) {
  // each side's boundary: the nearest usable candidate (the tracked one while it is seen); its
  // road points are the side's evidence (evidence_)
  std::array<int, 2> chosen{{-1, -1}};
  for (int i = 0; i < 2; ++i) {
    evidence_[i].clear();
    std::vector<BoundaryCandidate>& cands = (*in.candidates)[i];
    for (int k = 0; k < in.counts[i]; ++k) measure(in.K, plane, frame, road_range, i == 0, cands[k]);
    chosen[i] = choose(i, in);
    if (chosen[i] < 0) continue;
    for (const auto& q : cands[chosen[i]].road)
      evidence_[i].push_back(frame.toCamera(q.x(), q.y()).cast<float>());
  }
  return chosen;
}

void LaneFitter::handOverCrossedSide(std::array<int, 2>& chosen) {
  // A side whose marker passed under the vehicle (a lane change) is the other side's now: the
  // left marker to the right of the vehicle (y < 0), or the right one to its left.
  for (int i = 0; i < 2; ++i) {
    if (!tracker_.valid(i)) continue;
    const double crossed = (i == 0 ? -1.0 : 1.0) * tracker_.lateral(i, kCrossProbe);
    if (crossed <= 0.0) continue;
    tracker_.handOver(i);
    kind_score_[1 - i] = kind_score_[i];
    evidence_margin_[1 - i] = evidence_margin_[i];
    kind_score_[i] = evidence_margin_[i] = 0.f;
    disagree_ = {0, 0};
    chosen[1 - i] = chosen[i] >= 0 ? -1 : chosen[1 - i];  // this frame's choice was for the old side
    chosen[i] = -1;
    break;
  }
}

void LaneFitter::reportSide(int i, const LaneFitInput& in, const RoadFrame& frame,
                            double road_range, int chosen, double sample_step, MarkerTrace& m) {
  if (!tracker_.valid(i)) {
    kind_score_[i] = 0.f;
    evidence_margin_[i] = 0.f;
    return;
  }
  // this frame's chosen line, also where the tracker's gate kept its points out (the tracked
  // shape lags a turning vehicle): the lane model gates it against its own prediction
  if (chosen >= 0) m.measured.assign(evidence_[i].begin(), evidence_[i].end());
  // a side seen in one frame only is not carried on: one frame's stray line is no boundary
  if (tracker_.age(i) > 0 && !tracker_.established(i)) return;
  if (tracker_.age(i) == 0 && chosen >= 0) voteKind(i, (*in.candidates)[i][chosen], m);
  // reported: the side's model over its evidence's range, within the plane's range; a road
  // edge seen this frame where it was seen (a kerb need not run parallel to the paint, nor
  // be straight: it curves into a corner, it steps at a driveway)
  samples_.clear();
  if (kind_score_[i] < 0.f && tracker_.age(i) == 0 && chosen >= 0)
    measuredEdge((*in.candidates)[i][chosen].road, frame, samples_);
  // (a road edge not as far beyond where it was seen as paint: kerbs end at driveways and
  // intersections)
  if (samples_.empty())
    tracker_.sample(i, frame, sample_step, samples_,
                    kind_score_[i] < 0.f ? LaneTracker::kEdgeExtrapolation
                                         : LaneTracker::kPaintExtrapolation);
  for (const auto& q : samples_) {
    if (!(q.z() > 0.1f)) continue;
    if (frame.toRoad(q.cast<double>()).x() > std::max(road_range, 1.0)) break;
    m.points.push_back(q);
    m.pixels.emplace_back(in.K.project(q));
    m.scores.push_back(m.peak_score);
  }
  m.num_valid_points = static_cast<int>(m.points.size());
  m.found = m.num_valid_points >= params_.min_marker_points;
  if (!m.found) return;
  m.kind = kind_score_[i] >= 0.f ? BoundaryKind::kPaint : BoundaryKind::kRoadEdge;
  const double support = 1.0 - std::exp(-tracker_.frames(i) / kConfidenceFrames);
  const double fresh = std::pow(kConfidenceAgeDecay, tracker_.age(i));
  m.confidence = static_cast<float>(support * fresh * (0.5 + 0.5 * evidence_margin_[i]));
}

void LaneFitter::voteKind(int i, const BoundaryCandidate& c, MarkerTrace& m) {
  // the side's kind: a decaying vote of its classified evidence (a new side starts over)
  const float vote = c.evidence.kind == BoundaryKind::kPaint ? 1.f : -1.f;
  const float w = 0.25f + c.evidence.margin;
  if (tracker_.frames(i) <= 1) {
    kind_score_[i] = vote * w;
    evidence_margin_[i] = c.evidence.margin;
  } else {
    kind_score_[i] = kKindMemory * kind_score_[i] + vote * w;
    evidence_margin_[i] = kKindMemory * evidence_margin_[i] + (1.f - kKindMemory) * c.evidence.margin;
  }
  m.seed = c.trace.seed;
  m.seed_point = c.trace.seed_point;
  m.peak_score = c.trace.peak_score;
  m.angle = c.trace.angle;
  m.angle_valid = c.trace.angle_valid;
}

void LaneFitter::reportOuterLines(const LaneFitInput& in, const RoadFrame& frame,
                                  const std::array<int, 2>& chosen, Result& result) const {
  // Lines beyond the ego boundaries: the next lanes' and the road edges, as seen this frame (the
  // nearest of each).
  double outer_offset[4] = {0.0, 0.0, 0.0, 0.0};
  for (int i = 0; i < 2; ++i) {
    if (chosen[i] < 0) continue;
    const std::vector<BoundaryCandidate>& cands = (*in.candidates)[i];
    const double ego = std::fabs(cands[chosen[i]].lateral);
    for (int k = 0; k < in.counts[i]; ++k) {
      const BoundaryCandidate& c = cands[k];
      if (k == chosen[i] || !c.usable || std::fabs(c.lateral) < ego + kNextLaneMin) continue;
      const bool edge = c.evidence.kind == BoundaryKind::kRoadEdge;
      const int slot = edge ? (i == 0 ? kRoadEdgeLeft : kRoadEdgeRight)
                            : (i == 0 ? kNextLeft : kNextRight);
      MarkerTrace& m = result.outer[slot];
      if (m.found && std::fabs(outer_offset[slot]) <= std::fabs(c.lateral)) continue;
      outer_offset[slot] = c.lateral;
      m.pixels.clear();
      m.points.clear();
      m.scores.clear();
      for (const auto& q : c.road) {
        const Eigen::Vector3f P = frame.toCamera(q.x(), q.y()).cast<float>();
        m.points.push_back(P);
        m.pixels.emplace_back(in.K.project(P));
        m.scores.push_back(c.trace.peak_score);
      }
      m.num_valid_points = static_cast<int>(m.points.size());
      m.found = true;
      m.kind = c.evidence.kind;
      m.confidence = 0.5f * c.evidence.margin;  // one frame's evidence
      m.peak_score = c.trace.peak_score;
      m.seed = c.trace.seed;
      m.seed_point = c.trace.seed_point;
      m.angle = c.trace.angle;
      m.angle_valid = c.trace.angle_valid;
    }
  }
}

void LaneFitter::dropImplausibleWidth(Result& result) const {
  // Two sides closer or farther apart than any lane: the less confident one is not reported.
  const Params& p = params_;
  if (!result.left.found || !result.right.found || !(p.lane_width_max > 0.0)) return;
  const double width = tracker_.lateral(0, kWidthProbe) - tracker_.lateral(1, kWidthProbe);
  if (width >= p.lane_width_min && width <= p.lane_width_max) return;
  MarkerTrace& weaker = result.left.confidence < result.right.confidence ? result.left
                                                                         : result.right;
  weaker.found = false;
  weaker.confidence = 0.0f;
}

void LaneFitter::requirePaint(Result& result) const {
  // A lane is marked by paint: a road edge bounds it where one side has none (a kerb, rails,
  // an unpainted edge beside a painted line), but road edges alone (a street without markings,
  // parked cars and kerbs) are no lane.
  const bool paint = (result.left.found && result.left.kind == BoundaryKind::kPaint) ||
                     (result.right.found && result.right.kind == BoundaryKind::kPaint);
  if (paint) return;
  for (MarkerTrace* m : {&result.left, &result.right}) {
    m->found = false;
    m->confidence = 0.0f;
  }
  for (MarkerTrace& m : result.outer) clearTrace(m);
}

void LaneFitter::measuredEdge(const std::vector<Eigen::Vector2d>& road, const RoadFrame& frame,
                              std::vector<Eigen::Vector3f>& out) const {
  out.clear();
  if (road.size() < static_cast<size_t>(kMinEdgePoints)) return;
  // a robust quadratic lateral(forward) of its own points (a kerb curves into a corner): least
  // squares, then refits on the points within a narrowing band (leaves in the gutter, a drain,
  // a missing row pull single points or short stretches off the edge)
  Eigen::Vector3d coef = Eigen::Vector3d::Zero();
  bool have = false;
  double near = 0.0, far = 0.0;
  for (int pass = 0; pass < 4; ++pass) {
    const double band = pass == 0 ? 1e9 : (pass == 1 ? 2.0 * kEdgeSpike : kEdgeSpike);
    Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
    Eigen::Vector3d r = Eigen::Vector3d::Zero();
    int used = 0;
    near = 1e9;
    far = -1e9;
    for (const auto& q : road) {
      if (q.x() < kNearestForward) continue;
      const double s = q.x() / 20.0;  // scaled: well conditioned
      const Eigen::Vector3d phi(1.0, s, s * s);
      if (have && std::fabs(q.y() - coef.dot(phi)) > band) continue;
      N.noalias() += phi * phi.transpose();
      r += phi * q.y();
      near = std::min(near, q.x());
      far = std::max(far, q.x());
      ++used;
    }
    if (used < kMinEdgePoints) return;
    N(2, 2) += 1e-6;  // a short edge: the curvature term stays small
    coef = N.ldlt().solve(r);
    have = true;
  }
  // sampled over its inliers' range, uniformly in 1/f (like LaneTracker::sample())
  near = std::max(near, kNearestForward);
  if (!(far > near)) return;
  const int n = kMaxEdgeSamples;
  for (int k = 0; k < n; ++k) {
    const double f = 1.0 / (1.0 / near + (1.0 / far - 1.0 / near) * k / (n - 1));
    const double s = f / 20.0;
    out.push_back(frame.toCamera(f, coef[0] + coef[1] * s + coef[2] * s * s).cast<float>());
  }
}

}  // namespace rgbd_lane_detector
