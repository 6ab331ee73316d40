#include "rgbd_lane_detector/lane_detector.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "rgbd_lane_detector/adaptive_threshold.h"
#include "rgbd_lane_detector/depth_points.h"
#include "rgbd_lane_detector/half_binary.h"
#include "rgbd_lane_detector/lane_plane.h"
#include "rgbd_lane_detector/parallel.h"
#include "rgbd_lane_detector/pca_refinement.h"
#include "rgbd_lane_detector/response_map.h"
#include "rgbd_lane_detector/sliding_box.h"

namespace rgbd_lane_detector {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point& t) {
  const Clock::time_point now = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - t).count();
  t = now;
  return ms;
}

int colourChannels(PixelFormat f) {
  switch (f) {
    case PixelFormat::kBgr8:
    case PixelFormat::kRgb8:
      return 3;
    case PixelFormat::kBgra8:
    case PixelFormat::kRgba8:
      return 4;
    case PixelFormat::kMono8:
      return 1;
  }
  return 0;
}

// Resample rows/columns through index maps (nearest neighbour), no allocation when sized.
template <typename T>
void remapNearest(const cv::Mat& src, const cv::Mat& col_map, const cv::Mat& row_map, int elem,
                  cv::Mat& dst) {
  const int* cm = col_map.ptr<int>();
  const int* rm = row_map.ptr<int>();
  for (int y = 0; y < dst.rows; ++y) {
    const T* s = src.ptr<T>(rm[y]);
    T* d = dst.ptr<T>(y);
    for (int x = 0; x < dst.cols; ++x)
      for (int c = 0; c < elem; ++c) d[x * elem + c] = s[cm[x] * elem + c];
  }
}

// Angle from the horizontal of a marker direction on the given side (deg).
double angleFromHorizontalDeg(double angle, bool left) {
  return (left ? M_PI - angle : angle) * 180.0 / M_PI;
}

// Keep a template angle inside the half-plane of its side, away from horizontal/vertical.
constexpr int kMaxSeedRetries = 4;
constexpr double kFollowGap = 10.0;  // m: dash gaps a followed line crosses (9 m on highways)
constexpr double kEdgeGap = 2.0;     // m: a followed road edge ends where it is not seen this long
constexpr double kEdgeReach = 0.3;   // m: a traced road edge this near a depth edge is the same
constexpr double kPredictedReach = 0.4;  // m: a predicted line's paint is sought this close

double clampAngle(double angle, bool left) {
  const double lo = 10.0 * M_PI / 180.0, hi = 88.0 * M_PI / 180.0;
  double from_h = left ? M_PI - angle : angle;  // angle from the horizontal
  from_h = std::min(std::max(from_h, lo), hi);
  return left ? M_PI - from_h : from_h;
}

}  // namespace

LaneDetector::LaneDetector(const Params& params) { setParams(params); }

void LaneDetector::setParams(const Params& params) {
  const Params p = sanitize(params);
  // New template geometry invalidates the adapted angles; any other change keeps the carried
  // state (a reconfigure must not throw away the PCA adaptation or the lane model).
  const bool new_templates = !sameTemplates(p, params_) || left_template_.size == 0;
  params_ = p;
  fitter_.setParams(p);
  LaneModelSettings ms;
  ms.gate = p.model_gate;
  ms.lost_frames = p.model_lost_frames;
  ms.width_min = p.lane_width_min;
  ms.width_max = p.lane_width_max > 0.0 ? p.lane_width_max : ms.width_max;
  ms.x_max = p.max_depth;
  ms.dashed_coverage = p.dashed_coverage;
  ms.yellowness = p.yellow_threshold;
  lane_model_.setSettings(ms);
  if (new_templates) reset();
}

void LaneDetector::reset() {
  next_left_angle_ = defaultLeftAngle(params_.template_angle_deg);
  next_right_angle_ = defaultRightAngle(params_.template_angle_deg);
  fitter_.reset();
  lane_model_.reset();
  road_.valid = false;
  templates_dirty_ = true;
}

Status LaneDetector::validate(const Frame& frame) const {
  if (frame.colour.empty() || frame.depth.empty()) return Status::kEmptyImage;
  if (frame.colour.size() != frame.depth.size()) return Status::kSizeMismatch;
  if (frame.colour.depth() != CV_8U || frame.colour.channels() != colourChannels(frame.format))
    return Status::kUnsupportedColour;
  if (frame.depth.type() == CV_16UC1) {
    if (!(frame.depth_scale > 0.0) || !std::isfinite(frame.depth_scale))
      return Status::kUnsupportedDepth;
  } else if (frame.depth.type() != CV_32FC1) {
    return Status::kUnsupportedDepth;
  }
  if (!frame.intrinsics.valid()) return Status::kInvalidIntrinsics;
  // searched region at the processing scale must hold a template
  const double s = params_.processing_scale;
  const int pw = std::max(1, static_cast<int>(std::lround(frame.colour.cols * s)));
  const int ph = std::max(1, static_cast<int>(std::lround(frame.colour.rows * s)));
  const int top = static_cast<int>(std::lround(params_.roi_top * ph));
  const int bottom = static_cast<int>(std::lround(params_.roi_bottom * ph));
  if (pw < params_.template_size || bottom - top < params_.template_size)
    return Status::kImageTooSmall;
  return Status::kOk;
}

void LaneDetector::prepareGeometry(const Frame& frame) {
  const double s = params_.processing_scale;
  const cv::Size in = frame.colour.size();
  const cv::Size proc(std::max(1, static_cast<int>(std::lround(in.width * s))),
                      std::max(1, static_cast<int>(std::lround(in.height * s))));
  if (in != input_size_ || proc != proc_size_ || s != scale_) {
    input_size_ = in;
    proc_size_ = proc;
    scale_ = s;
    if (proc == in) {
      col_map_.release();
      row_map_.release();
    } else {
      col_map_.create(1, proc.width, CV_32SC1);
      row_map_.create(1, proc.height, CV_32SC1);
      for (int x = 0; x < proc.width; ++x)
        col_map_.at<int>(x) = std::min(in.width - 1, static_cast<int>((x + 0.5) * in.width / proc.width));
      for (int y = 0; y < proc.height; ++y)
        row_map_.at<int>(y) =
            std::min(in.height - 1, static_cast<int>((y + 0.5) * in.height / proc.height));
    }
    // buffers change size: start from zeroed maps (rows outside the ROI stay 0)
    geometric_.release();
    response_left_.release();
    response_right_.release();
  }
  const int top = static_cast<int>(std::lround(params_.roi_top * proc.height));
  const int bottom = static_cast<int>(std::lround(params_.roi_bottom * proc.height));
  const cv::Rect roi(0, top, proc.width, bottom - top);
  if (roi != roi_) {
    roi_ = roi;
    geometric_.release();
  }
  roi_rows_ = cv::Range(roi_.y, roi_.y + roi_.height);
  proc_K_ = frame.intrinsics;
}

void LaneDetector::resampleColour(const Frame& frame) {
  if (col_map_.empty()) return;
  colour_small_.create(proc_size_, frame.colour.type());
  remapNearest<uint8_t>(frame.colour, col_map_, row_map_, frame.colour.channels(), colour_small_);
}

Status LaneDetector::detect(const Frame& frame, Result& result) {
  const Clock::time_point start = Clock::now();
  timings_ = StageTimings();
  result.left.found = result.right.found = false;
  result.plane.valid = false;
  result.status = validate(frame);
  if (result.status != Status::kOk) {
    for (MarkerTrace* m : {&result.left, &result.right}) {
      m->confidence = 0.0f;
      m->pixels.clear();
      m->points.clear();
      m->scores.clear();
    }
    result.plane.support.clear();
    result.timings = timings_;
    return result.status;
  }
  prepareGeometry(frame);
  if (templates_dirty_) {
    makeLineTemplate(params_.template_size, params_.template_line_width, next_left_angle_,
                     left_template_);
    makeLineTemplate(params_.template_size, params_.template_line_width, next_right_angle_,
                     right_template_);
    if (params_.acquisition_angle_deg > 0.0) {
      makeLineTemplate(params_.template_size, params_.template_line_width,
                       defaultLeftAngle(params_.acquisition_angle_deg), acquisition_left_);
      makeLineTemplate(params_.template_size, params_.template_line_width,
                       defaultRightAngle(params_.acquisition_angle_deg), acquisition_right_);
    }
    templates_dirty_ = false;
  }
  for (int side = 0; side < 2; ++side)
    acquiring_[side] = params_.acquisition_angle_deg > 0.0 && params_.track_lanes &&
                       !fitter_.tracker().established(side);

  Clock::time_point t = start;
  preprocess(frame);            // 1. half-binary image
  timings_.preprocess = msSince(t);
  computePoints(frame);         // 2. organised 3D points
  timings_.points = msSince(t);
  fitRoadSurface();             // 3. the road plane from depth, extended where depth is missing
  timings_.road = msSince(t);   //    (improved mode)
  computeResponses();           // 4.-6. normals and G, template matching, R
  computeAcquisitionResponses();
  msSince(t);
  for (int side = 0; side < 2; ++side) {  // 7. seeds, PCA angles and traces of each side's lines
    candidate_count_[side] = 0;
    findCandidates(side, side == 0 ? response_left_ : response_right_);
    if (acquiring_[side])
      findCandidates(side, side == 0 ? acquisition_response_left_ : acquisition_response_right_);
  }
  classifyCandidates(frame);    // 8. paint, road edge or no boundary (improved mode)
  followPredictedLines();
  addRoadEdgesFromDepth(frame);
  timings_.classify = msSince(t);
  LaneFitInput fit;             // 9. the lane plane and boundaries
  fit.K = proc_K_;
  fit.road = &road_;
  fit.road_range = road_surface_.validRange();
  fit.candidates = &candidates_;
  fit.counts = candidate_count_;
  fitter_.fit(fit, result);
  timings_.plane = msSince(t);
  measurePaint(frame, result);  // 10. dashed or solid, white or yellow
  updateLaneModel(frame, result);  // 11. the lane model for planners
  timings_.model = msSince(t);
  finish(result);
  timings_.total = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  result.timings = timings_;
  return Status::kOk;
}

void LaneDetector::preprocess(const Frame& frame) {
  resampleColour(frame);
  const cv::Mat& colour = col_map_.empty() ? frame.colour : colour_small_;
  // the grey image (a half-binary image at threshold 0) when the adaptive threshold or the
  // classifier reads it
  const bool grey = params_.adaptive_tau_c || params_.classify_boundaries;
  if (grey) halfBinary(colour, frame.format, 0, roi_rows_, grey_);
  if (params_.adaptive_tau_c) {
    // per-row threshold: row median + offset (fog, overpasses, shadows change the road's grey)
    applyRowThreshold(grey_, half_binary_, roi_rows_, params_.tau_c_offset, row_histogram_);
  } else {
    halfBinary(colour, frame.format, params_.tau_c, roi_rows_, half_binary_);
  }
  if (!params_.classify_boundaries) return;
  // the classifier measures profiles on the input image: its grey over the searched rows
  const double sy = static_cast<double>(input_size_.height) / proc_size_.height;
  grey_input_rows_ = cv::Range(
      std::max(0, static_cast<int>(std::floor(roi_rows_.start * sy))),
      std::min(input_size_.height, static_cast<int>(std::ceil(roi_rows_.end * sy))));
  if (!col_map_.empty()) halfBinary(frame.colour, frame.format, 0, grey_input_rows_, grey_input_);
}

void LaneDetector::computePoints(const Frame& frame) {
  // the ROI plus the normal window's margin, read through the maps: exact back-projection of
  // each sampled source pixel
  const int h = params_.normal_window / 2;
  const cv::Range point_rows(std::max(0, roi_.y - h),
                             std::min(proc_size_.height, roi_.y + roi_.height + h));
  DepthDecoder decoder;
  decoder.scale = frame.depth_scale;
  decoder.min_depth = params_.min_depth;
  decoder.max_depth = params_.max_depth;
  depthToPoints(frame.depth, decoder, proc_K_, point_rows, points_, col_map_, row_map_);
  if (params_.fill_depth_holes > 0) fillDepthHoles(points_, point_rows, params_.fill_depth_holes);
}

void LaneDetector::computeResponses() {
  const Params& p = params_;
  // 3. normals, and G (Eq. 2) in the same pass (no normal image is kept).
  // 4. matching. 3 and 4 are independent: on two cores when OpenCV may use two threads (each
  // timing is then its own stage's, and they overlap).
  auto normals = [&] {
    const Clock::time_point t3 = Clock::now();
    if (p.use_depth) {
      fals_.configure(proc_size_, proc_K_, p.normal_window, col_map_, row_map_);
      fals_.computeGeometric(points_, roi_rows_, p, geometric_);
    }
    timings_.normals = std::chrono::duration<double, std::milli>(Clock::now() - t3).count();
  };
  auto matching = [&] {
    const Clock::time_point t4 = Clock::now();
    matcher_.match(half_binary_, roi_, left_template_, right_template_, response_left_,
                   response_right_);
    timings_.matching = std::chrono::duration<double, std::milli>(Clock::now() - t4).count();
  };
  runPair(normals, matching);

  // 5. R (G was computed with the normals)
  const Clock::time_point t5 = Clock::now();
  if (p.use_depth) {
    if (p.plane_gate > 0.0 && fitter_.previousPlane().valid)
      applyPlaneGate(roi_rows_, response_left_, response_right_);
    fuseResponse(response_left_, geometric_, static_cast<float>(p.tau_g), roi_rows_, response_left_);
    fuseResponse(response_right_, geometric_, static_cast<float>(p.tau_g), roi_rows_, response_right_);
  } else if (geometric_.size() != proc_size_ || geometric_.type() != CV_32FC1) {
    geometric_.create(proc_size_, CV_32FC1);
    geometric_.setTo(0);
  } else {
    geometric_(roi_).setTo(0);
  }
  timings_.response = std::chrono::duration<double, std::milli>(Clock::now() - t5).count();
}

void LaneDetector::computeAcquisitionResponses() {
  if (!acquiring_[0] && !acquiring_[1]) return;
  const Clock::time_point t0 = Clock::now();
  const Params& p = params_;
  acquisition_matcher_.match(half_binary_, roi_, acquisition_left_, acquisition_right_,
                             acquisition_response_left_, acquisition_response_right_);
  if (p.use_depth) {
    if (p.plane_gate > 0.0 && fitter_.previousPlane().valid)
      applyPlaneGate(roi_rows_, acquisition_response_left_, acquisition_response_right_);
    for (cv::Mat* R : {&acquisition_response_left_, &acquisition_response_right_})
      fuseResponse(*R, geometric_, static_cast<float>(p.tau_g), roi_rows_, *R);
  }
  timings_.matching += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void LaneDetector::fitRoadSurface() {
  road_.valid = false;
  road_filled_valid_ = false;
  if (params_.plane_fit != PlaneFit::kRoadSurface) return;
  RoadSurfaceSettings s;
  s.up = Eigen::Vector3d(params_.up_x, params_.up_y, params_.up_z);
  s.max_tilt_deg = params_.plane_max_tilt_deg;
  s.height_min = params_.plane_distance_min;
  s.height_max = params_.plane_distance_max;
  s.fit_range = params_.road_fit_range;
  s.inlier_distance = params_.road_inlier_distance;
  s.noise_growth = params_.road_noise_growth;
  s.max_range = params_.max_depth;
  const double sx = static_cast<double>(proc_size_.width) / input_size_.width;
  s.far_columns =
      RoadSurface::corridorColumns(proc_K_.fx * sx, (proc_K_.cx + 0.5) * sx - 0.5, s.fit_range);
  if (!road_surface_.fit(points_, roi_rows_, s, fitter_.previousPlane(), road_)) return;
  // LiDAR and stereo often see nothing near the car: where a column's nearest depth is road, the
  // road continues toward the camera (its points give seeds there a road's normal and depth)
  const int h = params_.normal_window / 2;
  fillFromRoadPlane(points_, cv::Range(roi_rows_.start, std::min(proc_size_.height, roi_rows_.end + h)),
                    proc_K_, road_, s.inlier_distance, road_surface_.noiseGrowth(), road_filled_,
                    col_map_, row_map_);
  road_filled_valid_ = true;
}

void LaneDetector::findCandidates(int side, cv::Mat& R) {
  // The side's best seed first (the paper's), then, with boundary_candidates > 1, the next best
  // seeds off the lines already traced: a kerb or a rail may outscore the paint next to it.
  const Clock::time_point t0 = Clock::now();
  double tracing_ms = 0.0;
  const bool left = side == 0;
  std::vector<BoundaryCandidate>& cands = candidates_[side];
  const int first = candidate_count_[side];
  const int wanted = first + params_.boundary_candidates;
  if (static_cast<int>(cands.size()) < wanted) cands.resize(wanted);
  int& count = candidate_count_[side];
  restore_.clear();
  for (int k = 0; k < first; ++k)  // lines traced on another map are not sought again
    excludeTrace(R, cands[k].trace, cv::Point(-1, -1));
  const int half = params_.template_size / 2;
  for (int attempt = 0; attempt <= wanted + kMaxSeedRetries && count < wanted; ++attempt) {
    cv::Point peak;
    float value = 0.f;
    findBestMatch(R, left, peak, value);
    const bool traceable = value > params_.trace_threshold;
    if (traceable && offRoad(peak)) {
      // road_gate: a best match on a surface that is not road is removed from R for good
      const cv::Rect box = cv::Rect(peak.x - half, peak.y - half, 2 * half + 1, 2 * half + 1) & roi_;
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
    const LineTemplate& tmpl = left ? left_template_ : right_template_;
    m.angle = pca.valid ? clampAngle(pca.angle, left) : tmpl.angle;
    // a seed whose marker direction no ego-lane marker can have (the road edge line of a
    // highway, a neighbour lane's marker) is not traced (named option, off in the paper mode)
    float peak_value = value;
    if (pca.valid && !plausibleMarkerAngle(pca.angle, left)) peak_value = 0.f;
    if (count > first && !(peak_value > params_.trace_threshold)) {
      excludeBox(R, peak);  // a further seed that is no marker: look past it
      continue;
    }
    const Clock::time_point tt = Clock::now();
    buildTrace(R, peak, peak_value, m.angle, m);
    tracing_ms += std::chrono::duration<double, std::milli>(Clock::now() - tt).count();
    ++count;
    if (!traceable || count == wanted) break;
    excludeTrace(R, m, peak);
  }
  // the maps are published: put back what the search removed
  for (const auto& r : restore_) *r.first = r.second;
  timings_.tracing += tracing_ms;
  timings_.pca += std::chrono::duration<double, std::milli>(Clock::now() - t0).count() - tracing_ms;
}

void LaneDetector::excludeBox(cv::Mat& R, const cv::Point& centre) {
  const int h = std::max(1, params_.template_size / 4);
  const cv::Rect box = cv::Rect(centre.x - h, centre.y - h, 2 * h + 1, 2 * h + 1) & roi_;
  for (int y = box.y; y < box.y + box.height; ++y) {
    float* r = R.ptr<float>(y);
    for (int x = box.x; x < box.x + box.width; ++x) {
      if (r[x] == 0.f) continue;
      restore_.emplace_back(r + x, r[x]);
      r[x] = 0.f;
    }
  }
}

void LaneDetector::excludeTrace(cv::Mat& R, const MarkerTrace& trace, const cv::Point& peak) {
  // boxes along the traced line (processing pixels), so that the next seed is another line
  if (peak.x >= 0) excludeBox(R, peak);
  const double sx = static_cast<double>(proc_size_.width) / input_size_.width;
  const double sy = static_cast<double>(proc_size_.height) / input_size_.height;
  for (const auto& c : trace.pixels)
    excludeBox(R, cv::Point(static_cast<int>(std::lround((c.x + 0.5) * sx - 0.5)),
                            static_cast<int>(std::lround((c.y + 0.5) * sy - 0.5))));
}

void LaneDetector::classifyCandidates(const Frame& frame) {
  if (!params_.classify_boundaries || !road_.valid) {
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < candidate_count_[side]; ++k) {
        BoundaryEvidence& ev = candidates_[side][k].evidence;
        ev = BoundaryEvidence();
        ev.boundary = true;  // unclassified: every traced line is taken as paint
        ev.margin = 0.5f;
      }
    return;
  }
  const ClassifierInput& in = classifierInput(frame, road_);
  for (int side = 0; side < 2; ++side)
    for (int k = 0; k < candidate_count_[side]; ++k) {
      BoundaryCandidate& c = candidates_[side][k];
      classifier_.classify(in, c.trace.pixels, side == 0, params_, c.evidence);
      // a painted line: on the paint's centre, row by row, and as far as it goes
      if (c.evidence.boundary && c.evidence.kind == BoundaryKind::kPaint) {
        classifier_.followLine(in, c.trace.pixels, c.trace.points, params_, kFollowGap,
                               params_.max_depth);
        classifier_.centreDoubleLine(in, c.trace.pixels, c.trace.points, params_);
        // a trace where depth is missing (near the car) told its kind by colour alone: the line
        // followed into the depth tells it again (a kerb's bright top is no paint)
        if (!std::isfinite(c.evidence.line_height))
          classifier_.classify(in, c.trace.pixels, side == 0, params_, c.evidence);
      }
      // a kerb or an unpainted edge: where the road surface ends, as far as it goes (not a
      // rail: its head is it)
      if (c.evidence.boundary && c.evidence.kind == BoundaryKind::kRoadEdge &&
          c.evidence.narrow_rows < c.evidence.rows / 2)
        classifier_.followEdge(in, c.trace.pixels, c.trace.points, side == 0, params_, kEdgeGap,
                               params_.max_depth);
    }
}

const ClassifierInput& LaneDetector::classifierInput(const Frame& frame,
                                                     const PlaneEstimate& plane) {
  ClassifierInput& in = classifier_input_;
  in.colour = &frame.colour;
  in.format = frame.format;
  in.grey = col_map_.empty() ? &grey_ : &grey_input_;
  in.grey_rows = grey_input_rows_;
  in.K = frame.intrinsics;
  in.points = &points_;
  in.filled = road_filled_valid_ ? &road_filled_ : nullptr;
  in.scale_x = static_cast<double>(proc_size_.width) / input_size_.width;
  in.scale_y = static_cast<double>(proc_size_.height) / input_size_.height;
  in.plane = &plane;
  in.frame = PlaneFrame::fromPlane(plane);
  return in;
}

template <typename Lateral>
bool LaneDetector::candidateOnLine(int side, BoundaryKind kind, const PlaneFrame& frame,
                                   double reach, Lateral&& lateral) const {
  for (int k = 0; k < candidate_count_[side]; ++k) {
    const BoundaryCandidate& c = candidates_[side][k];
    if (!c.evidence.boundary || c.evidence.kind != kind) continue;
    int near = 0, total = 0;
    for (const auto& px : c.trace.pixels) {
      const Eigen::Vector3d ray((px.x - proc_K_.cx) / proc_K_.fx, (px.y - proc_K_.cy) / proc_K_.fy,
                                1.0);
      const double den = road_.normal.dot(ray);
      if (!(den < -1e-9)) continue;
      const Eigen::Vector2d q = frame.toPlane(ray * (-road_.distance / den));
      ++total;
      if (std::fabs(q.y() - lateral(q.x())) <= reach) ++near;
    }
    if (total >= params_.min_marker_points && near >= 0.6 * total) return true;
  }
  return false;
}

void LaneDetector::followPredictedLines() {
  const PlaneEstimate& previous = fitter_.previousPlane();
  if (!params_.classify_boundaries || !params_.track_lanes || !road_.valid || !previous.valid)
    return;
  ClassifierInput& in = classifier_input_;  // set by classifyCandidates()
  const PlaneFrame frame = PlaneFrame::fromPlane(road_);
  const double sx = static_cast<double>(proc_size_.width) / input_size_.width;
  const double sy = static_cast<double>(proc_size_.height) / input_size_.height;
  for (int side = 0; side < 2; ++side) {
    if (!fitter_.tracker().valid(side) || fitter_.sideKind(side) != BoundaryKind::kPaint) continue;
    std::vector<BoundaryCandidate>& cands = candidates_[side];
    int& count = candidate_count_[side];
    const LaneTracker& tracker = fitter_.tracker();
    if (candidateOnLine(side, BoundaryKind::kPaint, frame, kPredictedReach,
                        [&](double f) { return tracker.lateral(side, f); }))
      continue;  // the seeds found it: nothing to add
    if (static_cast<int>(cands.size()) <= count) cands.resize(count + 1);
    BoundaryCandidate& c = cands[count];
    MarkerTrace& m = c.trace;
    m.pixels.clear();
    m.points.clear();
    m.scores.clear();
    fitter_.tracker().sample(side, frame, 1.0, samples_);
    for (const auto& q : samples_) {
      if (!(q.z() > 0.1f)) continue;
      const cv::Point2f px(static_cast<float>(proc_K_.fx * q.x() / q.z() + proc_K_.cx),
                           static_cast<float>(proc_K_.fy * q.y() / q.z() + proc_K_.cy));
      m.pixels.push_back(px);
      m.points.push_back(pointAt(cv::Point2f(static_cast<float>((px.x + 0.5) * sx - 0.5),
                                             static_cast<float>((px.y + 0.5) * sy - 0.5))));
      m.scores.push_back(0.f);
    }
    if (m.pixels.size() < 2) continue;
    if (classifier_.followLine(in, m.pixels, m.points, params_, kFollowGap, params_.max_depth,
                               kPredictedReach) < params_.min_marker_points)
      continue;
    classifier_.classify(in, m.pixels, side == 0, params_, c.evidence);
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
    ++count;
  }
}

void LaneDetector::addRoadEdgesFromDepth(const Frame& frame) {
  if (!params_.classify_boundaries || !road_.valid) return;
  RoadEdgeSettings s;
  s.kerb_height = params_.kerb_height;
  s.offset_min = params_.boundary_offset_min;
  s.offset_max = params_.boundary_offset_max;
  s.max_range = std::max(params_.road_fit_range, 1.0);
  s.normal_window = params_.normal_window;
  edge_finder_.find(points_, road_filled_valid_ ? &road_filled_ : nullptr, roi_rows_, proc_K_,
                    col_map_, row_map_, road_, s, depth_edges_[0], depth_edges_[1]);
  const ClassifierInput& in = classifierInput(frame, road_);
  for (int side = 0; side < 2; ++side) {
    const RoadEdgeLine& e = depth_edges_[side];
    if (!e.found) continue;
    const double a = e.offset, b = std::tan(e.heading);
    if (candidateOnLine(side, BoundaryKind::kRoadEdge, in.frame, kEdgeReach,
                        [a, b](double f) { return a + b * f; }))
      continue;  // traced already
    std::vector<BoundaryCandidate>& cands = candidates_[side];
    int& count = candidate_count_[side];
    if (static_cast<int>(cands.size()) <= count) cands.resize(count + 1);
    BoundaryCandidate& c = cands[count];
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
    if (!c.evidence.boundary || c.evidence.kind != BoundaryKind::kRoadEdge) continue;
    ++count;
  }
}

void LaneDetector::measurePaint(const Frame& frame, Result& result) {
  MarkerTrace* traces[6] = {&result.left,           &result.right,
                            &result.outer[kNextLeft], &result.outer[kNextRight],
                            &result.outer[kRoadEdgeLeft], &result.outer[kRoadEdgeRight]};
  for (MarkerTrace* m : traces) m->paint_coverage = m->yellowness = -1.0f;
  if (!params_.classify_boundaries || !result.plane.valid) return;
  const ClassifierInput& in = classifierInput(frame, result.plane);
  for (int k = 0; k < 6; ++k) {
    MarkerTrace& m = *traces[k];
    if (!m.found || m.kind != BoundaryKind::kPaint) continue;
    const bool left = k == 0 || k == 2 || k == 4;
    classifier_.measurePaint(in, m.pixels, left, params_, m.paint_coverage, m.yellowness);
  }
}

void LaneDetector::updateLaneModel(const Frame& frame, Result& result) {
  result.lane_model.valid = false;
  if (!params_.lane_model) return;
  const MarkerTrace* traces[6] = {&result.left,           &result.right,
                                  &result.outer[kNextLeft], &result.outer[kNextRight],
                                  &result.outer[kRoadEdgeLeft], &result.outer[kRoadEdgeRight]};
  int count = 0;
  for (int k = 0; k < 6; ++k) {
    const MarkerTrace& m = *traces[k];
    if (!m.found) continue;
    // a tracked ego side is measured by this frame's chosen line: the tracker's points lag a
    // turning vehicle, and where it bridges a frame without a line they are no measurement
    const bool tracked = k < 2 && params_.track_lanes;
    if (tracked && m.measured.size() < 2) continue;
    BoundaryObservation& o = observations_[count++];
    o.left = k % 2 == 0;
    o.ego = k < 2;
    o.kind = m.kind;
    o.points = tracked ? &m.measured : &m.points;
    o.confidence = m.confidence;
    o.paint_coverage = m.paint_coverage;
    o.yellowness = m.yellowness;
  }
  if (!frame.has_vehicle_frame && !result.plane.valid) {
    lane_model_.update(Eigen::Isometry3d::Identity(), observations_.data(), 0, result.lane_model);
    return;
  }
  const Eigen::Isometry3d T =
      frame.has_vehicle_frame ? frame.vehicle_from_camera : roadAlignedFrame(result.plane);
  lane_model_.update(T, observations_.data(), count, result.lane_model);
}

void LaneDetector::finish(Result& result) {
  result.template_angle_left = left_template_.angle;
  result.template_angle_right = right_template_.angle;
  result.response_left = response_left_;
  result.response_right = response_right_;
  result.geometric = geometric_;
  result.half_binary = half_binary_;
  result.roi = roi_;
  result.scale = static_cast<double>(proc_size_.width) / input_size_.width;
  updateTemplates(result);
}

void LaneDetector::applyPlaneGate(const cv::Range& rows, cv::Mat& left, cv::Mat& right) {
  // A match on a surface off the lane plane (a truck's stripe, a guard rail) cannot be a road
  // marking: the responses of points farther than plane_gate from the previous plane are removed
  // from both maps (named option, off in the paper mode).
  // Only matches that can become seeds, PCA regions or traces are looked at: below tau_G,
  // R = M, and below the trace and PCA thresholds too nothing takes it.
  const Eigen::Vector3f pn = fitter_.previousPlane().normal.cast<float>();
  const float pd = static_cast<float>(fitter_.previousPlane().distance);
  const float max_off = static_cast<float>(params_.plane_gate);
  const float tau = static_cast<float>(
      std::min({params_.tau_g, params_.trace_threshold, params_.pca_threshold}));
  constexpr int kBlock = 16;
  for (int y = rows.start; y < rows.end; ++y) {
    const float* q = points_.ptr<float>(y);
    float* ml = left.ptr<float>(y);
    float* mr = right.ptr<float>(y);
    for (int x0 = 0; x0 < proc_size_.width; x0 += kBlock) {
      const int x1 = std::min(x0 + kBlock, proc_size_.width);
      float top = 0.f;  // the block's best match (a max the compiler vectorises)
      for (int x = x0; x < x1; ++x) top = std::max(top, std::max(ml[x], mr[x]));
      if (top < tau) continue;
      for (int x = x0; x < x1; ++x) {
        if (ml[x] < tau && mr[x] < tau) continue;
        const float* p = q + 3 * x;
        if (std::fabs(pn.x() * p[0] + pn.y() * p[1] + pn.z() * p[2] + pd) > max_off)
          ml[x] = mr[x] = 0.f;  // NaN (no depth) compares false: kept
      }
    }
  }
}

bool LaneDetector::offRoad(const cv::Point& pixel) const {
  // road_gate: the surface normal at a match, where depth gives one, must be road-like
  if (!params_.road_gate || !params_.use_depth) return false;
  float n[3];
  if (!falsNormalAt(points_, pixel.x, pixel.y, params_.normal_window, proc_K_, col_map_, row_map_,
                    n))
    return false;
  const double up = n[0] * params_.up_x + n[1] * params_.up_y + n[2] * params_.up_z;
  return std::fabs(up) < params_.road_gate_cos;
}

bool LaneDetector::plausibleMarkerAngle(double angle, bool left) const {
  const double deg = angleFromHorizontalDeg(angle, left);
  return deg >= params_.marker_angle_min_deg && deg <= params_.marker_angle_max_deg;
}

void LaneDetector::findBestMatch(const cv::Mat& R, bool left, cv::Point& peak, float& value) {
  cv::Rect area = roi_;
  if (params_.ego_lane_seeds) {
    // the ego lane's left marker lies left of the principal point's column, the right one right
    const int cx = static_cast<int>(std::lround(proc_K_.cx * proc_size_.width / input_size_.width));
    const int split = std::min(std::max(cx, 1), proc_size_.width - 1);
    area = left ? cv::Rect(0, roi_.y, split, roi_.height)
                : cv::Rect(split, roi_.y, proc_size_.width - split, roi_.height);
  }
  double max_v = 0.0;
  cv::Point max_p(-1, -1);
  if (predictedBand(left ? 0 : 1, area)) {
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

bool LaneDetector::predictedBand(int side, const cv::Rect& area) {
  const int band = params_.track_seed_band;
  const PlaneEstimate& previous = fitter_.previousPlane();
  if (!params_.track_lanes || band <= 0 || !previous.valid || !fitter_.tracker().valid(side))
    return false;
  const PlaneFrame frame = PlaneFrame::fromPlane(previous);
  fitter_.tracker().sample(side, frame, 1.0, samples_);
  // per processing row, the columns within `band` of the predicted marker (lo > hi: none)
  band_lo_.assign(proc_size_.height, 1);
  band_hi_.assign(proc_size_.height, 0);
  const double sx = static_cast<double>(proc_size_.width) / input_size_.width;
  const double sy = static_cast<double>(proc_size_.height) / input_size_.height;
  bool any = false;
  cv::Point2d prev;
  bool have_prev = false;
  for (const auto& q : samples_) {
    if (!(q.z() > 0.1f)) continue;
    const cv::Point2d cur((proc_K_.fx * q.x() / q.z() + proc_K_.cx + 0.5) * sx - 0.5,
                          (proc_K_.fy * q.y() / q.z() + proc_K_.cy + 0.5) * sy - 0.5);
    if (have_prev) {
      const int y0 = std::max(area.y, static_cast<int>(std::ceil(std::min(prev.y, cur.y))));
      const int y1 = std::min(area.y + area.height - 1,
                              static_cast<int>(std::floor(std::max(prev.y, cur.y))));
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

void LaneDetector::buildTrace(const cv::Mat& R, const cv::Point& peak, float peak_value,
                              double angle, MarkerTrace& trace) {
  trace.peak_score = peak_value;
  const double inv_s = static_cast<double>(input_size_.width) / proc_size_.width;
  const double inv_sy = static_cast<double>(input_size_.height) / proc_size_.height;
  trace.seed = cv::Point2f(static_cast<float>((peak.x + 0.5) * inv_s - 0.5),
                           static_cast<float>((peak.y + 0.5) * inv_sy - 0.5));
  trace.angle = angle;
  trace.num_valid_points = 0;
  trace.seed_point = pointAt(cv::Point2f(static_cast<float>(peak.x), static_cast<float>(peak.y)));
  if (!(peak_value > params_.trace_threshold)) return;

  TraceParams tp;
  tp.box_size = params_.template_size;
  tp.jump = params_.jump_step;
  tp.threshold = static_cast<float>(params_.trace_threshold);
  tp.max_steps = params_.max_trace_steps;
  tp.gap_steps = params_.gap_steps;
  traceMarker(R, cv::Point2f(static_cast<float>(peak.x), static_cast<float>(peak.y)), angle, tp,
              roi_, trace_pixels_, trace_scores_);
  for (size_t i = 0; i < trace_pixels_.size(); ++i) {
    const cv::Point2f& c = trace_pixels_[i];
    trace.pixels.emplace_back(static_cast<float>((c.x + 0.5) * inv_s - 0.5),
                              static_cast<float>((c.y + 0.5) * inv_sy - 0.5));
    trace.scores.push_back(trace_scores_[i]);
    Eigen::Vector3f pt = pointAt(c);
    if (offRoad(cv::Point(static_cast<int>(std::lround(c.x)), static_cast<int>(std::lround(c.y)))))
      pt.setConstant(std::numeric_limits<float>::quiet_NaN());
    trace.points.push_back(pt);
    if (!std::isnan(pt.z())) ++trace.num_valid_points;
  }
}

Eigen::Vector3f LaneDetector::pointAt(const cv::Point2f& c) const {
  // The centroid's own point, else the depth of the nearest valid pixel in its box on the
  // centroid's ray (never a zero depth).
  const int cx = std::min(std::max(static_cast<int>(std::lround(c.x)), 0), proc_size_.width - 1);
  const int cy = std::min(std::max(static_cast<int>(std::lround(c.y)), 0), proc_size_.height - 1);
  const cv::Vec3f& p = points_.at<cv::Vec3f>(cy, cx);
  if (!std::isnan(p[2])) return Eigen::Vector3f(p[0], p[1], p[2]);
  // ray through the sampled source pixel, scaled to z = 1
  const int sx = col_map_.empty() ? cx : col_map_.at<int>(cx);
  const int sy = row_map_.empty() ? cy : row_map_.at<int>(cy);
  const float rx = static_cast<float>((sx - proc_K_.cx) / proc_K_.fx);
  const float ry = static_cast<float>((sy - proc_K_.cy) / proc_K_.fy);
  const int half = params_.template_size / 2;
  for (int r = 1; r <= half; ++r) {
    for (int dy = -r; dy <= r; ++dy) {
      const int y = cy + dy;
      if (y < 0 || y >= proc_size_.height) continue;
      const int step = (dy == -r || dy == r) ? 1 : 2 * r;
      for (int dx = -r; dx <= r; dx += step) {
        const int x = cx + dx;
        if (x < 0 || x >= proc_size_.width) continue;
        const cv::Vec3f& q = points_.at<cv::Vec3f>(y, x);
        if (std::isnan(q[2])) continue;
        return Eigen::Vector3f(rx * q[2], ry * q[2], q[2]);
      }
    }
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  return Eigen::Vector3f(nan, nan, nan);
}

void LaneDetector::updateTemplates(const Result& result) {
  // Both sides matched above P_PCA: redraw the templates at the PCA angles for the next frame;
  // otherwise return to the default templates. adapt_per_side: each side on its own.
  const bool ok_l = result.left.angle_valid && result.left.peak_score > params_.pca_threshold;
  const bool ok_r = result.right.angle_valid && result.right.peak_score > params_.pca_threshold;
  const bool both = params_.adapt_templates && ok_l && ok_r;
  const bool adapt_l = both || (params_.adapt_templates && params_.adapt_per_side && ok_l);
  const bool adapt_r = both || (params_.adapt_templates && params_.adapt_per_side && ok_r);
  const double nl = adapt_l ? result.left.angle : defaultLeftAngle(params_.template_angle_deg);
  const double nr = adapt_r ? result.right.angle : defaultRightAngle(params_.template_angle_deg);
  if (nl != left_template_.angle || nr != right_template_.angle) {
    next_left_angle_ = nl;
    next_right_angle_ = nr;
    templates_dirty_ = true;
  }
}

}  // namespace rgbd_lane_detector
