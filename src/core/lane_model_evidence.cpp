// The lane model's evidence: what is remembered of each boundary between frames (its
// sightings, kind and colour votes, scatter), the published model from the filter's state and
// that memory, the evidence score and its calibration, and the names of the model's enums.
#include "rgbd_lane_detector/lane_model.h"

#include <algorithm>
#include <cmath>

namespace rgbd_lane_detector {
namespace {

constexpr double kMaxStd = 0.10;        // m: a boundary is published where its lateral std is
                                        // at most this
constexpr double kRangeStep = 0.5;      // m: steps of the search for that range
constexpr float kMemory = 0.7f;         // per-frame weight of the past in the smoothed evidence
// The evidence score of a boundary (calibratedConfidence() is fitted on it): frames of evidence
// for a support of 1 - 1/e, and its factor per frame without evidence. Not the detector's
// confidence of a tracked side (lane_fitter.cpp), which decays faster.
constexpr double kEvidenceSupportFrames = 3.0;
constexpr double kEvidenceAgeDecay = 0.85;
constexpr double kResidualScale = 0.3;  // m
constexpr double kCoverageMargin = 0.3; // paint coverage this far from dashed_coverage: a clear kind
constexpr double kRangeScale = 10.0;    // m of published range for a span factor of 1 - 1/e

// The name of enum value @p i in @p names (indexed by value; static text), "unknown" outside.
template <size_t N>
const char* nameOf(const char* const (&names)[N], int i) {
  return i >= 0 && i < static_cast<int>(N) ? names[i] : "unknown";
}

}  // namespace

const char* boundaryPositionName(BoundaryPosition p) {
  static constexpr const char* kNames[] = {"ego_left",  "ego_right",      "next_left",
                                           "next_right", "road_edge_left", "road_edge_right"};
  return nameOf(kNames, static_cast<int>(p));
}

const char* lineKindName(LineKind k) {
  static constexpr const char* kNames[] = {"unknown", "solid", "dashed", "road_edge"};
  return nameOf(kNames, static_cast<int>(k));
}

const char* lineColourName(LineColour c) {
  static constexpr const char* kNames[] = {"unknown", "white", "yellow"};
  return nameOf(kNames, static_cast<int>(c));
}

float calibratedConfidence(float evidence) {
  // (evidence, P(correct)) knots: isotonic regression of "correct" on the evidence over every
  // boundary published on the evaluation sequences of seed 1 (make eval, improved mode), each
  // pooled block at its mean evidence with P = (correct + 1) / (boundaries + 2);
  // tools/scripts/fit_confidence.py build/eval/lane_model.csv prints this table.
  static constexpr float kKnots[][2] = {
      {0.0000f, 0.8551f}, {0.2495f, 0.8551f}, {0.4622f, 0.8936f}, {0.5606f, 0.9200f},
      {0.6199f, 0.9231f}, {0.6570f, 0.9490f}, {0.7118f, 0.9624f}, {0.7747f, 0.9841f},
      {0.8034f, 0.9852f}, {0.8172f, 0.9887f}, {0.8332f, 0.9924f}, {0.8785f, 0.9974f},
      {0.9428f, 0.9988f}, {0.9728f, 0.9997f}, {1.0000f, 0.9997f}};
  constexpr int n = sizeof(kKnots) / sizeof(kKnots[0]);
  if (!(evidence > kKnots[0][0])) return kKnots[0][1];
  for (int i = 1; i < n; ++i) {
    if (evidence > kKnots[i][0]) continue;
    const float w = (evidence - kKnots[i - 1][0]) / (kKnots[i][0] - kKnots[i - 1][0]);
    return kKnots[i - 1][1] + w * (kKnots[i][1] - kKnots[i - 1][1]);
  }
  return kKnots[n - 1][1];
}

float LaneModelFilter::evidence(const Memory& m, double range) const {
  // each factor in [0, 1]: seen in several frames, seen lately, where the model puts it, by a
  // confident detector, of a clear kind (a firm paint / edge vote; paint coverage away from the
  // dashed / solid threshold), over a useful range
  const double support = 1.0 - std::exp(-m.frames / kEvidenceSupportFrames);
  const double fresh = std::pow(kEvidenceAgeDecay, m.age);
  const double fit = std::exp(-m.residual / kResidualScale);
  const double detector = 0.5 + 0.5 * m.detector_confidence;
  double kind = std::min(1.0, static_cast<double>(std::fabs(m.edge_vote)));
  if (m.edge_vote <= 0.0f)
    kind *= m.coverage < 0.0f ? 0.5
                              : std::min(1.0, std::fabs(m.coverage - settings_.dashed_coverage) /
                                                  kCoverageMargin);
  const double span = 1.0 - std::exp(-range / kRangeScale);
  return static_cast<float>(support * fresh * fit * detector * (0.5 + 0.5 * kind) * span);
}

void LaneModelFilter::remember(const Track& t, int p, double residual) {
  Memory& m = memory_[p];
  const BoundaryObservation& o = *t.obs;
  const bool fresh = !known(p);
  m.frames = fresh ? 1 : m.frames + 1;
  m.age = 0;
  if (fresh) m.num_extents = m.next_extent = 0;
  m.extents[m.next_extent] = Eigen::Vector2d(t.x_min, t.x_max);
  m.next_extent = (m.next_extent + 1) % kRangeFrames;
  m.num_extents = std::min(m.num_extents + 1, kRangeFrames);
  const float edge = o.kind == BoundaryKind::kRoadEdge ? 1.0f : -1.0f;
  auto blend = [fresh](float old_value, float value) {
    if (value < 0.0f) return old_value;
    return fresh || old_value < 0.0f ? value : kMemory * old_value + (1.0f - kMemory) * value;
  };
  m.detector_confidence = fresh ? o.confidence
                                : kMemory * m.detector_confidence + (1.0f - kMemory) * o.confidence;
  m.coverage = blend(fresh ? -1.0f : m.coverage, o.paint_coverage);
  m.yellow = blend(fresh ? -1.0f : m.yellow, o.yellowness);
  m.edge_vote = fresh ? edge : kMemory * m.edge_vote + (1.0f - kMemory) * edge;
  m.residual = fresh ? residual : kMemory * m.residual + (1.0 - kMemory) * residual;
}

void LaneModelFilter::fill(LaneModelEstimate& model) const {
  model.valid = false;
  model.lane_changes = lane_changes_;
  for (auto& b : model.boundaries) b.valid = false;
  if (!initialised_) return;
  const bool left = known(0);
  const bool right = known(1);
  if (!left && !right) return;
  model.valid = true;
  model.width = x_[4];
  model.offset = -x_[0];
  model.heading_error = -std::atan(x_[1]);
  model.curvature = x_[2];
  model.curvature_rate = x_[3];
  model.centre = {x_[0], x_[1], 0.5 * x_[2], x_[3] / 6.0};
  model.x_min = 1e9;
  model.x_max = 0.0;
  for (int p = 0; p < kNumBoundaryPositions; ++p) {
    const Memory& m = memory_[p];
    LaneBoundaryModel& b = model.boundaries[p];
    b.position = static_cast<BoundaryPosition>(p);
    if (!known(p)) continue;
    if (!isEgo(p) && endsRoad(egoOf(p))) continue;
    // the range of its recent sightings (an ego boundary: of the ego lane's, both sides being
    // the one lane's edges), as far as the model knows it to kMaxStd
    b.x_min = 1e9;
    b.x_max = 0.0;
    for (int q : {p, isEgo(p) && known(1 - p) ? 1 - p : p})
      for (int i = 0; i < memory_[q].num_extents; ++i) {
        b.x_min = std::min(b.x_min, memory_[q].extents[i][0]);
        b.x_max = std::max(b.x_max, memory_[q].extents[i][1]);
      }
    while (b.x_max > b.x_min && lateralVariance(p, b.x_max) > kMaxStd * kMaxStd)
      b.x_max = std::max(b.x_min, b.x_max - kRangeStep);
    if (!(b.x_max > b.x_min) || lateralVariance(p, b.x_max) > kMaxStd * kMaxStd) continue;
    b.valid = true;
    const double c0 = predicted(p, 0.0);
    b.c = {c0, x_[1], 0.5 * x_[2], x_[3] / 6.0};
    if (m.edge_vote > 0.0f) {
      b.kind = LineKind::kRoadEdge;
      b.colour = LineColour::kUnknown;
    } else {
      b.kind = m.coverage < 0.0f ? LineKind::kUnknown
               : m.coverage < settings_.dashed_coverage ? LineKind::kDashed
                                                        : LineKind::kSolid;
      b.colour = m.yellow < 0.0f ? LineColour::kUnknown
                 : m.yellow >= settings_.yellowness ? LineColour::kYellow
                                                    : LineColour::kWhite;
    }
    b.lateral_std = static_cast<float>(std::sqrt(lateralVariance(p, b.x_max)));
    b.evidence = evidence(m, b.x_max - b.x_min);
    b.confidence = calibratedConfidence(b.evidence);
    b.age = m.age;
    if (isEgo(p)) {
      model.x_min = std::min(model.x_min, b.x_min);
      model.x_max = std::max(model.x_max, b.x_max);
    }
  }
  if (model.x_min > model.x_max) model.x_min = model.x_max = 0.0;
  model.valid = model.boundaries[0].valid || model.boundaries[1].valid;
}

}  // namespace rgbd_lane_detector
