/**
 * @file lane_detector.h
 * @brief The detector facade: runs every stage of the method in order on one RGB-D frame.
 */
#pragma once

#include <array>
#include <vector>

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/boundary_candidates.h"
#include "rgbd_lane_detector/boundary_classifier.h"
#include "rgbd_lane_detector/depth_points.h"
#include "rgbd_lane_detector/fals_normals.h"
#include "rgbd_lane_detector/lane_fitter.h"
#include "rgbd_lane_detector/lane_model.h"
#include "rgbd_lane_detector/line_template.h"
#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/road_surface.h"
#include "rgbd_lane_detector/template_matching.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/**
 * @brief Lane marker and lane plane detector (Quach et al.), ROS-free.
 *
 * detect() runs the stages in order: pre-processing (half-binary image), depth to points, the
 * road surface from depth (improved mode; extended toward the camera where depth is missing),
 * template matching, normals with the geometric map G where it enters R, the response map R,
 * boundary candidates (seeds, PCA angle, sliding-box tracing) per side, their classification
 * (paint, road edge, no boundary), and the lane fit (LaneFitter), paint measurements and the lane
 * model.
 * Carries state between frames: the PCA-refined template angles and, with the temporal
 * options, the previous plane and the lane model. Call reset() when the stream restarts
 * (rosbag loop, seek).
 * Not thread-safe: one detector per thread. Buffers are allocated on the first frame and on
 * size changes only, so with a reused Result the steady state does not allocate.
 */
/**
 * @brief The processing scale detect() uses for frames of @p size and @p intrinsics: @p
 * params.processing_scale when it is set (> 0), else the automatic choice. The templates are
 * made for a lane line about 20 px wide at the nearest rows (the paper's 640x380 R200 frames,
 * KITTI's 1242x375); a lane line of 10 cm on a road params.camera_height below the camera has,
 * at the bottom image row v, the width 0.10 (v - cy) / camera_height px whatever the focal
 * length. The automatic scale brings that to 24 px (no resampling when it is already narrower,
 * or when the scale would be above 0.8: resampling costs more than it saves): a 1920x1080 camera
 * is processed at about 1280x720, a 640x480, 1280x760 or 1242x375 one as it is.
 */
double processingScale(const Params& params, const cv::Size& size, const Intrinsics& intrinsics);

class LaneDetector {
 public:
  explicit LaneDetector(const Params& params = Params());

  /// Replace the parameters (sanitised); applies from the next detect(). New template geometry
  /// starts the adapted template angles again; the lane, the lane model and the plane stay.
  void setParams(const Params& params);
  const Params& params() const { return params_; }

  /// Forget carried state (template angles, previous plane, lane model).
  void reset();

  /**
   * @brief Allocate and plan everything for frames of one size and camera, so that the first
   * detect() on such frames costs about a steady-state frame: call it when the camera_info (or
   * the first frame's size) arrives. Runs detect() on a generated frame (grey road plane in front
   * of the camera), then reset(): carried state is forgotten. Allocates.
   * @param[in] size colour (and depth) image size.
   * @param[in] intrinsics the colour camera's.
   * @param[in] format colour layout of the coming frames.
   * @return what detect() returns for such frames (kOk, or why they would be refused).
   */
  Status prepare(const cv::Size& size, const Intrinsics& intrinsics,
                 PixelFormat format = PixelFormat::kBgr8);

  /**
   * @brief The vehicle moved since the last frame (odometry): the lane model is moved with it
   * before the next detect() (lane_model option; no effect otherwise).
   * @param[in] motion pose of the vehicle frame now in the vehicle frame at the last frame.
   */
  void predictMotion(const Eigen::Isometry3d& motion) { lane_model_.predict(motion); }

  /**
   * @brief Detect the lane markers and the lane plane in one frame.
   * @param[in] frame colour, registered depth and intrinsics (read in place).
   * @param[out] result reused output; see Result for buffer lifetimes.
   * @return result.status; on anything but Status::kOk the result holds no detection and the
   *         carried state is unchanged.
   */
  Status detect(const Frame& frame, Result& result);

  /**
   * @brief Whether Result::geometric holds G at every pixel of the searched rows (for the
   * response/geometric image), or, by default, only where G enters R (M >= tau_G in any match
   * map, fusionMask()) and 0 elsewhere. The default computes the normals only there, which
   * saves most of the normals stage; R and the detections are the same either way. The full
   * map is computed next to matching on two cores when OpenCV may use two threads (runPair()).
   * Applies from the next detect().
   */
  void setFullGeometricMap(bool full) { full_geometric_ = full; }
  bool fullGeometricMap() const { return full_geometric_; }

  /// Check a frame without processing it.
  Status validate(const Frame& frame) const;

  /**
   * @brief The lines traced on one side in the last detect(), best seed first, with what the
   * classifier found them to be (overlays, tuning).
   * @param[in] side 0 left, 1 right.
   * @param[out] count number of candidates.
   * @return the candidates (valid until the next detect() or setParams()).
   */
  const BoundaryCandidate* candidates(int side, int& count) const {
    return finder_.candidates(side, count);
  }

  /// Templates that the next detect() will use.
  const LineTemplate& leftTemplate() const { return left_template_; }
  const LineTemplate& rightTemplate() const { return right_template_; }

 private:
  /// The templates start again from the parameters' angles (made at the next frame).
  void resetTemplates();
  /// The stages of a validated frame, in order; each times itself (StageTimer into timings_).
  void runStages(const Frame& frame, Result& result);
  /// The processing image's geometry (prepareGeometry()), the templates of this frame, the
  /// sides that acquire.
  void prepareFrame(const Frame& frame);
  /// 1. The half-binary image (and the classifier's grey).
  void preprocess(const Frame& frame);
  /// 2. Organised 3D points of the searched rows.
  void computePoints(const Frame& frame);
  /// The road plane from depth (improved mode), near the vehicle's up axis when the frame gives
  /// the camera's pose, held over a fit that jumps from the last plane, extended toward the
  /// camera where depth is missing (RoadSurface::extendToCamera()).
  void fitRoadSurface(const Frame& frame);
  /// 3.-5. Normals and G, template matching, the plane gate, R: the steps below.
  void computeResponses();
  /// 3. Normals and G, everywhere or (@p mask) only where G enters R.
  void computeGeometric(const cv::Mat* mask);
  /// 4. NCC matching with the templates (and the acquisition templates of the sides that acquire);
  /// @p mark: the first pass of maskFusion() with the scores (NccMatcher::Mark).
  void matchTemplates(bool mark = false);
  /// plane_gate acts this frame (gateByPlane(), gatedFusionMask()).
  bool planeGate() const;
  /// plane_gate: matches off the previous frame's plane removed (applyPlaneGate()).
  void gateByPlane();
  /// Where G enters R (fusionMask()); @p gate: gateByPlane() in the same pass (gatedFusionMask()).
  void maskFusion(bool gate);
  /// 5. R of every matched map.
  void fuseResponses();
  /// A side acquires this frame (its acquisition template is matched too).
  bool acquiring() const { return acquiring_[0] || acquiring_[1]; }
  /// The match maps of this frame: both sides', then the acquisition map of each side that
  /// acquires (a side with a tracked boundary has none: its map is neither matched nor read).
  cv::Mat* const* matchMaps() {
    match_maps_[0] = &response_left_;
    match_maps_[1] = &response_right_;
    int n = 2;
    if (acquiring_[0]) match_maps_[n++] = &acquisition_response_left_;
    if (acquiring_[1]) match_maps_[n++] = &acquisition_response_right_;
    return match_maps_;
  }
  /// How many maps matchMaps() holds.
  int matchMapCount() const { return 2 + int{acquiring_[0]} + int{acquiring_[1]}; }
  /// 6.-7. Each side's seeds, PCA angles and traced lines (BoundaryCandidateFinder).
  void traceCandidates(const Frame& frame);
  /// What each traced line is: paint, road edge or no boundary (improved mode).
  void classifyCandidates();
  /// 8. The lane plane and boundaries (LaneFitter).
  void fitLane(Result& result);
  /// Paint coverage (dashed / solid) and colour of every reported painted boundary.
  void measurePaint(const Frame& frame, Result& result);
  /// lane_model: the Kalman filter of the lane in the vehicle frame.
  void updateLaneModel(const Frame& frame, Result& result);
  void finish(Result& result);

  void prepareGeometry(const Frame& frame);
  /// The frame as the candidate search sees it (candidate_frame_).
  const CandidateFrame& candidateFrame(const Frame& frame);
  void resampleColour(const Frame& frame);
  void updateTemplates(const Result& result);

  Params params_;
  // carried state
  double next_left_angle_ = 0.0;
  double next_right_angle_ = 0.0;
  bool templates_dirty_ = true;

  // geometry of the processing image
  cv::Size input_size_;
  cv::Size proc_size_;
  double scale_ = 1.0;
  Intrinsics proc_K_;
  cv::Rect roi_;
  cv::Range roi_rows_;
  cv::Mat col_map_, row_map_;  ///< CV_32SC1 source column / row of each processing pixel

  // per-frame buffers (allocated on size change only)
  cv::Mat colour_small_;
  cv::Mat* match_maps_[4] = {};  ///< matchMaps()
  cv::Mat depth_blocks_;  ///< depthBlocks() of points_ (before the road's extension)
  cv::Mat grey_;        ///< grey of the searched rows at the processing scale (improved mode)
  cv::Range grey_input_rows_;  ///< rows of the input image that the classifier's grey covers
  cv::Mat half_binary_;
  cv::Mat points_;
  DepthPointsTables depth_tables_;  ///< depthToPoints()'s tables
  cv::Mat road_filled_;  ///< 255 where points_ holds the road plane, not depth (RoadSurface::extendToCamera())
  bool road_filled_valid_ = false;  ///< road_filled_ belongs to this frame
  cv::Mat geometric_;
  bool full_geometric_ = false;  ///< setFullGeometricMap()
  cv::Mat fusion_mask_;          ///< where G enters R (fusionMask())
  NccMatcher::Mark fusion_mark_;  ///< matchTemplates()'s first pass of fusion_mask_
  cv::Mat response_left_, response_right_;
  StageTimings timings_;

  FalsNormals fals_;
  NccMatcher matcher_;
  LineTemplate left_template_, right_template_;
  // acquisition: templates at acquisition_angle_deg for sides without a tracked boundary
  LineTemplate acquisition_left_, acquisition_right_;
  cv::Mat acquisition_response_left_, acquisition_response_right_;
  std::array<bool, 2> acquiring_{{false, false}};
  RoadSurface road_surface_;
  PlaneEstimate road_;
  int plane_holds_ = 0;  ///< frames in a row whose fit jumped from the last plane (kept instead)
  /// Fitted planes at the mount's height minus those far from it (clamped); below 0 the mount's
  /// plane does not stand in for a frame without a fit.
  int mount_evidence_ = 0;
  CandidateFrame candidate_frame_;
  BoundaryCandidateFinder finder_;
  BoundaryClassifier paint_classifier_;  ///< measurePaint()
  ClassifierInput paint_input_;
  LaneFitter fitter_;
  LaneModelFilter lane_model_;
  bool model_in_vehicle_frame_ = false;  ///< lane_model_'s frame: the vehicle's, else the road's
  std::array<BoundaryObservation, 6> observations_;
  std::vector<int> row_histogram_;
};

}  // namespace rgbd_lane_detector
