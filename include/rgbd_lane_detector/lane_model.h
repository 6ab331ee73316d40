/**
 * @file lane_model.h
 * @brief The lane model planners consume: typed boundaries as cubics in the vehicle frame, the
 * ego lane's width, offset, heading and curvature, tracked by a Kalman filter (improved mode's
 * last stage, after the detector's per-frame boundaries).
 *
 * Vehicle frame (REP-103): x forward, y left, z up, origin on the road under the vehicle
 * reference point (base_link, or the road-aligned frame under the camera:
 * RoadFrame::roadFromCamera(), geometry.h). Each boundary is y(x) = c0 + c1 x + c2 x^2 + c3 x^3 over [x_min, x_max]:
 * c0 its lateral offset at the vehicle (m, + left), atan(c1) its heading relative to the
 * vehicle's x axis, 2 c2 its curvature at x = 0 (1/m, + turning left; c2 is the raw x^2
 * coefficient, half the curvature, as in Apollo's LaneMarker), 6 c3 the curvature's rate of
 * change along x (1/m^2).
 *
 * The filter's state is the ego lane: the lateral position of its centre line at the vehicle
 * y0, its heading psi (the centre line's slope dy/dx = tan psi at x = 0), curvature kappa,
 * curvature rate kappa', width w, the speed vy at which y0 changes per update and the rate
 * omega at which the slope changes per update (the vehicle drifting, turning or changing lanes;
 * without odometry these carry the model between sightings). Its centre line is y(x) = y0 +
 * tan(psi) x + kappa x^2 / 2 + kappa' x^3 / 6, the ego boundaries are that line +-w/2.
 * Measurements are each frame's boundaries in the vehicle frame, each reduced to up to kStations
 * stations (the median point of each of kStations equal stretches of its x range: robust to a
 * few stray points, spread along the line whatever the density of its points), associated with
 * the model by their lateral offset: the ego sides, the next lanes' lines and the road edges. A measurement one lane width from the ego
 * side it would belong to, on the side the vehicle moves to, is a lane change: the model is
 * relabelled (the old right line becomes the new left one) instead of being lost. Measurements
 * farther than the gate from every boundary are ignored, stations beyond 3 sigmas of the model
 * skipped and those beyond 1.5 sigmas down-weighted (Huber); a boundary whose measurements
 * scatter from frame to frame (a kerb, one line of a double line or the other) counts less. When
 * for 3 frames the detector sees its ego lane and the model takes none of it, the model starts
 * over from this frame; after lost_frames frames without an ego measurement it is reset. An
 * optional motion between stamps (odom -> base_link) moves the model before the update. Nothing
 * is published beyond an ego boundary that is a road edge.
 *
 * Each boundary is published over the range of its recent sightings (an ego boundary: of the ego
 * lane's, both sides being the one lane's edges) as far as its lateral standard deviation stays
 * within 0.1 m, with its kind (solid / dashed from the paint coverage, road edge by a vote),
 * colour, age and an evidence score; its confidence is that evidence calibrated
 * (calibratedConfidence()).
 */
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rgbd_lane_detector/geometry.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/// One boundary seen in a frame, in the camera optical frame (what the detector reports).
struct BoundaryObservation {
  bool left = true;                       ///< left of the vehicle
  bool ego = true;                        ///< the detector's ego side (else a line beyond it)
  BoundaryKind kind = BoundaryKind::kPaint;
  const std::vector<Eigen::Vector3f>* points = nullptr;  ///< on the road, optical frame
  float confidence = 0.0f;                ///< the detector's confidence in it
  float paint_coverage = -1.0f;           ///< share of its length with paint (< 0: unknown)
  float yellowness = -1.0f;               ///< yellow vs white evidence of its paint (< 0: unknown)
};

/// Settings of the lane model filter (filled from Params).
struct LaneModelSettings {
  double gate = 0.5;             ///< m: measurements farther from every boundary are ignored
  int lost_frames = 10;          ///< frames without an ego measurement before a reset
  double measurement_std = 0.02; ///< m: lateral noise of a boundary point at 10 m (linear in x)
  double width_min = 0.8, width_max = 5.5;  ///< plausible lane widths (m)
  double x_max = 60.0;           ///< longest range reported (m)
  double dashed_coverage = 0.8;  ///< paint coverage below this is a dashed line
  double yellowness = 0.25;      ///< paint more yellow than this is yellow
};

/**
 * @brief Kalman filter of the ego lane with its neighbours' boundaries and the road edges.
 * No allocation in steady state.
 */
class LaneModelFilter {
 public:
  LaneModelFilter();
  /// Forget the model.
  void reset();
  /// Replace the settings (the model is kept).
  void setSettings(const LaneModelSettings& s) { settings_ = s; }

  /**
   * @brief Move the model by the vehicle's motion since the last update (odom -> base_link).
   * @param[in] motion pose of the vehicle now in the vehicle frame of the last update.
   */
  void predict(const Eigen::Isometry3d& motion);

  /**
   * @brief Update with one frame's boundaries.
   * @param[in] vehicle_from_camera pose of the camera optical frame in the vehicle frame.
   * @param[in] observations this frame's boundaries (any order; empty: nothing seen).
   * @param[in] count number of observations.
   * @param[out] model the model after the update (valid false when no ego lane is known).
   */
  void update(const Eigen::Isometry3d& vehicle_from_camera,
              const BoundaryObservation* observations, int count, LaneModelEstimate& model);

 private:
  /// y0, slope tan(psi), kappa, kappa', w, the lane's sideways speed vy (m per update) and the
  /// rate of its slope omega (per update)
  using State = Eigen::Matrix<double, 7, 1>;
  using Cov = Eigen::Matrix<double, 7, 7>;
  using Row = Eigen::Matrix<double, 1, 7>;
  static constexpr int kStations = 10;       ///< stations kept per observation
  /// BoundaryPosition p: even on the left, odd on the right; 0 and 1 the ego lane's.
  static bool isLeft(int p) { return p % 2 == 0; }
  static bool isEgo(int p) { return p < 2; }
  /// The ego boundary on p's side.
  static int egoOf(int p) { return isLeft(p) ? 0 : 1; }
  static constexpr int kMaxPoints = 2048;    ///< points of an observation used (thinned beyond)

  /// One observation in the vehicle frame: up to kStations (x, y) samples, near to far.
  struct Track {
    std::array<Eigen::Vector2d, kStations> xy;
    int n = 0;
    double x_min = 0.0, x_max = 0.0;
    const BoundaryObservation* obs = nullptr;
    int assigned = -1;  ///< BoundaryPosition it was associated with, -1: none
  };
  /// What is remembered of each boundary position between frames.
  static constexpr int kRangeFrames = 3;  ///< recent sightings whose ranges are published
  struct Memory {
    int frames = 0;           ///< frames it was seen since it appeared
    int age = 1000;           ///< frames since it was last seen
    std::array<Eigen::Vector2d, kRangeFrames> extents;  ///< (x_min, x_max) of recent sightings
    int num_extents = 0, next_extent = 0;
    double beyond = 0.0;      ///< outer boundaries: lateral distance beyond their ego side (m)
    double beyond_var = 1.0;
    float detector_confidence = 0.0f;
    float coverage = -1.0f;   ///< smoothed paint coverage (< 0: unknown)
    float yellow = -1.0f;     ///< smoothed yellowness (< 0: unknown)
    float edge_vote = 0.0f;   ///< > 0: road edge, < 0: paint
    double residual = 0.0;    ///< smoothed mean |y - prediction| of its observations (m)
  };

  /// Reduce observation @p o to the stations of track @p t in the vehicle frame (false: fewer
  /// than two).
  bool project(const Eigen::Isometry3d& T, const BoundaryObservation& o, Track& t);
  /// Boundary @p p was seen within the last lost_frames frames.
  bool known(int p) const { return memory_[p].age <= settings_.lost_frames; }
  /// The ego boundary of side @p side (0 left, 1 right) is a road edge: nothing lies beyond it.
  bool endsRoad(int side) const { return known(side) && memory_[side].edge_vote > 0.0f; }
  /// Lateral position of boundary @p p at x (from the state and the memory).
  double predicted(int p, double x) const;
  Row measurementRow(int p, double x) const;
  /// Variance of boundary @p p's lateral position at @p x (the state's and, beyond the ego
  /// lane, its distance's).
  double lateralVariance(int p, double x) const;
  /// Variance of a boundary point's lateral position at @p x as the detector measures it.
  double measurementVariance(double x) const;
  /// Variance added to boundary @p p's measurements: how much they scattered recently.
  double boundaryScatter(int p) const;
  /// Drop the stations of @p t off the curve through the others (stray points), worst first.
  void trimStations(Track& t) const;
  /// Start the model from this frame's ego observations (tracks_[0, count)), if any.
  void initialiseFromEgo(int count);
  void initialise(const Track* left, const Track* right);
  void associate(int count);
  /// Kalman update of the ego lane with the stations of @p t at ego position @p p.
  /// @return the stations used (the others were beyond the gate).
  int updateEgo(const Track& t, int p);
  void updateOuter(const Track& t, int p);
  void remember(const Track& t, int p, double residual);
  void relabel(int direction);
  void fill(LaneModelEstimate& model) const;
  /// Uncalibrated evidence in [0, 1] of a boundary with memory @p m published over @p range m
  /// (this and remember(), fill(): lane_model_evidence.cpp).
  float evidence(const Memory& m, double range) const;

  LaneModelSettings settings_;
  State x_;
  Cov P_;
  bool initialised_ = false;
  int lost_ = 0;
  int disagree_ = 0;  ///< consecutive frames with the ego lane seen and none of it used
  int lane_changes_ = 0;
  std::array<Track, 8> tracks_;
  std::array<Memory, kNumBoundaryPositions> memory_;
  std::vector<Eigen::Vector2d> scratch_;  ///< project(): an observation's points (reserved once)
};

/**
 * @brief LaneBoundary.confidence from a boundary's uncalibrated evidence: the probability that a
 * boundary with that evidence is correct (on its true line within 0.3 m, with its true label,
 * kind and colour; tools/eval/lane_model_scoring.h), by isotonic regression on the evaluation
 * sequences of seed 1 (make eval; fitted by tools/scripts/fit_confidence.py, checked on seed 2:
 * docs/RESULTS.md). Monotonic, piecewise linear between the fitted knots.
 * @param[in] evidence LaneBoundaryModel::evidence, in [0, 1].
 * @return the confidence, in [0, 1].
 */
float calibratedConfidence(float evidence);

}  // namespace rgbd_lane_detector
