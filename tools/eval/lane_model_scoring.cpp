#include "rgbd_lane_detector_tools/lane_model_scoring.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rgbd_lane_detector {
namespace tools {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTruthGap = 2.0;  // m: the truth is sampled every 0.5 m; a longer step is a gap

int sumOver(const std::array<int, kNumBoundaryPositions>& a, const std::vector<int>& positions) {
  int s = 0;
  for (int p : positions) s += a[p];
  return s;
}

double ratio(int a, int b) { return b > 0 ? static_cast<double>(a) / b : kNaN; }

}  // namespace

LineKind trueLineKind(const TrueBoundary& b) {
  if (b.kind == BoundaryKind::kRoadEdge) return LineKind::kRoadEdge;
  switch (b.style) {
    case LineStyle::kSolid:
    case LineStyle::kDoubleSolid:
      return LineKind::kSolid;
    case LineStyle::kDashed:
      return LineKind::kDashed;
    case LineStyle::kRoadEdge:
      return LineKind::kRoadEdge;
    default:
      return LineKind::kUnknown;
  }
}

rgbd_lane_detector::LineColour trueLineColour(const TrueBoundary& b) {
  if (b.kind != BoundaryKind::kPaint) return rgbd_lane_detector::LineColour::kUnknown;
  switch (b.colour) {
    case LineColour::kWhite:
      return rgbd_lane_detector::LineColour::kWhite;
    case LineColour::kYellow:
      return rgbd_lane_detector::LineColour::kYellow;
    default:
      return rgbd_lane_detector::LineColour::kUnknown;
  }
}

PositionScore::PositionScore() : mean_distance(kNaN), worst_distance(kNaN) {
  std::fill(std::begin(lateral_error), std::end(lateral_error), kNaN);
}

LaneModelScore::LaneModelScore()
    : width_error(kNaN), offset_error(kNaN), heading_error(kNaN), curvature_error(kNaN) {}

LaneModelScore scoreLaneModel(const LaneModelEstimate& model, const FrameTruth& truth,
                              const LaneModelRules& rules) {
  LaneModelScore s;
  s.model_valid = model.valid;
  s.truth_valid = truth.has_vehicle_frame && truth.lane.valid;
  if (!truth.has_vehicle_frame) return s;
  if (model.valid && s.truth_valid) {
    s.width_error = std::fabs(model.width - truth.lane.width);
    s.offset_error = std::fabs(model.offset - truth.lane.offset);
    s.heading_error = std::fabs(model.heading_error - truth.lane.heading);
    s.curvature_error = std::fabs(model.curvature - truth.lane.curvature);
  }
  for (int p = 0; p < kNumBoundaryPositions; ++p) {
    PositionScore& ps = s.positions[p];
    const TrueBoundary* t = truth.boundary(static_cast<BoundaryLabel>(p));
    const LateralLine line = t ? LateralLine(t->points_base, kTruthGap) : LateralLine();
    ps.truth = t != nullptr && !line.empty();
    if (ps.truth) {
      ps.true_kind = trueLineKind(*t);
      ps.true_colour = trueLineColour(*t);
    }
    const LaneBoundaryModel& b = model.boundaries[p];
    ps.reported = model.valid && b.valid;
    if (!ps.reported) continue;
    ps.kind = b.kind;
    ps.colour = b.colour;
    ps.confidence = b.confidence;
    ps.evidence = b.evidence;
    ps.age = b.age;
    ps.lateral_std = b.lateral_std;
    ps.x_min = b.x_min;
    ps.x_max = b.x_max;
    if (!ps.truth) {
      ps.worst_distance = kInf;
      continue;
    }
    // samples every step over the truth's range intersected with the published one, where the
    // truth exists (not in its gaps); the overlap is the length they stand for
    const double lo = std::max(b.x_min, line.xMin()), hi = std::min(b.x_max, line.xMax());
    double sum = 0.0, worst = 0.0;
    int n = 0, samples = 0;
    for (double x = lo; x <= hi + 1e-9; x += rules.step) {
      ++samples;
      const double d = std::fabs(b.lateral(x) - line.at(std::min(x, hi)));
      if (!std::isfinite(d)) continue;
      sum += d;
      worst = std::max(worst, d);
      ++n;
    }
    ps.overlap = samples > 1 ? (hi - lo) * n / samples : 0.0;
    if (n > 0) {
      ps.mean_distance = sum / n;
      ps.worst_distance = worst;
    }
    // the overlap must cover min_overlap, or all of the shorter of the two lines
    const double needed =
        std::min({rules.min_overlap, line.length(), b.x_max - b.x_min});
    ps.matched = n > 1 && ps.overlap >= needed - rules.step - 1e-9 &&
                 ps.mean_distance < rules.match_distance;
    ps.correct = ps.matched && ps.kind == ps.true_kind &&
                 (ps.true_colour == rgbd_lane_detector::LineColour::kUnknown ||
                  ps.colour == ps.true_colour);
    for (int k = 0; k < kNumLateralDistances; ++k) {
      const double x = kLateralDistances[k];
      if (x < b.x_min || x > b.x_max) continue;
      ps.lateral_error[k] = std::fabs(b.lateral(x) - line.at(x));  // NaN beyond the truth
    }
  }
  return s;
}

double ReliabilityBin::meanConfidence() const {
  return count > 0 ? sum_confidence / count : kNaN;
}
double ReliabilityBin::fractionCorrect() const { return ratio(correct, count); }

const std::vector<double>& defaultReliabilityEdges() {
  static const std::vector<double> edges = {0.0, 0.5, 0.7, 0.8, 0.85, 0.9, 0.95, 0.98, 0.99, 1.0};
  return edges;
}

std::vector<ReliabilityBin> reliabilityTable(const std::vector<std::pair<float, bool>>& samples,
                                             const std::vector<double>& edges) {
  if (edges.size() < 2) return {};
  const int bins = static_cast<int>(edges.size()) - 1;
  std::vector<ReliabilityBin> table(bins);
  for (int i = 0; i < bins; ++i) {
    table[i].lo = edges[i];
    table[i].hi = edges[i + 1];
  }
  for (const auto& s : samples) {
    const double c = std::min(edges.back(), std::max(edges.front(), static_cast<double>(s.first)));
    const int i = static_cast<int>(std::upper_bound(edges.begin() + 1, edges.end() - 1, c) -
                                   (edges.begin() + 1));
    ++table[i].count;
    table[i].correct += s.second;
    table[i].sum_confidence += c;
  }
  return table;
}

double expectedCalibrationError(const std::vector<ReliabilityBin>& table) {
  int total = 0;
  double sum = 0.0;
  for (const auto& b : table) {
    if (b.count == 0) continue;
    total += b.count;
    sum += b.count * std::fabs(b.meanConfidence() - b.fractionCorrect());
  }
  return total > 0 ? sum / total : kNaN;
}

void LaneModelSummary::add(const LaneModelScore& s, int frame) {
  ++frames;
  if (s.model_valid) ++model_frames;
  if (std::isfinite(s.width_error)) {
    width.push_back(s.width_error);
    offset.push_back(s.offset_error);
    heading.push_back(s.heading_error);
    curvature.push_back(s.curvature_error);
  }
  bool beyond = false;
  for (int p = 0; p < kNumBoundaryPositions; ++p) {
    const PositionScore& ps = s.positions[p];
    if (ps.reported) {
      ps.matched ? ++tp[p] : ++fp[p];
      calibration.emplace_back(ps.confidence, ps.correct);
      for (int k = 0; k < kNumLateralDistances; ++k)
        if (std::isfinite(ps.lateral_error[k])) lateral[p][k].push_back(ps.lateral_error[k]);
      if (!std::isnan(ps.worst_distance) && (worst_frame < 0 || ps.worst_distance > worst)) {
        worst = ps.worst_distance;
        worst_frame = frame;
        worst_position = p;
      }
      beyond = beyond || ps.worst_distance > worst_limit;
    }
    if (ps.truth && !ps.matched) ++fn[p];
    if (ps.matched) {
      ++kind_total[p];
      kind_correct[p] += ps.kind == ps.true_kind;
      ++kind_confusion[static_cast<int>(ps.true_kind)][static_cast<int>(ps.kind)];
      if (ps.true_colour != rgbd_lane_detector::LineColour::kUnknown) {
        ++colour_total[p];
        colour_correct[p] += ps.colour == ps.true_colour;
      }
    }
  }
  frames_beyond_limit += beyond;
}

void LaneModelSummary::merge(const LaneModelSummary& o) {
  frames += o.frames;
  model_frames += o.model_frames;
  for (int p = 0; p < kNumBoundaryPositions; ++p) {
    for (int k = 0; k < kNumLateralDistances; ++k)
      lateral[p][k].insert(lateral[p][k].end(), o.lateral[p][k].begin(), o.lateral[p][k].end());
    tp[p] += o.tp[p];
    fp[p] += o.fp[p];
    fn[p] += o.fn[p];
    kind_total[p] += o.kind_total[p];
    kind_correct[p] += o.kind_correct[p];
    colour_total[p] += o.colour_total[p];
    colour_correct[p] += o.colour_correct[p];
  }
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) kind_confusion[i][j] += o.kind_confusion[i][j];
  const auto append = [](std::vector<double>& to, const std::vector<double>& from) {
    to.insert(to.end(), from.begin(), from.end());
  };
  append(width, o.width);
  append(offset, o.offset);
  append(heading, o.heading);
  append(curvature, o.curvature);
  calibration.insert(calibration.end(), o.calibration.begin(), o.calibration.end());
  if (o.worst_frame >= 0 && (worst_frame < 0 || o.worst > worst)) {
    worst = o.worst;
    worst_frame = o.worst_frame;
    worst_position = o.worst_position;
  }
  frames_beyond_limit += o.frames_beyond_limit;
}

double LaneModelSummary::precision(const std::vector<int>& positions) const {
  const int t = sumOver(tp, positions);
  return ratio(t, t + sumOver(fp, positions));
}

double LaneModelSummary::recall(const std::vector<int>& positions) const {
  const int t = sumOver(tp, positions);
  return ratio(t, t + sumOver(fn, positions));
}

double LaneModelSummary::f1(const std::vector<int>& positions) const {
  const double p = precision(positions), r = recall(positions);
  if (!std::isfinite(p) || !std::isfinite(r)) return kNaN;
  return p + r > 0 ? 2.0 * p * r / (p + r) : 0.0;
}

double LaneModelSummary::kindAccuracy(const std::vector<int>& positions) const {
  return 100.0 * ratio(sumOver(kind_correct, positions), sumOver(kind_total, positions));
}

double LaneModelSummary::colourAccuracy(const std::vector<int>& positions) const {
  return 100.0 * ratio(sumOver(colour_correct, positions), sumOver(colour_total, positions));
}

int LaneModelSummary::kindSamples(const std::vector<int>& positions) const {
  return sumOver(kind_total, positions);
}

int LaneModelSummary::colourSamples(const std::vector<int>& positions) const {
  return sumOver(colour_total, positions);
}

std::vector<double> LaneModelSummary::lateralErrors(const std::vector<int>& positions,
                                                    int k) const {
  std::vector<double> v;
  for (int p : positions) v.insert(v.end(), lateral[p][k].begin(), lateral[p][k].end());
  return v;
}

std::vector<int> allPositions() {
  std::vector<int> v(kNumBoundaryPositions);
  for (int p = 0; p < kNumBoundaryPositions; ++p) v[p] = p;
  return v;
}

std::vector<int> egoPositions() { return {0, 1}; }

}  // namespace tools
}  // namespace rgbd_lane_detector
