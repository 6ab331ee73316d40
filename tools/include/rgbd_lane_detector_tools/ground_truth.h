/**
 * @file ground_truth.h
 * @brief Per-frame lane ground truth of a sequence (GT/LANES/ground_truth.json).
 *
 * JSON (written compactly, read with cv::FileStorage; flags are 1/0):
 * @code
 * { "format": 2,
 *   "mount": { "translation": [x, y, z], "rotation": [qx, qy, qz, qw] },
 *   "frames": [ {
 *     "index": 0,
 *     "plane_normal": [nx, ny, nz], "plane_distance": d, "plane_rms": r,
 *     "has_lane": 1, "lane_optional": 0,
 *     "base_to_camera": { "translation": [x, y, z], "rotation": [qx, qy, qz, qw] },
 *     "lane": { "valid": 1, "width": w, "offset": o, "heading": h, "curvature": k },
 *     "boundaries": [ { "label": "ego_left", "kind": "paint", "style": "dashed",
 *                       "colour": "white", "edge": "none", "points": [[x, y, z], ...] },
 *                     ... ] }, ... ] }
 * @endcode
 * Points are written to 0.1 mm. On reading, FrameTruth::left / right are the ego boundaries'
 * points and TrueBoundary::points_base = base_to_camera * points (the file stores each point
 * once, in the optical frame).
 *
 * **Camera optical frame** (x right, y down, z forward), metres: the plane, "left"/"right" and
 * every boundary's "points". The plane is n . p + d = 0 with n the unit normal pointing toward
 * the camera (d > 0, the camera height).
 * - On a planar road it is the road plane itself (plane_rms 0). On a road with vertical
 *   curvature (crest / sag) it is the total-least-squares plane of the true road surface of the
 *   ego lane from gt_plane_min to gt_plane_max ahead along the road (3-20 m by default; samples
 *   every gt_step along the road and at 5 lateral positions across the lane); plane_rms is the
 *   RMS distance of those surface samples from it.
 *
 * **Ego sides.** FrameTruth::left / right (format 1's "left" / "right") are the ego lane's
 * boundary lines (the points of ego_left / ego_right), near to far, sampled every gt_step of road from gt_min_distance to gt_max_distance ahead, where the
 * boundary exists (a line interrupted by an intersection has no samples there; dash gaps are
 * part of a dashed line). Empty when that side has no boundary (kind "none"). The line is
 *   - paint: the centre of the painted line (of both lines for a double line);
 *   - road edge: where the drivable road surface ends: the bottom of a kerb's face, the centre
 *     of the tram rail nearest the lane, the asphalt edge, the paved shoulder's outer edge.
 *
 * **Boundaries.** Every boundary of the layout that exists in the frame, with its position
 * label (BoundaryLabel), kind (paint / road_edge), style, colour and what the edge is, its
 * polyline in the optical frame ("points", same sampling as above) and in base_link
 * (TrueBoundary::points_base). Labels follow the vehicle's current lane: the lane that holds the point of
 * the road under the camera (base_link's origin); after a lane change they switch exactly when
 * that point crosses the line. A boundary has one label, the first that applies in the order
 * ego, next, road edge (a kerb bounding the ego lane is ego_right, not road_edge_right).
 * next_left / next_right are the far boundaries of the lanes beside the ego lane (when they are
 * adjacent: a tram zone is not a lane); road_edge_left / right are the outer ends of the
 * drivable surface (shoulder to grass, kerb, asphalt edge).
 *
 * **lane_optional** (1/0): reporting no lane is acceptable in this frame. Set when the ego
 * lane's painted lines end (an intersection: from the stop line to where the lines resume)
 * anywhere between the point under the camera and gt_required_range (20 m) ahead along the road.
 *
 * **has_lane** (1/0): the ego lane has at least one boundary (kind not none).
 *
 * **Vehicle frame base_link** (REP-103: x forward, y left, z up): origin on the true road
 * surface under the camera (at the camera's road coordinates), x along the vehicle's heading
 * in the road surface, z the road's up direction (a vehicle on a grade is pitched with it).
 * "base_to_camera" is the true pose of the camera optical frame in base_link in this frame
 * (p_base = R p_optical + t, R as a unit quaternion x, y, z, w): the nominal mount plus the
 * body motion (pitch, roll and height wobble). "mount" is the nominal, fixed mount
 * (camera_height, pitch_deg, roll_deg), the transform sequence_to_bag / --bag publish on
 * /tf_static. The lane model, in base_link, of the current ego lane at x = 0:
 *   - width: distance between the ego boundaries' lines (m);
 *   - offset: lateral position of base_link's origin relative to the lane centre, positive
 *     when the vehicle is left of the centre (REP-103 y);
 *   - heading: yaw of the vehicle relative to the lane direction, positive when it points to
 *     the left of the lane (counter-clockwise); the centre line's slope in base_link is
 *     dy/dx = -tan(heading);
 *   - curvature: of the lane centre line, 1/m, positive when the lane turns left.
 *   valid is 1 when has_lane (the lane's nominal geometry is given for every frame).
 *
 * Format 1 files (no "format", no "boundaries") remain readable: their "left" / "right" lines
 * become ego boundaries of kind paint, style and colour unknown; no vehicle frame, no lane model.
 */
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {
namespace tools {

/// Position label of a boundary relative to the vehicle's current lane (issue 14's labels).
enum class BoundaryLabel : int {
  kEgoLeft = 0,
  kEgoRight,
  kNextLeft,
  kNextRight,
  kRoadEdgeLeft,
  kRoadEdgeRight,
};
constexpr int kNumBoundaryLabels = 6;

/// Line style; kRoadEdge for a boundary without paint, kUnknown in format 1 files.
enum class LineStyle : int { kUnknown = 0, kSolid, kDashed, kDoubleSolid, kRoadEdge };

/// Paint colour; kNone for a road edge, kUnknown in format 1 files.
enum class LineColour : int { kUnknown = 0, kNone, kWhite, kYellow };

/// What a road edge physically is (kNone for paint).
enum class EdgeType : int { kNone = 0, kKerb, kRails, kAsphaltEdge, kShoulderEdge };

/// Names used in the JSON file ("ego_left", "solid", "white", "kerb", ...).
const char* boundaryLabelName(BoundaryLabel label);
const char* lineStyleName(LineStyle style);
const char* lineColourName(LineColour colour);
const char* edgeTypeName(EdgeType edge);

/// One true boundary of a frame.
struct TrueBoundary {
  BoundaryLabel label = BoundaryLabel::kEgoLeft;
  BoundaryKind kind = BoundaryKind::kPaint;
  LineStyle style = LineStyle::kUnknown;
  LineColour colour = LineColour::kUnknown;
  EdgeType edge = EdgeType::kNone;
  std::vector<Eigen::Vector3d> points;       ///< optical frame, near to far
  std::vector<Eigen::Vector3d> points_base;  ///< base_link, same samples (empty in format 1)
};

/// "none" for a missing side (nullptr), else boundaryKindName() of its kind.
const char* sideKindName(const TrueBoundary* side);

/// True lane model of the current ego lane in base_link (see the file comment).
struct LaneModelTruth {
  bool valid = false;
  double width = 0.0;
  double offset = 0.0;
  double heading = 0.0;
  double curvature = 0.0;
};

/// Ground truth of one frame.
struct FrameTruth {
  int index = 0;
  Eigen::Vector3d normal = Eigen::Vector3d(0, -1, 0);
  double distance = 0.0;
  double plane_rms = 0.0;      ///< RMS of the true surface about the plane (0: planar road)
  bool has_lane = false;       ///< the ego lane has at least one boundary
  bool lane_optional = false;  ///< reporting no lane is acceptable (see the file comment)
  std::vector<Eigen::Vector3d> left;   ///< ego left line (= ego_left's points), near to far
  std::vector<Eigen::Vector3d> right;  ///< ego right line (= ego_right's points)
  std::vector<TrueBoundary> boundaries;  ///< every boundary present, at most one per label
  bool has_vehicle_frame = false;        ///< base_to_camera and lane are set (format 2)
  Eigen::Isometry3d base_to_camera = Eigen::Isometry3d::Identity();  ///< p_base = T p_optical
  LaneModelTruth lane;

  /// The boundary with @p label, or nullptr when the frame has none.
  const TrueBoundary* boundary(BoundaryLabel label) const;
  /// Ego side: left (true) or right; nullptr when that side has no boundary (kind "none").
  const TrueBoundary* egoSide(bool left) const {
    return boundary(left ? BoundaryLabel::kEgoLeft : BoundaryLabel::kEgoRight);
  }
  /// Set left / right and has_lane from the ego boundaries (call after filling boundaries).
  void syncEgoLines();
};

/// Ground truth of a sequence, indexed by frame.
struct SequenceTruth {
  std::vector<FrameTruth> frames;
  int format = 2;  ///< 1 for files written before the extended format
  bool has_mount = false;
  Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();  ///< nominal base_link <- optical
  /// Truth of frame @p index, or nullptr.
  const FrameTruth* find(int index) const;
};

/**
 * @brief Write ground truth as JSON (format 2).
 * @return false with @p error on an I/O failure.
 */
bool writeGroundTruth(const std::string& path, const SequenceTruth& truth, std::string& error);

/**
 * @brief Read ground truth written by writeGroundTruth() (format 2) or by generator version 1.
 * @return false with @p error when the file is missing or malformed.
 */
bool readGroundTruth(const std::string& path, SequenceTruth& truth, std::string& error);

}  // namespace tools
}  // namespace rgbd_lane_detector
