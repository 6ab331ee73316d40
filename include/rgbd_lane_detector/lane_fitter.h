/**
 * @file lane_fitter.h
 * @brief Stage 8: the lane plane and the lane boundaries from the traced lines (METHOD.md
 * section 4 and the named improvements).
 *
 * Paper mode: the plane through three marker points (or robust least squares over every marker
 * point), both sides or nothing. Improved mode: the road plane comes from depth (RoadSurface),
 * each side's boundary is the nearest traced line that is a lane boundary (BoundaryClassifier),
 * tracked in the road plane (LaneTracker) and reported on its own with its kind and confidence.
 */
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/boundary_classifier.h"
#include "rgbd_lane_detector/lane_tracker.h"
#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/// One traced line of one side and what the classifier found it to be.
struct BoundaryCandidate {
  MarkerTrace trace;           ///< seed, angle, centroids (input pixels), scores, depth points
  BoundaryEvidence evidence;   ///< kind, or not a boundary
  std::vector<Eigen::Vector2d> road;  ///< (forward, lateral) of its points (RoadFrame x, y)
  double offset = 0.0;         ///< lateral offset of its line at the camera (m, + left)
  double lateral = 0.0;        ///< median lateral position of its points (m, + left): where it is
  double heading = 0.0;        ///< its direction in the road plane (rad, + toward the left)
  bool usable = false;         ///< a boundary on its side, in range, along the road
};

/// Per-frame inputs of the fitter (views).
struct LaneFitInput {
  Intrinsics K;                     ///< of the input image (the traces' pixel coordinates)
  const PlaneEstimate* road = nullptr;  ///< road plane from depth (improved mode; may be invalid)
  double road_range = 0.0;          ///< distance ahead up to which the road plane holds (m)
  /// Candidates of each side (0 left, 1 right), best seed first; [side][0..counts[side]).
  std::array<std::vector<BoundaryCandidate>, 2>* candidates = nullptr;
  std::array<int, 2> counts{{0, 0}};
};

/**
 * @brief Fits the lane plane and reports the lane boundaries of one frame, carrying the lane
 * model between frames. No allocation in steady state.
 */
class LaneFitter {
 public:
  LaneFitter();
  /// Replace the parameters (already sanitised); carried state is kept.
  void setParams(const Params& params) { params_ = params; }
  /// Forget the carried plane and lane model.
  void reset();

  /**
   * @brief Fit one frame.
   * @param[in] in candidates (improved mode) or the single traced line per side (paper mode),
   *            and the road plane from depth when the mode uses it.
   * @param[in,out] result receives left, right and plane.
   */
  void fit(const LaneFitInput& in, Result& result);

  /// Plane of the previous frame (invalid: none).
  const PlaneEstimate& previousPlane() const { return previous_plane_; }
  /// The lane model (for the seed search near the predicted boundaries).
  const LaneTracker& tracker() const { return tracker_; }
  /// What side @p i's tracked boundary is (its kind vote).
  BoundaryKind sideKind(int i) const {
    return kind_score_[i] >= 0.f ? BoundaryKind::kPaint : BoundaryKind::kRoadEdge;
  }

  /**
   * @brief Road-plane geometry of a candidate: its points (depth where the depth lies on the
   * road, else the pixel's ray met with the plane within @p road_range), its offset at the
   * camera and heading (robust line through them), its median lateral position, and whether it
   * can be this side's boundary.
   * @param[in] frame road coordinates of the plane.
   * @param[in] left side of the candidate.
   * @param[in,out] c candidate (trace and evidence in; road, offset, heading, usable out).
   */
  void measure(const Intrinsics& K, const PlaneEstimate& plane, const RoadFrame& frame,
               double road_range, bool left, BoundaryCandidate& c) const;

 private:
  void fitMarkerPlane(const LaneFitInput& in, Result& result);
  /// Improved mode: the steps below, in order.
  void fitBoundaries(const LaneFitInput& in, Result& result);
  /// The plane the boundaries lie on: the road surface from depth, else the best seeds' plane,
  /// else the last plane while a side is tracked (invalid: none); @p road_range is where it holds.
  void boundaryPlane(const LaneFitInput& in, PlaneEstimate& plane, double& road_range);
  /// Each side cleared, with its best seed's image measurements (templates, overlays).
  void takeSeedMeasurements(const LaneFitInput& in, Result& result) const;
  /// Each side's candidates measured on the plane and its boundary chosen (index, or -1), its
  /// road points the side's evidence (evidence_).
  std::array<int, 2> chooseBoundaries(const LaneFitInput& in, const PlaneEstimate& plane,
                                      const RoadFrame& frame, double road_range);
  /// A tracked side whose marker passed under the vehicle (a lane change) becomes the other side.
  void handOverCrossedSide(std::array<int, 2>& chosen);
  /// Side @p i reported in @p m: its kind vote, its points (the tracked model, or a road edge
  /// where it was seen) and its confidence.
  void reportSide(int i, const LaneFitInput& in, const RoadFrame& frame, double road_range,
                  int chosen, double sample_step, MarkerTrace& m);
  /// Side @p i's kind vote and margin updated with its chosen candidate @p c, whose seed @p m takes.
  void voteKind(int i, const BoundaryCandidate& c, MarkerTrace& m);
  /// The next lanes' lines and the road edges beyond the chosen boundaries (result.outer).
  void reportOuterLines(const LaneFitInput& in, const RoadFrame& frame,
                        const std::array<int, 2>& chosen, Result& result) const;
  /// Two sides closer or farther apart than any lane: the less confident one is dropped.
  void dropImplausibleWidth(Result& result) const;
  /// Road edges alone are no lane: nothing is reported without a painted side.
  void requirePaint(Result& result) const;
  /// Index of the candidate chosen as side @p i's boundary this frame, or -1.
  int choose(int i, const LaneFitInput& in);
  bool planePlausible(const PlaneEstimate& plane) const;
  void snapToPlane(const Intrinsics& K, const PlaneEstimate& plane, MarkerTrace& m) const;
  /// Median lane width (m) between the two sides' points, NaN when they do not overlap.
  double laneWidth(const PlaneEstimate& plane, const MarkerTrace& L, const MarkerTrace& R) const;
  void rejectIncomplete(Result& result) const;
  void smoothPlane(PlaneEstimate& plane) const;
  void copyTrace(const MarkerTrace& from, MarkerTrace& to) const;
  /// A road edge seen this frame on its own points @p road (forward, lateral): their robust
  /// quadratic curve over their range, 40 points near to far in @p out (camera frame; empty
  /// when fewer than 5 points fit it).
  void measuredEdge(const std::vector<Eigen::Vector2d>& road, const RoadFrame& frame,
                    std::vector<Eigen::Vector3f>& out) const;

  Params params_;
  PlaneEstimate previous_plane_;
  LaneTracker tracker_;
  std::array<float, 2> kind_score_{{0.f, 0.f}};  ///< > 0 paint, < 0 road edge (decaying vote)
  std::array<float, 2> evidence_margin_{{0.f, 0.f}};  ///< classifier margin, smoothed
  std::array<int, 2> disagree_{{0, 0}};        ///< frames a nearer line than the track was seen
  std::array<double, 2> disagree_offset_{{0.0, 0.0}};  ///< where it was last seen
  std::vector<Eigen::Vector3f> fit_points_;
  std::vector<Eigen::Vector3f> samples_;
  std::array<std::vector<Eigen::Vector3f>, 2> evidence_;
  mutable std::vector<double> width_samples_;
  mutable std::vector<double> laterals_;
  const std::vector<Eigen::Vector3f> none_;
};

}  // namespace rgbd_lane_detector
