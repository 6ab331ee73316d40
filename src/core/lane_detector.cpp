// The detector facade: its parameters and carried state, the stages of a frame in order
// (runStages()) and each stage's use of the core. The processing image (scale, maps, ROI) and
// the validation of a frame: processing_image.cpp.
#include "rgbd_lane_detector/lane_detector.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "rgbd_lane_detector/adaptive_threshold.h"
#include "rgbd_lane_detector/depth_points.h"
#include "rgbd_lane_detector/half_binary.h"
#include "rgbd_lane_detector/lane_plane.h"
#include "rgbd_lane_detector/parallel.h"
#include "rgbd_lane_detector/pca_refinement.h"
#include "rgbd_lane_detector/pixel_kernels.h"
#include "rgbd_lane_detector/response_map.h"
#include "rgbd_lane_detector/sliding_box.h"
#include "rgbd_lane_detector/stage_timer.h"

namespace rgbd_lane_detector {

LaneDetector::LaneDetector(const Params& params) { setParams(params); }

void LaneDetector::setParams(const Params& params) {
  const Params p = sanitize(params);
  // New template geometry invalidates the adapted angles; any other change keeps the carried
  // state (a reconfigure must not throw away the PCA adaptation or the lane model).
  const bool new_templates = !sameTemplates(p, params_) || left_template_.size == 0;
  params_ = p;
  finder_.setParams(p);
  fitter_.setParams(p);
  LaneModelSettings ms;
  ms.gate = p.model_gate;
  ms.lost_frames = p.model_lost_frames;
  if (p.lane_width_max > 0.0) {  // else no lane width check: the model's own plausible widths
    ms.width_min = p.lane_width_min;
    ms.width_max = p.lane_width_max;
  }
  ms.x_max = p.max_depth;
  ms.dashed_coverage = p.dashed_coverage;
  ms.yellowness = p.yellow_threshold;
  lane_model_.setSettings(ms);
  if (new_templates) resetTemplates();
}

void LaneDetector::resetTemplates() {
  next_left_angle_ = defaultLeftAngle(params_.template_angle_deg);
  next_right_angle_ = defaultRightAngle(params_.template_angle_deg);
  templates_dirty_ = true;
}

void LaneDetector::reset() {
  resetTemplates();
  fitter_.reset();
  lane_model_.reset();
  road_.valid = false;
  plane_holds_ = 0;
  mount_evidence_ = 0;
}

Status LaneDetector::prepare(const cv::Size& size, const Intrinsics& intrinsics,
                             PixelFormat format) {
  // A frame as a camera 1.5 m above a flat grey road sees it (no markers): every buffer, table
  // and plan of detect() is made for this size, the memory touched once. A camera detect() would
  // refuse is refused here, before anything is allocated.
  if (size.width <= 0 || size.height <= 0) return Status::kEmptyImage;
  if (!intrinsics.valid()) return Status::kInvalidIntrinsics;
  Frame f;
  f.format = format;
  f.intrinsics = intrinsics;
  f.colour.create(size, CV_8UC(pixelLayout(format).channels));
  f.colour.setTo(cv::Scalar::all(90));
  f.depth.create(size, CV_32FC1);
  for (int v = 0; v < size.height; ++v) {
    const double below = intrinsics.fy > 0.0 ? (v - intrinsics.cy) / intrinsics.fy : 0.0;
    f.depth.row(v).setTo(below > 0.02 ? 1.5 / below : std::numeric_limits<double>::quiet_NaN());
  }
  Result r;
  const Status status = detect(f, r);
  reset();
  return status;
}

Status LaneDetector::detect(const Frame& frame, Result& result) {
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
  {
    const StageTimer total(timings_.total);
    runStages(frame, result);
  }
  result.timings = timings_;
  return Status::kOk;
}

void LaneDetector::runStages(const Frame& frame, Result& result) {
  // Numbered as in METHOD.md and the stages' files; the improvements without a number.
  prepareFrame(frame);            // the processing image's geometry, this frame's templates
  preprocess(frame);              // 1. half-binary image
  computePoints(frame);           // 2. organised 3D points
  fitRoadSurface(frame);          // the road plane from depth, extended where depth is missing
  computeResponses();             // 3.-5. normals and G, template matching, R
  traceCandidates(frame);         // 6.-7. each side's seeds, PCA angles and traced lines
  classifyCandidates();           // paint, road edge or no boundary
  fitLane(result);                // 8. the lane plane and boundaries
  measurePaint(frame, result);    // dashed or solid, white or yellow
  updateLaneModel(frame, result); // the lane model for planners
  finish(result);
}

void LaneDetector::prepareFrame(const Frame& frame) {
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
}

void LaneDetector::traceCandidates(const Frame& frame) {
  const CandidateFrame& cf = candidateFrame(frame);
  finder_.clear();
  for (int side = 0; side < 2; ++side) {
    finder_.traceLines(cf, side, side == 0 ? response_left_ : response_right_);
    if (acquiring_[side])
      finder_.traceLines(cf, side, side == 0 ? acquisition_response_left_ : acquisition_response_right_);
  }
  timings_.pca = finder_.pcaMs();
  timings_.tracing = finder_.tracingMs();
}

void LaneDetector::classifyCandidates() {
  const StageTimer timer(timings_.classify);
  finder_.classify(candidate_frame_);
  finder_.traceBesidePaint(candidate_frame_, response_left_, response_right_);
  finder_.traceLoneDash(candidate_frame_);
}

void LaneDetector::fitLane(Result& result) {
  const StageTimer timer(timings_.plane);
  LaneFitInput fit;
  fit.K = proc_K_;
  fit.road = &road_;
  fit.road_range = road_.valid ? road_.range : 0.0;
  fit.candidates = &finder_.candidates();
  fit.counts = finder_.counts();
  fitter_.fit(fit, result);
}

void LaneDetector::preprocess(const Frame& frame) {
  const StageTimer timer(timings_.preprocess);
  const bool scaled = !col_map_.empty();
  if (params_.classify_boundaries) {
    // the classifier measures profiles on the input image: its grey over the searched rows
    const double sy = static_cast<double>(input_size_.height) / proc_size_.height;
    grey_input_rows_ = cv::Range(
        std::max(0, static_cast<int>(std::floor(roi_rows_.start * sy))),
        std::min(input_size_.height, static_cast<int>(std::ceil(roi_rows_.end * sy))));
  }
  if (scaled && params_.classify_boundaries) {
    // the processing grey straight from the input's pixels (the colour is never resampled; the
    // classifier computes the input's grey where it reads it)
    halfBinary(frame.colour, frame.format, 0, roi_rows_, grey_, col_map_, row_map_);
    if (params_.adaptive_tau_c)
      applyRowThreshold(grey_, half_binary_, roi_rows_, params_.tau_c_offset, row_histogram_,
                        params_.paint_contrast);
    else  // the half-binary image of a grey image: its pixels at tau_c or above
      halfBinary(grey_, PixelFormat::kMono8, params_.tau_c, roi_rows_, half_binary_);
    return;
  }
  resampleColour(frame);
  const cv::Mat& colour = scaled ? colour_small_ : frame.colour;
  // the grey image (a half-binary image at threshold 0) when the adaptive threshold or the
  // classifier reads it (unscaled: the classifier's grey is this one)
  const bool grey = params_.adaptive_tau_c || params_.classify_boundaries;
  if (grey) halfBinary(colour, frame.format, 0, roi_rows_, grey_);
  if (params_.adaptive_tau_c) {
    // per-row threshold: row median + offset (fog, overpasses, shadows change the road's grey)
    applyRowThreshold(grey_, half_binary_, roi_rows_, params_.tau_c_offset, row_histogram_,
                      params_.classify_boundaries ? params_.paint_contrast : 0.0);
  } else {
    halfBinary(colour, frame.format, params_.tau_c, roi_rows_, half_binary_);
  }
}

void LaneDetector::computePoints(const Frame& frame) {
  const StageTimer timer(timings_.points);
  // the ROI plus the normal window's margin, read through the maps: exact back-projection of
  // each sampled source pixel
  const int h = params_.normal_window / 2;
  const cv::Range point_rows(std::max(0, roi_.y - h),
                             std::min(proc_size_.height, roi_.y + roi_.height + h));
  DepthDecoder decoder;
  decoder.scale = frame.depth_scale;
  decoder.min_depth = params_.min_depth;
  decoder.max_depth = params_.max_depth;
  depthToPoints(frame.depth, decoder, proc_K_, point_rows, points_, col_map_, row_map_,
                &depth_blocks_, &depth_tables_);
  if (params_.fill_depth_holes > 0) {
    fillDepthHoles(points_, point_rows, params_.fill_depth_holes);
    depthBlocks(points_, point_rows, depth_blocks_);
  }
  road_surface_.setDepthBlocks(&depth_blocks_);  // the fit and the extension pass empty blocks
}

void LaneDetector::computeResponses() {
  if (!params_.use_depth) {  // without depth, R = M
    matchTemplates();
    if (geometric_.size() != proc_size_ || geometric_.type() != CV_32FC1) {
      geometric_.create(proc_size_, CV_32FC1);
      geometric_.setTo(0);
    } else {
      geometric_(roi_).setTo(0);
    }
    return;
  }
  if (full_geometric_) {
    // G everywhere does not depend on M: 3 and 4 on two cores when OpenCV may use two threads
    // (each timing is then its own stage's, and they overlap)
    runPair([this] { computeGeometric(nullptr); }, [this] { matchTemplates(); });
  } else {
    matchTemplates(true);
  }
  const bool gate = planeGate();
  if (gate && full_geometric_) gateByPlane();
  if (!full_geometric_) {
    // R needs G only where M >= tau_G (about 1% of the pixels of a road): G there only, which
    // saves most of the normals stage (the gate in the same pass over the maps)
    maskFusion(gate);
    computeGeometric(&fusion_mask_);
  }
  fuseResponses();
}

void LaneDetector::computeGeometric(const cv::Mat* mask) {
  // 3. normals, and G (Eq. 2) in the same pass (no normal image is kept), for every pixel or
  // (mask given) only where G enters R.
  const StageTimer timer(timings_.normals);
  fals_.configure(proc_size_, proc_K_, params_.normal_window, col_map_, row_map_);
  if (mask)
    fals_.computeGeometric(points_, roi_rows_, params_, *mask, geometric_);
  else
    fals_.computeGeometric(points_, roi_rows_, params_, geometric_);
}

void LaneDetector::matchTemplates(bool mark) {
  // 4. matching, with the acquisition templates too for the sides that acquire: one pass (the
  // window sums shared), each map as its template alone gives it
  const StageTimer timer(timings_.matching);
  const LineTemplate* templates[4] = {&left_template_, &right_template_};
  int n = 2;
  if (acquiring_[0]) templates[n++] = &acquisition_left_;
  if (acquiring_[1]) templates[n++] = &acquisition_right_;
  // the fusion mask's pass over the maps (maskFusion()) made while they are scored: where a map
  // reaches the lowest level the gate or the mask acts at
  fusion_mark_ = NccMatcher::Mark();
  const Params& p = params_;
  const float tau_g = static_cast<float>(p.tau_g);
  fusion_mark_.level =
      planeGate()
          ? std::min(static_cast<float>(std::min({p.tau_g, p.trace_threshold, p.pca_threshold})),
                     tau_g)
          : tau_g;
  fusion_mark_.mask = &fusion_mask_;
  matcher_.match(half_binary_, roi_, templates, matchMaps(), n, mark ? &fusion_mark_ : nullptr);
}

bool LaneDetector::planeGate() const {
  return params_.plane_gate > 0.0 && fitter_.previousPlane().valid;
}

void LaneDetector::gateByPlane() {
  // a match off the lane plane is no road marking; only what can become a seed, a PCA region or
  // a trace is looked at (below tau_G, R = M)
  const StageTimer timer(timings_.response);
  const Params& p = params_;
  const PlaneEstimate& previous = fitter_.previousPlane();
  const float max_off = static_cast<float>(p.plane_gate);
  const float tau = static_cast<float>(std::min({p.tau_g, p.trace_threshold, p.pca_threshold}));
  applyPlaneGate(points_, roi_rows_, previous, max_off, tau, response_left_, response_right_);
  // (one acquiring side: its map gated alone, as its own pair)
  cv::Mat* const* maps = matchMaps();
  if (acquiring())
    applyPlaneGate(points_, roi_rows_, previous, max_off, tau, *maps[2],
                   *maps[matchMapCount() - 1]);
}

void LaneDetector::maskFusion(bool gate) {
  const StageTimer timer(timings_.normals);
  const float tau = static_cast<float>(params_.tau_g);
  if (gate) {  // gateByPlane()'s gate first
    const Params& p = params_;
    const float low = static_cast<float>(std::min({p.tau_g, p.trace_threshold, p.pca_threshold}));
    gatedFusionMask(points_, fitter_.previousPlane(), static_cast<float>(p.plane_gate), low,
                    matchMaps(), matchMapCount(), tau, roi_rows_, fusion_mask_,
                    fusion_mark_.marked);
    return;
  }
  if (fusion_mark_.marked) return;  // (the mark at tau_G is the mask)
  cv::Mat* const* maps = matchMaps();
  switch (matchMapCount()) {
    case 2:
      fusionMask({maps[0], maps[1]}, tau, roi_rows_, fusion_mask_);
      break;
    case 3:
      fusionMask({maps[0], maps[1], maps[2]}, tau, roi_rows_, fusion_mask_);
      break;
    default:
      fusionMask({maps[0], maps[1], maps[2], maps[3]}, tau, roi_rows_, fusion_mask_);
  }
}

void LaneDetector::fuseResponses() {
  // 5. R
  const StageTimer timer(timings_.response);
  const float tau = static_cast<float>(params_.tau_g);
  if (!full_geometric_) {  // G where the fusion mask is: R = M elsewhere
    fuseResponseMasked(matchMaps(), matchMapCount(), geometric_, tau, roi_rows_, fusion_mask_);
    return;
  }
  cv::Mat* const* maps = matchMaps();
  for (int i = 0; i < matchMapCount(); ++i)
    fuseResponse(*maps[i], geometric_, tau, roi_rows_, *maps[i]);
}

const CandidateFrame& LaneDetector::candidateFrame(const Frame& frame) {
  CandidateFrame& f = candidate_frame_;
  f.colour = &frame.colour;
  f.format = frame.format;
  f.grey = col_map_.empty() ? &grey_ : nullptr;  // resampled: from the colour
  f.grey_rows = grey_input_rows_;
  f.K = proc_K_;
  f.input_size = input_size_;
  f.proc_size = proc_size_;
  f.roi = roi_;
  f.roi_rows = roi_rows_;
  f.col_map = &col_map_;
  f.row_map = &row_map_;
  f.points = &points_;
  f.filled = road_filled_valid_ ? &road_filled_ : nullptr;
  f.road = &road_;
  f.fitter = &fitter_;
  f.template_angle = {left_template_.angle, right_template_.angle};
  return f;
}

void LaneDetector::measurePaint(const Frame& frame, Result& result) {
  const StageTimer timer(timings_.model);
  MarkerTrace* traces[6] = {&result.left,           &result.right,
                            &result.outer[kNextLeft], &result.outer[kNextRight],
                            &result.outer[kRoadEdgeLeft], &result.outer[kRoadEdgeRight]};
  for (MarkerTrace* m : traces) m->paint_coverage = m->yellowness = -1.0f;
  if (!params_.classify_boundaries || !result.plane.valid) return;
  classifierInputOf(candidateFrame(frame), result.plane, paint_input_);
  const ClassifierInput& in = paint_input_;
  for (int k = 0; k < 6; ++k) {
    MarkerTrace& m = *traces[k];
    if (!m.found || m.kind != BoundaryKind::kPaint) continue;
    const bool left = k == 0 || k == 2 || k == 4;
    paint_classifier_.measurePaint(in, m.pixels, left, params_, m.paint_coverage, m.yellowness);
  }
}

void LaneDetector::updateLaneModel(const Frame& frame, Result& result) {
  const StageTimer timer(timings_.model);
  result.lane_model.valid = false;
  // switched off: its state is stale when it is switched on again (ages advance in updates)
  if (!params_.lane_model) {
    lane_model_.reset();
    return;
  }
  // its state lies in the frame it was updated in: the vehicle frame (tf), or the road frame
  // under the camera when tf did not give the vehicle's (late, or not yet there)
  if (frame.has_vehicle_frame != model_in_vehicle_frame_) {
    lane_model_.reset();
    model_in_vehicle_frame_ = frame.has_vehicle_frame;
  }
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
      frame.has_vehicle_frame ? frame.vehicle_from_camera
                              : RoadFrame::fromPlane(result.plane).roadFromCamera();
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
