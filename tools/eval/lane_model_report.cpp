#include "rgbd_lane_detector_tools/lane_model_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rgbd_lane_detector {
namespace tools {
namespace {

std::string num(const char* f, double v) {
  if (!std::isfinite(v)) return std::isinf(v) ? "inf" : "-";
  char buf[64];
  std::snprintf(buf, sizeof(buf), f, v);
  return buf;
}

// "median / p95 (n)" of @p v, "-" when empty.
std::string spread(const std::vector<double>& v, const char* f, double scale = 1.0) {
  if (v.empty()) return "-";
  return num(f, scale * percentile(v, 50)) + " / " + num(f, scale * percentile(v, 95)) + " (" +
         std::to_string(v.size()) + ")";
}

// "value (n)" of a percentage.
std::string percentCell(double v, int n) {
  return n > 0 ? num("%.1f", v) + " (" + std::to_string(n) + ")" : "-";
}

const char* pass(bool ok) { return ok ? "yes" : "**no**"; }

// The (confidence, correct) samples at or above @p c: count and % correct.
void above(const std::vector<std::pair<float, bool>>& samples, double c, int& n, double& pct) {
  int correct = 0;
  n = 0;
  for (const auto& s : samples) {
    if (s.first < c) continue;
    ++n;
    correct += s.second;
  }
  pct = n > 0 ? 100.0 * correct / n : std::nan("");
}

}  // namespace

LaneModelReport::LaneModelReport(std::ostream* csv, std::string curve_sequence,
                                 std::string lane_change_sequence)
    : csv_(csv), curve_(std::move(curve_sequence)), lane_change_(std::move(lane_change_sequence)) {
  if (csv_)
    *csv_ << "sequence,mode,frame,position,reported,truth,matched,overlap,mean_distance,"
             "worst_distance,confidence,evidence,age,lateral_std,x_min,x_max,kind,true_kind,colour,"
             "true_colour,correct\n";
}

void LaneModelReport::add(const std::string& sequence, const std::string& mode, int frame,
                          const LaneModelScore& score) {
  auto it = std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) {
    return e.sequence == sequence && e.mode == mode;
  });
  if (it == entries_.end()) {
    entries_.push_back(Entry{sequence, mode, LaneModelSummary()});
    entries_.back().summary.worst_limit = targets.lane_change_worst;
    it = entries_.end() - 1;
  }
  it->summary.add(score, frame);
  if (!csv_) return;
  for (int p = 0; p < kNumBoundaryPositions; ++p) {
    const PositionScore& s = score.positions[p];
    if (!s.reported && !s.truth) continue;
    *csv_ << sequence << "," << mode << "," << frame << ","
          << boundaryPositionName(static_cast<BoundaryPosition>(p)) << "," << s.reported << ","
          << s.truth << "," << s.matched << "," << num("%.2f", s.overlap) << ","
          << num("%.4f", s.mean_distance) << "," << num("%.4f", s.worst_distance) << ","
          << (s.reported ? num("%.4f", s.confidence) : "") << ","
          << (s.reported ? num("%.4f", s.evidence) : "") << ","
          << (s.reported ? std::to_string(s.age) : "") << ","
          << (s.reported ? num("%.4f", s.lateral_std) : "") << ","
          << (s.reported ? num("%.2f", s.x_min) : "") << ","
          << (s.reported ? num("%.2f", s.x_max) : "") << ","
          << (s.reported ? lineKindName(s.kind) : "") << ","
          << (s.truth ? lineKindName(s.true_kind) : "") << ","
          << (s.reported ? lineColourName(s.colour) : "") << ","
          << (s.truth ? lineColourName(s.true_colour) : "") << "," << s.correct << "\n";
  }
}

std::vector<std::string> LaneModelReport::modes() const {
  std::vector<std::string> m;
  for (const auto& e : entries_)
    if (std::find(m.begin(), m.end(), e.mode) == m.end()) m.push_back(e.mode);
  return m;
}

LaneModelSummary LaneModelReport::pooled(const std::string& mode) const {
  LaneModelSummary s;
  s.worst_limit = targets.lane_change_worst;
  for (const auto& e : entries_)
    if (e.mode == mode) s.merge(e.summary);
  return s;
}

const LaneModelSummary* LaneModelReport::find(const std::string& sequence,
                                              const std::string& mode) const {
  for (const auto& e : entries_)
    if (e.sequence == sequence && e.mode == mode) return &e.summary;
  return nullptr;
}

void LaneModelReport::writeMarkdown(std::ostream& md, const std::string& suffix) const {
  const std::vector<int> ego = egoPositions(), all = allPositions();
  const std::vector<std::string> ms = modes();

  md << "#### Lane model: lateral error of the ego boundaries" << suffix << "\n\n"
     << "`Result::lane_model` (what `lane_model` publishes) in base_link against the true "
        "boundary of the same label (`lane_model_scoring.h`): median / 95th percentile (m) and "
        "count of |y_model(x) - y_true(x)| at 5, 10, 20 and 40 m ahead, over every published "
        "ego boundary whose range [x_min, x_max] and truth contain that x.\n\n"
     << "| sequence | mode | boundary | 5 m | 10 m | 20 m | 40 m |\n"
     << "| --- | --- | --- | ---: | ---: | ---: | ---: |\n";
  auto lateralRow = [&](const std::string& seq, const std::string& mode,
                        const LaneModelSummary& s, const std::vector<int>& positions,
                        const std::string& label) {
    md << "| " << seq << " | " << mode << " | " << label;
    for (int k = 0; k < kNumLateralDistances; ++k)
      md << " | " << spread(s.lateralErrors(positions, k), "%.3f");
    md << " |\n";
  };
  for (const auto& e : entries_)
    for (int p : ego)
      lateralRow(e.sequence, e.mode, e.summary, {p},
                 boundaryPositionName(static_cast<BoundaryPosition>(p)));
  for (const auto& mode : ms) {
    const LaneModelSummary s = pooled(mode);
    lateralRow("**all**", mode, s, {0}, "ego_left");
    lateralRow("**all**", mode, s, {1}, "ego_right");
    lateralRow("**all**", mode, s, ego, "**both**");
  }

  md << "\n#### Lane model: ego lane geometry" << suffix << "\n\n"
     << "Frames with a valid model (an ego boundary known) and the absolute errors of its width, "
        "lateral offset, heading and curvature at x = 0 against the true lane model: median / "
        "95th percentile (count).\n\n"
     << "| sequence | mode | model % | width (m) | offset (m) | heading (mrad) | curvature "
        "(1e-4/m) |\n| --- | --- | ---: | ---: | ---: | ---: | ---: |\n";
  auto geometryRow = [&](const std::string& seq, const std::string& mode,
                         const LaneModelSummary& s) {
    md << "| " << seq << " | " << mode << " | "
       << num("%.1f", s.frames ? 100.0 * s.model_frames / s.frames : NAN) << " | "
       << spread(s.width, "%.3f") << " | " << spread(s.offset, "%.3f") << " | "
       << spread(s.heading, "%.1f", 1e3) << " | " << spread(s.curvature, "%.2f", 1e4) << " |\n";
  };
  for (const auto& e : entries_) geometryRow(e.sequence, e.mode, e.summary);
  for (const auto& mode : ms) geometryRow("**all**", mode, pooled(mode));

  md << "\n#### Lane model: F1, kind and colour" << suffix << "\n\n"
     << "A published boundary matches the true boundary of its label when its mean lateral "
        "distance, sampled every 0.5 m over the truth's range intersected with its own, is below "
        "0.30 m, the two overlapping over 5 m or all of the shorter one (ONCE-3DLanes style, with "
        "the label). Per position TP / FP / FN "
        "(FN: a true boundary of that label without a match, seen by the camera or not); "
        "precision, recall and F1 over all six positions. Kind (solid, dashed, road edge; a "
        "double line is solid) and colour (white, yellow; paint only) accuracy over the matched "
        "boundaries, % (count).\n\n"
     << "| sequence | mode | ego_left | ego_right | next_left | next_right | road_edge_left | "
        "road_edge_right | precision % | recall % | F1 % | kind % | colour % |\n"
     << "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | "
        "---: |\n";
  auto f1Row = [&](const std::string& seq, const std::string& mode, const LaneModelSummary& s) {
    md << "| " << seq << " | " << mode;
    for (int p : all)
      md << " | " << s.tp[p] << " / " << s.fp[p] << " / " << s.fn[p];
    md << " | " << num("%.1f", 100.0 * s.precision(all)) << " | "
       << num("%.1f", 100.0 * s.recall(all)) << " | " << num("%.1f", 100.0 * s.f1(all)) << " | "
       << percentCell(s.kindAccuracy(all), s.kindSamples(all)) << " | "
       << percentCell(s.colourAccuracy(all), s.colourSamples(all)) << " |\n";
  };
  for (const auto& e : entries_) f1Row(e.sequence, e.mode, e.summary);
  for (const auto& mode : ms) f1Row("**all**", mode, pooled(mode));

  md << "\nKind of the matched boundaries, all sequences (rows: truth, columns: published):\n\n"
     << "| mode | truth | unknown | solid | dashed | road_edge |\n"
     << "| --- | --- | ---: | ---: | ---: | ---: |\n";
  for (const auto& mode : ms) {
    const LaneModelSummary s = pooled(mode);
    for (int t = 1; t < 4; ++t) {
      md << "| " << mode << " | " << lineKindName(static_cast<LineKind>(t));
      for (int r = 0; r < 4; ++r) md << " | " << s.kind_confusion[t][r];
      md << " |\n";
    }
  }

  md << "\n#### Lane model: the farthest published boundary" << suffix << "\n\n"
     << "Per sequence, the largest lateral distance of any published boundary from the true "
        "boundary with its label, over the range both cover (inf: a label the frame has no "
        "true boundary for), the frame and position where it happened, and the frames that "
        "publish a boundary farther than " << num("%.2f", targets.lane_change_worst)
     << " m.\n\n"
     << "| sequence | mode | frames | farthest (m) | frame | position | frames beyond "
     << num("%.1f", targets.lane_change_worst) << " m |\n"
     << "| --- | --- | ---: | ---: | ---: | --- | ---: |\n";
  for (const auto& e : entries_) {
    const LaneModelSummary& s = e.summary;
    md << "| " << e.sequence << " | " << e.mode << " | " << s.frames << " | "
       << (s.worst_frame >= 0 ? num("%.3f", s.worst) : "-") << " | "
       << (s.worst_frame >= 0 ? std::to_string(s.worst_frame) : "-") << " | "
       << (s.worst_position >= 0
               ? boundaryPositionName(static_cast<BoundaryPosition>(s.worst_position))
               : "-")
       << " | " << s.frames_beyond_limit << " |\n";
  }

  md << "\n#### Lane model: confidence calibration" << suffix << "\n\n"
     << "Reliability of `LaneBoundary.confidence`, every published boundary of every sequence "
        "pooled: per confidence bin the boundaries, their mean confidence and the share that is "
        "correct (matched as above, with the true kind and, for paint, the true colour). ECE: the "
        "count-weighted mean |confidence - correct|.\n\n";
  for (const auto& mode : ms) {
    const LaneModelSummary s = pooled(mode);
    const std::vector<ReliabilityBin> table = reliabilityTable(s.calibration);
    md << "| mode | confidence | boundaries | mean confidence | correct % |\n"
       << "| --- | --- | ---: | ---: | ---: |\n";
    for (const auto& b : table)
      md << "| " << mode << " | " << num("%.2f", b.lo) << "-" << num("%.2f", b.hi) << " | "
         << b.count << " | " << num("%.3f", b.meanConfidence()) << " | "
         << num("%.1f", 100.0 * b.fractionCorrect()) << " |\n";
    int n = 0;
    double pct = 0.0;
    above(s.calibration, targets.confidence, n, pct);
    md << "\n" << mode << ": " << s.calibration.size() << " boundaries, ECE "
       << num("%.3f", expectedCalibrationError(table)) << "; confidence >= "
       << num("%.2f", targets.confidence) << ": " << n << " boundaries, " << num("%.1f", pct)
       << "% correct.\n\n";
  }
  for (const auto& mode : ms) writeMustShow(md, mode, suffix);
}

void LaneModelReport::writeMustShow(std::ostream& md, const std::string& mode,
                                    const std::string& suffix) const {
  const LaneModelSummary s = pooled(mode);
  const std::vector<int> ego = egoPositions(), all = allPositions();
  const std::vector<double> e10 = s.lateralErrors(ego, 1), e40 = s.lateralErrors(ego, 3);
  const double med10 = percentile(e10, 50), p95_10 = percentile(e10, 95);
  const double med40 = percentile(e40, 50);
  const LaneModelSummary* curve = find(curve_, mode);
  const double curvature = curve ? percentile(curve->curvature, 50) : NAN;
  const double kind = s.kindAccuracy(all), colour = s.colourAccuracy(all);
  const LaneModelSummary* change = find(lane_change_, mode);
  int n = 0;
  double pct = 0.0;
  above(s.calibration, targets.confidence, n, pct);
  md << "#### Lane model: must-show figures" << suffix << ", " << mode << " mode\n\n"
     << "| figure | target | measured | met |\n| --- | --- | ---: | --- |\n"
     << "| ego boundaries' lateral error at 10 m, median (all sequences) | <= "
     << num("%.2f", targets.median_10) << " m | " << num("%.3f", med10) << " | "
     << pass(med10 <= targets.median_10) << " |\n"
     << "| ego boundaries' lateral error at 10 m, 95th percentile | <= "
     << num("%.2f", targets.p95_10) << " m | " << num("%.3f", p95_10) << " | "
     << pass(p95_10 <= targets.p95_10) << " |\n"
     << "| ego boundaries' lateral error at 40 m, median | <= " << num("%.2f", targets.median_40)
     << " m | " << num("%.3f", med40) << " | " << pass(med40 <= targets.median_40) << " |\n"
     << "| curvature error on `" << curve_ << "`, median | <= "
     << num("%.0e", targets.curvature) << " 1/m | " << num("%.2e", curvature) << " | "
     << pass(curvature <= targets.curvature) << " |\n"
     << "| kind accuracy of matched boundaries | >= " << num("%.0f", targets.kind) << "% | "
     << num("%.1f", kind) << "% | " << pass(kind >= targets.kind) << " |\n"
     << "| colour accuracy of matched paint boundaries | >= " << num("%.0f", targets.colour)
     << "% | " << num("%.1f", colour) << "% | " << pass(colour >= targets.colour) << " |\n"
     << "| `" << lane_change_ << "`: farthest published boundary from its true one | <= "
     << num("%.1f", targets.lane_change_worst) << " m | "
     << (change && change->worst_frame >= 0 ? num("%.3f", change->worst) : "-") << " | "
     << pass(change && change->frames > 0 && change->frames_beyond_limit == 0) << " |\n"
     << "| boundaries with confidence >= " << num("%.1f", targets.confidence)
     << " that are correct | >= " << num("%.0f", targets.confidence_correct) << "% | "
     << num("%.1f", pct) << "% (" << n << ") | " << pass(n > 0 && pct >= targets.confidence_correct)
     << " |\n\n";
}

}  // namespace tools
}  // namespace rgbd_lane_detector
