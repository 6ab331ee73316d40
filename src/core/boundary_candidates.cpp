#include "rgbd_lane_detector/boundary_candidates.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "rgbd_lane_detector/fals_normals.h"
#include "rgbd_lane_detector/pca_refinement.h"
#include "rgbd_lane_detector/response_map.h"
#include "rgbd_lane_detector/sliding_box.h"

namespace rgbd_lane_detector {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kMaxSeedRetries = 4;   // seeds that are no marker looked past per line
constexpr double kFollowGap = 13.0;  // m: dash gaps a followed line crosses (9-12 m on motorways)
constexpr double kSeedReach = 0.3;   // m: a seed's paint is sought this far either side of it
constexpr double kSeedSpan = 1.0;    // m: the line through a seed starts this far either side
constexpr double kMaxSeedHeading = 25.0 * M_PI / 180.0;  // a followed seed's line runs ahead within this
constexpr double kStrokeGap = 1.0;     // m without paint between two dashes of a followed line
constexpr double kRowsPerGap = 2.5;    // ... and more than this many image rows' road
constexpr double kStrokeLength = 8.0;  // m: one stretch of paint this long is a line (no arrow)
constexpr double kDashGap = 2.0;       // m without a narrow band between two dashes of worn paint
constexpr int kMinDashes = 2;          // dashes that tell worn paint from a rail ...
constexpr double kMaxDashCoverage = 0.6;  // ... where they cover at most this share of the line
constexpr double kDashRange = 25.0;    // m ahead within which the dashes are counted
constexpr double kEdgeGap = 2.0;     // m: a followed road edge ends where it is not seen this long
constexpr double kEdgeReach = 0.3;   // m: a traced road edge this near a depth edge is the same
constexpr double kPredictedReach = 0.4;  // m: a predicted line's paint is sought this close

// Angle from the horizontal of a marker direction on the given side (deg).
double angleFromHorizontalDeg(double angle, bool left) {
  return (left ? M_PI - angle : angle) * 180.0 / M_PI;
}

// Keep a template angle inside the half-plane of its side, away from horizontal/vertical.
double clampAngle(double angle, bool left) {
  const double lo = 10.0 * M_PI / 180.0, hi = 88.0 * M_PI / 180.0;
  double from_h = left ? M_PI - angle : angle;  // angle from the horizontal
  from_h = std::min(std::max(from_h, lo), hi);
  return left ? M_PI - from_h : from_h;
}

// Road-plane coordinates (forward, lateral left) of the input pixel (u, v): its ray met with the
// road plane of @p f in @p frame; false where the ray does not meet the road ahead.
bool roadCoordinates(const CandidateFrame& f, const RoadFrame& frame, double u, double v,
                     Eigen::Vector2d& q) {
  const Eigen::Vector3d ray = f.K.ray(u, v);
  double z = 0.0;
  if (!rayPlaneDepth(*f.road, ray, z)) return false;
  q = frame.toRoad(ray * z);
  return true;
}

// More candidate slots, each with room for a line followed over kReservedRows image rows: a
// slot's trace is refilled every frame, by lines of any length, without growing.
void grow(std::vector<BoundaryCandidate>& cands, int size) {
  const size_t first = cands.size();
  cands.resize(size);
  for (size_t k = first; k < cands.size(); ++k) {
    MarkerTrace& m = cands[k].trace;
    m.pixels.reserve(BoundaryCandidateFinder::kReservedRows);
    m.points.reserve(BoundaryCandidateFinder::kReservedRows);
    m.scores.reserve(BoundaryCandidateFinder::kReservedRows);
  }
}

// A trace cut short by the classifier (cutAtObject: the line ends at a vehicle) keeps its
// points and scores for its pixels only.
void matchLengths(MarkerTrace& m) {
  if (m.points.size() > m.pixels.size()) m.points.resize(m.pixels.size());
  if (m.scores.size() > m.pixels.size()) m.scores.resize(m.pixels.size());
}

}  // namespace

void classifierInputOf(const CandidateFrame& f, const PlaneEstimate& plane, ClassifierInput& in) {
  in.colour = f.colour;
  in.format = f.format;
  in.grey = f.grey;
  in.grey_rows = f.grey_rows;
  in.K = f.K;
  in.points = f.points;
  in.filled = f.filled;
  in.scale_x = static_cast<double>(f.proc_size.width) / f.input_size.width;
  in.scale_y = static_cast<double>(f.proc_size.height) / f.input_size.height;
  in.plane = &plane;
  in.frame = RoadFrame::fromPlane(plane);
}

BoundaryCandidate& BoundaryCandidateFinder::next(int side) {
  std::vector<BoundaryCandidate>& cands = candidates_[side];
  if (static_cast<int>(cands.size()) <= counts_[side]) grow(cands, counts_[side] + 1);
  return cands[counts_[side]];
}

void BoundaryCandidateFinder::traceLines(const CandidateFrame& f, int side, cv::Mat& R) {
  // The side's best seed first (the paper's), then, with boundary_candidates > 1, the next best
  // seeds off the lines already traced: a kerb or a rail may outscore the paint next to it.
  const Clock::time_point t0 = Clock::now();
  double tracing_ms = 0.0;
  const bool left = side == 0;
  std::vector<BoundaryCandidate>& cands = candidates_[side];
  const int first = counts_[side];
  const int wanted = first + params_.boundary_candidates;
  if (static_cast<int>(cands.size()) < wanted) grow(cands, wanted);
  int& count = counts_[side];
  restore_.clear();
  for (int k = 0; k < first; ++k)  // lines traced on another map are not sought again
    excludeTrace(f, R, cands[k].trace, cv::Point(-1, -1));
  const int half = params_.template_size / 2;
  for (int attempt = 0; attempt <= wanted + kMaxSeedRetries && count < wanted; ++attempt) {
    cv::Point peak;
    float value = 0.f;
    findBestMatch(f, R, left, peak, value);
    const bool traceable = value > params_.trace_threshold;
    if (traceable && offRoad(f, peak)) {
      // road_gate: a best match on a surface that is not road is removed from R for good
      const cv::Rect box =
          cv::Rect(peak.x - half, peak.y - half, 2 * half + 1, 2 * half + 1) & f.roi;
      for (int y = box.y; y < box.y + box.height; ++y)  // (cv::Mat::setTo allocates)
        std::fill_n(R.ptr<float>(y) + box.x, box.width, 0.f);
      continue;
    }
    if (!traceable && count > first) break;
    if (!traceable && first > 0) break;  // a further map adds traceable lines only
    BoundaryCandidate& c = cands[count];
    MarkerTrace& m = c.trace;
    m.found = false;
    m.kind = BoundaryKind::kPaint;
    m.confidence = 0.0f;
    m.pixels.clear();
    m.scores.clear();
    m.points.clear();
    const PcaAngle pca = pcaMarkerAngle(R, peak, static_cast<float>(params_.pca_threshold),
                                        params_.template_size, pca_stack_, pca_visited_);
    m.angle_valid = pca.valid;
    m.angle = pca.valid ? clampAngle(pca.angle, left) : f.template_angle[side];
    // a seed whose marker direction no ego-lane marker can have (the road edge line of a
    // highway, a neighbour lane's marker) is not traced (named option, off in the paper mode)
    float peak_value = value;
    const bool implausible = pca.valid && !plausibleMarkerAngle(pca.angle, left);
    if (implausible) {
      peak_value = 0.f;
      m.angle_valid = false;  // (a short dash's blob: followFromSeed() may still find its line)
    }
    if (count > first && !(peak_value > params_.trace_threshold)) {
      excludeBox(f, R, peak);  // a further seed that is no marker: look past it
      continue;
    }
    const Clock::time_point tt = Clock::now();
    buildTrace(f, R, peak, peak_value, m.angle, m);
    if (implausible) m.peak_score = value;  // untraced, but a match worth following
    tracing_ms += std::chrono::duration<double, std::milli>(Clock::now() - tt).count();
    ++count;
    if (!traceable || count == wanted) break;
    excludeTrace(f, R, m, peak);
  }
  // the maps are published: put back what the search removed
  for (const auto& r : restore_) *r.first = r.second;
  tracing_ms_ += tracing_ms;
  pca_ms_ += std::chrono::duration<double, std::milli>(Clock::now() - t0).count() - tracing_ms;
}

void BoundaryCandidateFinder::excludeBox(const CandidateFrame& f, cv::Mat& R,
                                         const cv::Point& centre) {
  const int h = std::max(1, params_.template_size / 4);
  const cv::Rect box = cv::Rect(centre.x - h, centre.y - h, 2 * h + 1, 2 * h + 1) & f.roi;
  for (int y = box.y; y < box.y + box.height; ++y) {
    float* r = R.ptr<float>(y);
    for (int x = box.x; x < box.x + box.width; ++x) {
      if (r[x] == 0.f) continue;
      restore_.emplace_back(r + x, r[x]);
      r[x] = 0.f;
    }
  }
}

void BoundaryCandidateFinder::excludeTrace(const CandidateFrame& f, cv::Mat& R,
                                           const MarkerTrace& trace, const cv::Point& peak) {
  // boxes along the traced line (processing pixels), so that the next seed is another line
  if (peak.x >= 0) excludeBox(f, R, peak);
  const double sx = static_cast<double>(f.proc_size.width) / f.input_size.width;
  const double sy = static_cast<double>(f.proc_size.height) / f.input_size.height;
  for (const auto& c : trace.pixels)
    excludeBox(f, R,
               cv::Point(static_cast<int>(std::lround((c.x + 0.5) * sx - 0.5)),
                         static_cast<int>(std::lround((c.y + 0.5) * sy - 0.5))));
}

void BoundaryCandidateFinder::findBestMatch(const CandidateFrame& f, const cv::Mat& R, bool left,
                                            cv::Point& peak, float& value) {
  cv::Rect area = f.roi;
  if (params_.ego_lane_seeds) {
    // the ego lane's left marker lies left of the principal point's column, the right one right
    const int cx = static_cast<int>(std::lround(f.K.cx * f.proc_size.width / f.input_size.width));
    const int split = std::min(std::max(cx, 1), f.proc_size.width - 1);
    area = left ? cv::Rect(0, f.roi.y, split, f.roi.height)
                : cv::Rect(split, f.roi.y, f.proc_size.width - split, f.roi.height);
  }
  double max_v = 0.0;
  cv::Point max_p(-1, -1);
  if (predictedBand(f, left ? 0 : 1, area)) {
    // the side's lane model predicts where the marker is: take the best match near it
    float best = 0.f;
    for (int y = area.y; y < area.y + area.height; ++y) {
      const int lo = band_lo_[y], hi = band_hi_[y];
      if (lo > hi) continue;
      const float* r = R.ptr<float>(y);
      for (int x = lo; x <= hi; ++x) {
        if (r[x] > best) {
          best = r[x];
          max_p = cv::Point(x, y);
        }
      }
    }
    if (best > params_.trace_threshold) {
      peak = max_p;
      value = best;
      return;
    }
  }
  maxLocation(R(area), max_v, max_p);  // cv::minMaxLoc's result, vectorised
  peak = max_p + area.tl();
  value = static_cast<float>(max_v);
}

bool BoundaryCandidateFinder::predictedBand(const CandidateFrame& f, int side,
                                            const cv::Rect& area) {
  const int band = params_.track_seed_band;
  const PlaneEstimate& previous = f.fitter->previousPlane();
  if (!params_.track_lanes || band <= 0 || !previous.valid || !f.fitter->tracker().valid(side))
    return false;
  const RoadFrame frame = RoadFrame::fromPlane(previous);
  f.fitter->tracker().sample(side, frame, 1.0, samples_);
  // per processing row, the columns within `band` of the predicted marker (lo > hi: none)
  band_lo_.assign(f.proc_size.height, 1);
  band_hi_.assign(f.proc_size.height, 0);
  const double sx = static_cast<double>(f.proc_size.width) / f.input_size.width;
  const double sy = static_cast<double>(f.proc_size.height) / f.input_size.height;
  bool any = false;
  cv::Point2d prev;
  bool have_prev = false;
  for (const auto& q : samples_) {
    if (!(q.z() > 0.1f)) continue;
    const cv::Point2d px = f.K.project(q);
    const cv::Point2d cur((px.x + 0.5) * sx - 0.5, (px.y + 0.5) * sy - 0.5);
    if (have_prev) {
      const int y0 = std::max(area.y, static_cast<int>(std::ceil(std::min(prev.y, cur.y))));
      const int y1 =
          std::min(area.y + area.height - 1, static_cast<int>(std::floor(std::max(prev.y, cur.y))));
      for (int y = y0; y <= y1; ++y) {
        const double t = cur.y != prev.y ? (y - prev.y) / (cur.y - prev.y) : 0.0;
        const double u = prev.x + t * (cur.x - prev.x);
        const int lo = std::max(area.x, static_cast<int>(std::floor(u)) - band);
        const int hi = std::min(area.x + area.width - 1, static_cast<int>(std::ceil(u)) + band);
        if (lo > hi) continue;
        band_lo_[y] = band_hi_[y] < band_lo_[y] ? lo : std::min(band_lo_[y], lo);
        band_hi_[y] = std::max(band_hi_[y], hi);
        any = true;
      }
    }
    prev = cur;
    have_prev = true;
  }
  return any;
}

bool BoundaryCandidateFinder::plausibleMarkerAngle(double angle, bool left) const {
  const double deg = angleFromHorizontalDeg(angle, left);
  return deg >= params_.marker_angle_min_deg && deg <= params_.marker_angle_max_deg;
}

bool BoundaryCandidateFinder::offRoad(const CandidateFrame& f, const cv::Point& pixel) const {
  // road_gate: the surface normal at a match, where depth gives one, must be road-like
  if (!params_.road_gate || !params_.use_depth) return false;
  float n[3];
  if (!falsNormalAt(*f.points, pixel.x, pixel.y, params_.normal_window, f.K, *f.col_map, *f.row_map,
                    n))
    return false;
  const double up = n[0] * params_.up_x + n[1] * params_.up_y + n[2] * params_.up_z;
  return std::fabs(up) < params_.road_gate_cos;
}

void BoundaryCandidateFinder::buildTrace(const CandidateFrame& f, const cv::Mat& R,
                                         const cv::Point& peak, float peak_value, double angle,
                                         MarkerTrace& trace) {
  trace.peak_score = peak_value;
  const double inv_s = static_cast<double>(f.input_size.width) / f.proc_size.width;
  const double inv_sy = static_cast<double>(f.input_size.height) / f.proc_size.height;
  trace.seed = cv::Point2f(static_cast<float>((peak.x + 0.5) * inv_s - 0.5),
                           static_cast<float>((peak.y + 0.5) * inv_sy - 0.5));
  trace.angle = angle;
  trace.num_valid_points = 0;
  trace.seed_point =
      pointAt(f, cv::Point2f(static_cast<float>(peak.x), static_cast<float>(peak.y)));
  if (!(peak_value > params_.trace_threshold)) return;

  TraceParams tp;
  tp.box_size = params_.template_size;
  tp.jump = params_.jump_step;
  tp.threshold = static_cast<float>(params_.trace_threshold);
  tp.max_steps = params_.max_trace_steps;
  tp.gap_steps = params_.gap_steps;
  traceMarker(R, cv::Point2f(static_cast<float>(peak.x), static_cast<float>(peak.y)), angle, tp,
              f.roi, trace_pixels_, trace_scores_);
  for (size_t i = 0; i < trace_pixels_.size(); ++i) {
    const cv::Point2f& c = trace_pixels_[i];
    trace.pixels.emplace_back(static_cast<float>((c.x + 0.5) * inv_s - 0.5),
                              static_cast<float>((c.y + 0.5) * inv_sy - 0.5));
    trace.scores.push_back(trace_scores_[i]);
    Eigen::Vector3f pt = pointAt(f, c);
    if (offRoad(f,
                cv::Point(static_cast<int>(std::lround(c.x)), static_cast<int>(std::lround(c.y)))))
      pt.setConstant(std::numeric_limits<float>::quiet_NaN());
    trace.points.push_back(pt);
    if (!std::isnan(pt.z())) ++trace.num_valid_points;
  }
}

Eigen::Vector3f BoundaryCandidateFinder::pointAt(const CandidateFrame& f,
                                                 const cv::Point2f& c) const {
  // The centroid's own point, else the depth of the nearest valid pixel in its box on the
  // centroid's ray (never a zero depth).
  const int cx = std::min(std::max(static_cast<int>(std::lround(c.x)), 0), f.proc_size.width - 1);
  const int cy = std::min(std::max(static_cast<int>(std::lround(c.y)), 0), f.proc_size.height - 1);
  const cv::Vec3f& p = f.points->at<cv::Vec3f>(cy, cx);
  if (!std::isnan(p[2])) return Eigen::Vector3f(p[0], p[1], p[2]);
  // ray through the sampled source pixel, scaled to z = 1
  const int sx = f.col_map->empty() ? cx : f.col_map->at<int>(cx);
  const int sy = f.row_map->empty() ? cy : f.row_map->at<int>(cy);
  const Eigen::Vector3d ray = f.K.ray(sx, sy);
  const float rx = static_cast<float>(ray.x());
  const float ry = static_cast<float>(ray.y());
  const int half = params_.template_size / 2;
  for (int r = 1; r <= half; ++r) {
    for (int dy = -r; dy <= r; ++dy) {
      const int y = cy + dy;
      if (y < 0 || y >= f.proc_size.height) continue;
      const int step = (dy == -r || dy == r) ? 1 : 2 * r;
      for (int dx = -r; dx <= r; dx += step) {
        const int x = cx + dx;
        if (x < 0 || x >= f.proc_size.width) continue;
        const cv::Vec3f& q = f.points->at<cv::Vec3f>(y, x);
        if (std::isnan(q[2])) continue;
        return Eigen::Vector3f(rx * q[2], ry * q[2], q[2]);
      }
    }
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  return Eigen::Vector3f(nan, nan, nan);
}

void BoundaryCandidateFinder::classify(const CandidateFrame& f) {
  if (!params_.classify_boundaries || f.road == nullptr || !f.road->valid) {
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < counts_[side]; ++k) {
        BoundaryEvidence& ev = candidates_[side][k].evidence;
        ev = BoundaryEvidence();
        ev.boundary = true;  // unclassified: every traced line is taken as paint
        ev.margin = 0.5f;
      }
    return;
  }
  classifierInputOf(f, *f.road, classifier_input_);
  const ClassifierInput& in = classifier_input_;
  for (int side = 0; side < 2; ++side)
    for (int k = 0; k < counts_[side]; ++k) {
      BoundaryCandidate& c = candidates_[side][k];
      if (static_cast<int>(c.trace.pixels.size()) < params_.min_marker_points)
        followFromSeed(f, side == 0, c.trace);
      classifier_.classify(in, c.trace.pixels, side == 0, params_, c.evidence);
      matchLengths(c.trace);
      if (c.evidence.boundary && c.evidence.kind == BoundaryKind::kRoadEdge &&
          c.evidence.narrow_rows >= c.evidence.rows / 2)
        dashedNarrowLine(f, side, c);
      // a painted line: on the paint's centre, row by row, and as far as it goes
      if (c.evidence.boundary && c.evidence.kind == BoundaryKind::kPaint) {
        classifier_.followLine(in, c.trace.pixels, c.trace.points, params_, kFollowGap,
                               params_.max_depth);
        if (classifier_.cutAtObject(in, c.trace.pixels, side == 0, params_)) matchLengths(c.trace);
        if (loneStroke(f, c.trace.pixels) && classifier_.arrowHead(in, c.trace.pixels, params_)) {
          c.evidence.boundary = false;
          c.evidence.reason = "lane arrow";
          continue;
        }
        classifier_.centreDoubleLine(in, c.trace.pixels, c.trace.points, params_);
        // a trace where depth is missing (near the car) told its kind by colour alone: the line
        // followed into the depth tells it again (a kerb's bright top is no paint)
        if (!std::isfinite(c.evidence.line_height)) {
          classifier_.classify(in, c.trace.pixels, side == 0, params_, c.evidence);
          matchLengths(c.trace);
        }
      }
      // a kerb or an unpainted edge: where the road surface ends, as far as it goes (not a
      // rail: its head is it)
      if (c.evidence.boundary && c.evidence.kind == BoundaryKind::kRoadEdge &&
          c.evidence.narrow_rows < c.evidence.rows / 2)
        classifier_.followEdge(in, c.trace.pixels, c.trace.points, side == 0, params_, kEdgeGap,
                               params_.max_depth);
    }
  followPredictedLines(f);
  addRoadEdgesFromDepth(f);
}

int BoundaryCandidateFinder::paintStretches(const CandidateFrame& f,
                                            const std::vector<cv::Point2f>& pixels, double gap,
                                            double* extent, double* painted,
                                            double max_forward) const {
  int stretches = 0;
  double near_f = std::numeric_limits<double>::infinity(), far_f = -near_f, last_f = 0.0;
  double start_f = 0.0, covered = 0.0;
  const RoadFrame& frame = classifier_input_.frame;
  for (const auto& px : pixels) {  // near to far
    Eigen::Vector2d q, q1;
    if (!roadCoordinates(f, frame, px.x, px.y, q)) continue;
    const double fwd = q.x();
    if (fwd > max_forward) continue;
    // far away one image row spans more road than the gap: rows found on neighbouring rows
    // are one stretch (kRowsPerGap rows without paint make a gap there)
    const double row_m = roadCoordinates(f, frame, px.x, px.y - 1.0, q1)
                             ? std::fabs(q1.x() - fwd)
                             : std::numeric_limits<double>::infinity();
    if (stretches == 0 || std::fabs(fwd - last_f) > std::max(gap, kRowsPerGap * row_m)) {
      if (stretches > 0) covered += std::fabs(last_f - start_f);
      ++stretches;
      start_f = fwd;
    }
    last_f = fwd;
    near_f = std::min(near_f, fwd);
    far_f = std::max(far_f, fwd);
  }
  if (stretches > 0) covered += std::fabs(last_f - start_f);
  if (extent) *extent = stretches > 0 ? far_f - near_f : 0.0;
  if (painted) *painted = covered;
  return stretches;
}

bool BoundaryCandidateFinder::followed(const ClassifierInput& in, double reach) {
  // seed_pixels_ followed row by row; the rows found replace them (with their points) only when
  // there are enough of them
  const int found = classifier_.followLine(in, seed_pixels_, seed_points_, params_, kFollowGap,
                                           params_.max_depth, reach);
  return found >= std::max(params_.min_marker_points, 3) &&
         seed_points_.size() == seed_pixels_.size();
}

bool BoundaryCandidateFinder::runsAhead(const CandidateFrame& f,
                                         const std::vector<cv::Point2f>& pixels) const {
  // from its nearest to its farthest row, in road coordinates
  Eigen::Vector2d a(0.0, 0.0), b(0.0, 0.0);
  bool have = false;
  for (const auto& px : pixels) {
    Eigen::Vector2d q;
    if (!roadCoordinates(f, classifier_input_.frame, px.x, px.y, q)) continue;
    if (!have) a = q;
    b = q;
    have = true;
  }
  const Eigen::Vector2d t = b - a;
  return have && t.x() > 0.0 && std::fabs(t.y()) <= std::tan(kMaxSeedHeading) * t.x();
}

bool BoundaryCandidateFinder::loneStroke(const CandidateFrame& f,
                                          const std::vector<cv::Point2f>& pixels) const {
  // paint on two stretches (dashes) or over a length no arrow has is a lane line
  double extent = 0.0;
  return paintStretches(f, pixels, kStrokeGap, &extent) < 2 && !(extent >= kStrokeLength);
}

void BoundaryCandidateFinder::dashedNarrowLine(const CandidateFrame& f, int side,
                                               BoundaryCandidate& c) {
  // a rail head runs on without a break; a line narrower than paint that comes in dashes is worn
  // paint (the bright core of a faded dash measures a few centimetres)
  seed_pixels_.assign(c.trace.pixels.begin(), c.trace.pixels.end());
  seed_points_.clear();
  const ClassifierInput& in = classifier_input_;
  double extent = 0.0, painted = 0.0;
  if (!followed(in, BoundaryClassifier::kTraceReach)) return;
  // within kDashRange, where a rail head is resolved on every row (farther, any thin line
  // breaks up)
  const int dashes = paintStretches(f, seed_pixels_, kDashGap, &extent, &painted, kDashRange);
  if (dashes < kMinDashes || painted > kMaxDashCoverage * extent) return;
  c.trace.pixels.assign(seed_pixels_.begin(), seed_pixels_.end());
  c.trace.points.assign(seed_points_.begin(), seed_points_.end());
  c.trace.scores.resize(c.trace.pixels.size(), c.trace.peak_score);
  c.evidence.kind = BoundaryKind::kPaint;
  c.evidence.reason = "narrow dashes (worn paint)";
  (void)side;
}

bool BoundaryCandidateFinder::followFromSeed(const CandidateFrame& f, bool left, MarkerTrace& m) {
  const ClassifierInput& in = classifier_input_;  // set by classify()
  if (!(m.peak_score > params_.trace_threshold) || m.seed.x < 0.f) return false;
  // the seed lies on the road where the depth measures it (a match without depth, on a wall, a
  // car or a kerb top, or where the road plane only fills missing depth, is followed nowhere)
  const Eigen::Vector3f& sp = m.seed_point;
  if (!sp.allFinite() || std::fabs(f.road->normal.cast<float>().dot(sp) +
                                   static_cast<float>(f.road->distance)) > params_.kerb_height)
    return false;
  if (f.filled != nullptr) {
    const int px = static_cast<int>(std::lround((m.seed.x + 0.5) * f.proc_size.width / f.input_size.width - 0.5));
    const int py = static_cast<int>(std::lround((m.seed.y + 0.5) * f.proc_size.height / f.input_size.height - 0.5));
    if (px >= 0 && py >= 0 && px < f.filled->cols && py < f.filled->rows && f.filled->at<uint8_t>(py, px) != 0)
      return false;
  }
  Eigen::Vector2d q;
  if (!roadCoordinates(f, in.frame, m.seed.x, m.seed.y, q)) return false;
  // an ego-lane boundary's distance beside the camera (lateral: + left)
  const double beside = left ? q.y() : -q.y();
  if (beside < params_.boundary_offset_min || beside > params_.boundary_offset_max) return false;
  // the line through the seed straight ahead on the road (ego-lane lines run with the vehicle)
  seed_pixels_.clear();
  seed_points_.clear();
  for (double df : {-kSeedSpan, 0.0, kSeedSpan}) {
    const Eigen::Vector3d p = in.frame.toCamera(q.x() + df, q.y());
    if (!(p.z() > 0.1)) continue;
    seed_pixels_.emplace_back(f.K.project(p));
  }
  if (seed_pixels_.size() < 2 || !followed(in, kSeedReach)) return false;
  if (loneStroke(f, seed_pixels_) || !runsAhead(f, seed_pixels_)) return false;
  m.pixels.assign(seed_pixels_.begin(), seed_pixels_.end());
  m.points.assign(seed_points_.begin(), seed_points_.end());
  m.scores.assign(m.pixels.size(), m.peak_score);
  m.num_valid_points = 0;
  for (const auto& p : m.points) m.num_valid_points += !std::isnan(p.z());
  return true;
}

template <typename Lateral>
bool BoundaryCandidateFinder::candidateOnLine(const CandidateFrame& f, int side, BoundaryKind kind,
                                              const RoadFrame& frame, double reach,
                                              Lateral&& lateral) const {
  for (int k = 0; k < counts_[side]; ++k) {
    const BoundaryCandidate& c = candidates_[side][k];
    if (!c.evidence.boundary || c.evidence.kind != kind) continue;
    int near = 0, total = 0;
    for (const auto& px : c.trace.pixels) {
      Eigen::Vector2d q;
      if (!roadCoordinates(f, frame, px.x, px.y, q)) continue;
      ++total;
      if (std::fabs(q.y() - lateral(q.x())) <= reach) ++near;
    }
    if (total >= params_.min_marker_points && near >= 0.6 * total) return true;
  }
  return false;
}

void BoundaryCandidateFinder::followPredictedLines(const CandidateFrame& f) {
  const PlaneEstimate& previous = f.fitter->previousPlane();
  if (!params_.track_lanes || !previous.valid) return;
  const ClassifierInput& in = classifier_input_;  // set by classify()
  const RoadFrame frame = RoadFrame::fromPlane(*f.road);
  const double sx = static_cast<double>(f.proc_size.width) / f.input_size.width;
  const double sy = static_cast<double>(f.proc_size.height) / f.input_size.height;
  for (int side = 0; side < 2; ++side) {
    if (!f.fitter->tracker().valid(side) || f.fitter->sideKind(side) != BoundaryKind::kPaint)
      continue;
    const LaneTracker& tracker = f.fitter->tracker();
    if (candidateOnLine(f, side, BoundaryKind::kPaint, frame, kPredictedReach,
                        [&](double f) { return tracker.lateral(side, f); }))
      continue;  // the seeds found it: nothing to add
    BoundaryCandidate& c = next(side);
    MarkerTrace& m = c.trace;
    m.pixels.clear();
    m.points.clear();
    m.scores.clear();
    f.fitter->tracker().sample(side, frame, 1.0, samples_);
    for (const auto& q : samples_) {
      if (!(q.z() > 0.1f)) continue;
      const cv::Point2f px(f.K.project(q));
      m.pixels.push_back(px);
      m.points.push_back(pointAt(f, cv::Point2f(static_cast<float>((px.x + 0.5) * sx - 0.5),
                                                static_cast<float>((px.y + 0.5) * sy - 0.5))));
      m.scores.push_back(0.f);
    }
    if (m.pixels.size() < 2) continue;
    if (classifier_.followLine(in, m.pixels, m.points, params_, kFollowGap, params_.max_depth,
                               kPredictedReach) < params_.min_marker_points)
      continue;
    classifier_.classify(in, m.pixels, side == 0, params_, c.evidence);
    matchLengths(m);
    if (!c.evidence.boundary || c.evidence.kind != BoundaryKind::kPaint) continue;
    m.found = false;
    m.kind = BoundaryKind::kPaint;
    m.peak_score = static_cast<float>(params_.trace_threshold);
    m.seed = m.pixels.front();
    m.seed_point = m.points.front();
    m.angle_valid = false;
    m.num_valid_points = static_cast<int>(m.points.size());
    for (size_t i = 0; i < m.scores.size(); ++i) m.scores[i] = m.peak_score;
    m.scores.resize(m.pixels.size(), m.peak_score);
    ++counts_[side];
  }
}

void BoundaryCandidateFinder::addRoadEdgesFromDepth(const CandidateFrame& f) {
  RoadEdgeSettings s;
  s.kerb_height = params_.kerb_height;
  s.offset_min = params_.boundary_offset_min;
  s.offset_max = params_.boundary_offset_max;
  s.max_range = std::max(params_.road_fit_range, 1.0);
  s.normal_window = params_.normal_window;
  edge_finder_.find(*f.points, f.filled, f.roi_rows, f.K, *f.col_map, *f.row_map, *f.road, s,
                    depth_edges_[0], depth_edges_[1]);
  const ClassifierInput& in = classifier_input_;  // set by classify()
  for (int side = 0; side < 2; ++side) {
    const RoadEdgeLine& e = depth_edges_[side];
    if (!e.found) continue;
    const double a = e.offset, b = std::tan(e.heading);
    if (candidateOnLine(f, side, BoundaryKind::kRoadEdge, in.frame, kEdgeReach,
                        [a, b](double f) { return a + b * f; }))
      continue;  // traced already
    BoundaryCandidate& c = next(side);
    MarkerTrace& m = c.trace;
    m.found = false;
    m.kind = BoundaryKind::kRoadEdge;
    m.pixels.assign(e.pixels.begin(), e.pixels.end());
    m.points.assign(e.points.begin(), e.points.end());
    m.scores.assign(e.pixels.size(), static_cast<float>(params_.trace_threshold));
    m.peak_score = static_cast<float>(params_.trace_threshold);
    m.seed = m.pixels.front();
    m.seed_point = m.points.front();
    m.angle_valid = false;
    m.num_valid_points = static_cast<int>(m.points.size());
    // (its rows are the depth's own measurement of the edge: not moved by the colours, which a
    // gutter's leaves or an overexposed kerb mislead)
    classifier_.classify(in, m.pixels, side == 0, params_, c.evidence);
    matchLengths(m);
    if (!c.evidence.boundary || c.evidence.kind != BoundaryKind::kRoadEdge) continue;
    ++counts_[side];
  }
}

}  // namespace rgbd_lane_detector
