// The candidate search: each side's seeds (best matches of its response map off the lines
// already traced, near the tracked boundary first), their PCA angles and sliding-box traces, in
// the finder's candidate slots. Their classification and the lines followed or added after it:
// boundary_candidates_following.cpp.
#include "rgbd_lane_detector/boundary_candidates.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "rgbd_lane_detector/fals_normals.h"
#include "rgbd_lane_detector/geometry.h"
#include "rgbd_lane_detector/pca_refinement.h"
#include "rgbd_lane_detector/response_map.h"
#include "rgbd_lane_detector/sliding_box.h"

namespace rgbd_lane_detector {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kMaxSeedRetries = 4;   // seeds that are no marker looked past per line

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

void BoundaryCandidateFinder::startTrace(MarkerTrace& m) {
  m.found = false;
  m.kind = BoundaryKind::kPaint;
  m.confidence = 0.0f;
  m.pixels.clear();
  m.scores.clear();
  m.points.clear();
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
    startTrace(m);
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
      // (a short dash's blob, merged with the worn paint or texture beside it: followFromSeed()
      // may still find its line; a further seed too: the best seed may be another line's, or
      // a stretch of the same line that its follow cannot bridge)
      m.angle_valid = false;
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
                                         const cv::Point& centre, cv::Rect& previous) {
  const int h = std::max(1, params_.template_size / 4);
  const cv::Rect box = cv::Rect(centre.x - h, centre.y - h, 2 * h + 1, 2 * h + 1) & f.roi;
  for (int y = box.y; y < box.y + box.height; ++y) {
    float* r = R.ptr<float>(y);
    auto clear = [&](int x0, int x1) {
      for (int x = x0; x < x1; ++x) {
        if (r[x] == 0.f) continue;
        restore_.emplace_back(r + x, r[x]);
        r[x] = 0.f;
      }
    };
    // a traced line's boxes overlap the one before (its input pixels a row apart): that part
    // is 0 already, only the columns either side of it are read
    if (y >= previous.y && y < previous.br().y) {
      clear(box.x, std::min(box.br().x, previous.x));
      clear(std::max(box.x, previous.br().x), box.br().x);
    } else {
      clear(box.x, box.br().x);
    }
  }
  previous = box;
}

void BoundaryCandidateFinder::excludeTrace(const CandidateFrame& f, cv::Mat& R,
                                           const MarkerTrace& trace, const cv::Point& peak) {
  // boxes along the traced line (processing pixels), so that the next seed is another line
  cv::Rect previous;
  if (peak.x >= 0) excludeBox(f, R, peak, previous);
  for (const auto& c : trace.pixels) {
    const cv::Point2d q = f.toProcessing(c);
    excludeBox(f, R,
               cv::Point(roundColumn(q.x, f.proc_size.width), static_cast<int>(std::lround(q.y))),
               previous);
  }
}

void BoundaryCandidateFinder::findBestMatch(const CandidateFrame& f, const cv::Mat& R, bool left,
                                            cv::Point& peak, float& value) {
  cv::Rect area = f.roi;
  if (params_.ego_lane_seeds) {
    // the ego lane's left marker lies left of the principal point's column, the right one
    // right; a principal point on a column gives it to both sides (a mirror swaps them)
    const double cx = (f.K.cx + 0.5) * f.proc_size.width / f.input_size.width - 0.5;
    const int last_left = std::min(std::max(static_cast<int>(std::floor(cx)), 0),
                                   f.proc_size.width - 2);
    const int first_right = std::min(std::max(static_cast<int>(std::ceil(cx)), 1),
                                     f.proc_size.width - 1);
    area = left ? cv::Rect(0, f.roi.y, last_left + 1, f.roi.height)
                : cv::Rect(first_right, f.roi.y, f.proc_size.width - first_right, f.roi.height);
  }
  double max_v = 0.0;
  cv::Point max_p(-1, -1);
  if (predictedBand(f, left ? 0 : 1, area)) {
    // the side's lane model predicts where the marker is: take the best match near it (of
    // equal ones the topmost, then the innermost: a mirror finds the mirrored one)
    float best = 0.f;
    for (int y = area.y; y < area.y + area.height; ++y) {
      const int lo = band_lo_[y], hi = band_hi_[y];
      if (lo > hi) continue;
      const float* r = R.ptr<float>(y);
      float v = 0.f;
      int c = 0;
      rowMaximum(r + lo, hi - lo + 1, v, c);  // its first column
      if (!(v > best)) continue;
      best = v;
      int x = lo + c;
      if (left)  // the innermost: the last column of it
        for (int k = hi; k > x; --k)
          if (r[k] == v) {
            x = k;
            break;
          }
      max_p = cv::Point(x, y);
    }
    if (best > params_.trace_threshold) {
      peak = max_p;
      value = best;
      return;
    }
  }
  maxLocation(R(area), max_v, max_p);  // cv::minMaxLoc's result, vectorised
  peak = max_p + area.tl();
  if (left && max_p.x >= 0) {  // of equal maxima in the row the innermost, as on the right
    const float* r = R.ptr<float>(peak.y);
    for (int x = area.x + area.width - 1; x > peak.x; --x) {
      if (r[x] == static_cast<float>(max_v)) {
        peak.x = x;
        break;
      }
    }
  }
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
  bool any = false;
  cv::Point2d prev;
  bool have_prev = false;
  for (const auto& q : samples_) {
    if (!(q.z() > 0.1f)) continue;
    const cv::Point2d cur = f.toProcessing(f.K.project(q));
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
  trace.seed = cv::Point2f(f.toInput(peak));
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
    trace.pixels.emplace_back(f.toInput(c));
    trace.scores.push_back(trace_scores_[i]);
    Eigen::Vector3f pt = pointAt(f, c);
    if (offRoad(f,
                cv::Point(roundColumn(c.x, f.proc_size.width), static_cast<int>(std::lround(c.y)))))
      pt.setConstant(std::numeric_limits<float>::quiet_NaN());
    trace.points.push_back(pt);
    if (!std::isnan(pt.z())) ++trace.num_valid_points;
  }
}

Eigen::Vector3f BoundaryCandidateFinder::pointAt(const CandidateFrame& f,
                                                 const cv::Point2f& c) const {
  // The centroid's own point, else the depth of the nearest valid pixel in its box on the
  // centroid's ray (never a zero depth).
  const int cx = std::min(std::max(roundColumn(c.x, f.proc_size.width), 0), f.proc_size.width - 1);
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

}  // namespace rgbd_lane_detector
