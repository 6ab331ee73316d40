/**
 * @file road.h
 * @brief Road geometry: a straight line or a constant-curvature arc in the horizontal plane,
 * an optional vertical profile (crests and sags), the cross-section (lanes, painted lines,
 * kerb, tram tracks, asphalt edge, shoulders) and periodic intersections, in road coordinates
 * (s along the reference line, t lateral, positive right).
 *
 * World frame: x right, y up, z forward at s = 0. The ground is y = height(s) (y = 0 on a flat
 * road, so the ground-truth plane stays exact on curves: markers are circles in that plane).
 */
#pragma once

#include <vector>

#include <Eigen/Core>

#include "rgbd_lane_detector_tools/ground_truth.h"
#include "rgbd_lane_detector_tools/synth/scenario.h"

namespace rgbd_lane_detector {
namespace synth {

/// One painted line at a constant lateral offset.
struct MarkerLine {
  double offset = 0.0;  ///< t of the line centre (m, positive right of the reference line)
  double width = 0.15;
  bool dashed = false;
  double dash_length = 3.0;
  double period = 12.0;     ///< dash + gap
  double phase = 0.0;       ///< s of a dash start
  double double_gap = 0.0;  ///< > 0: two lines of `width` this far apart, centred on offset
  PaintColour colour = PaintColour::kWhite;
};

/**
 * @brief Height of the road along s: level, then repeated cycles of a crest (vertical curve of
 * radius R, a parabola), a falling tangent, a sag, a rising tangent and a crest back to level.
 * Every cycle returns to height 0 and grade 0.
 */
class VerticalProfile {
 public:
  VerticalProfile() = default;
  explicit VerticalProfile(const SceneSettings& s);
  bool flat() const { return cycle_.empty(); }
  double height(double s) const;  ///< m above y = 0
  double grade(double s) const;   ///< dheight / ds
  double minHeight() const { return min_height_; }
  double maxGrade() const { return max_grade_; }
  /**
   * @brief First crossing of a line s(l) = s0 + l ds, y(l) = y0 + l dy (l in (0, max_l)) with
   * the surface y = height(s) + offset, solved exactly (the profile is piecewise quadratic).
   * This is a ray on a straight road (s linear along the ray), starting above the surface.
   * @return false when there is none.
   */
  bool crossing(double s0, double ds, double y0, double dy, double offset, double max_l,
                double& l) const;

 private:
  struct Piece {
    double s0, h0, g0, k;  ///< start (in the cycle), height, grade, vertical curvature
  };
  const Piece& piece(double s, double& u) const;
  std::vector<Piece> cycle_;
  double start_ = 0.0, period_ = 0.0, min_height_ = 0.0, max_grade_ = 0.0;
};

/// One lane boundary of the cross-section, at a constant lateral offset.
struct BoundaryDef {
  double offset = 0.0;  ///< t of the true line (see ground_truth.h)
  bool present = false;  ///< false: nothing marks it (an unpainted separator)
  BoundaryKind kind = BoundaryKind::kPaint;
  tools::LineStyle style = tools::LineStyle::kSolid;
  tools::LineColour colour = tools::LineColour::kWhite;
  tools::EdgeType edge = tools::EdgeType::kNone;
};

/// One lane of the cross-section: its centre and its boundaries (indices in boundaries()).
struct LaneDef {
  double centre = 0.0;
  int left = -1, right = -1;
};

/**
 * @brief Road layout: horizontal geometry of the reference line (the initial ego lane's centre),
 * vertical profile, cross-section and road markings.
 */
class RoadGeometry {
 public:
  RoadGeometry() = default;
  explicit RoadGeometry(const SceneSettings& s);

  double curvature() const { return curvature_; }
  /// Ground point (x, z) of road coordinates (s, t).
  Eigen::Vector2d point(double s, double t) const;
  /// Heading (yaw, rad, positive right) of the reference line at @p s.
  double heading(double s) const { return curvature_ * s; }
  /**
   * @brief Road coordinates of a ground point.
   * @param[in] s_ref on an arc, the answer is the s closest to this (unwraps full turns).
   */
  void coordinates(double x, double z, double s_ref, double& s, double& t) const;
  /**
   * @brief First ray parameter in (min_l, max_l) where a ray in the x-z plane reaches the
   * lateral offset @p t_line (a vertical surface: a plane, or a cylinder on an arc).
   * @return false when the ray does not reach it in that interval.
   */
  bool rayToLateral(double ox, double oz, double dx, double dz, double t_line, double min_l,
                    double max_l, double& lambda) const;

  const VerticalProfile& profile() const { return profile_; }
  /// World point (x, y, z) of the road surface at road coordinates (s, t) (lane level).
  Eigen::Vector3d surfacePoint(double s, double t) const;

  const std::vector<MarkerLine>& markers() const { return markers_; }
  /// Index of the line painted at (s, t), or -1.
  int markerAt(double s, double t) const;
  /// Road marking other than a line at (s, t): 1 stop line, 2 zebra stripe, 3 arrow; 0 none.
  int roadMarkingAt(double s, double t) const;
  /// Lateral offsets of the outer road edges (centres of the outermost lines' positions).
  double leftEdge() const { return left_edge_; }
  double rightEdge() const { return right_edge_; }
  /// Lateral offset of the centre of lane @p lane (0 ego, negative left).
  double laneCentre(int lane) const {
    return lane * lane_width_ - (lane < 0 ? tram_zone_width_ : 0.0);
  }

  /// Boundaries of the cross-section, left to right (present or not).
  const std::vector<BoundaryDef>& boundaries() const { return boundaries_; }
  /// Lane @p lane (-lanes_left .. lanes_right).
  const LaneDef& lane(int lane) const { return lanes_[lane + lanes_left_]; }
  int lanesLeft() const { return lanes_left_; }
  int lanesRight() const { return lanes_right_; }
  /// Lane holding lateral offset @p t (clamped to the outer lanes).
  int laneAt(double t) const;
  /// Indices in boundaries() of the outer ends of the drivable surface.
  int roadEdgeLeft() const { return road_edge_left_; }
  int roadEdgeRight() const { return road_edge_right_; }

  // --- urban features ---
  /// Tram zone [tramZoneLeft(), tramZoneRight()] left of the ego lane (empty without tracks).
  double tramZoneLeft() const { return laneCentre(0) - 0.5 * lane_width_ - tram_zone_width_; }
  double tramZoneRight() const { return laneCentre(0) - 0.5 * lane_width_; }
  bool hasTram() const { return tram_zone_width_ > 0.0; }
  /// Rail part at lateral offset @p t inside the tram zone: 1 rail head, 2 groove, 3 between the
  /// rails of a track, 0 elsewhere in the zone.
  int tramPartAt(double t) const;
  /// Right side zone beyond the ego lane: raised by a kerb (> 0), lowered at an asphalt edge
  /// (< 0) or none (0); sideZoneStart() is where it begins (the true boundary line).
  double sideZoneHeight() const { return side_zone_height_; }
  double sideZoneStart() const { return side_zone_start_; }

  /// Intersections: true when the road has them.
  bool intersections() const { return intersection_period_ > 0.0; }
  /// Inside the crossing road (s between its near and far edge).
  bool inCrossing(double s) const;
  /// Where the lines are interrupted by an intersection (stop line to where they resume).
  bool inLineGap(double s) const;
  /// Road distance from @p s to the next line gap's start (0 inside one, +inf without).
  double distanceToLineGap(double s) const;

 private:
  /// Intersection k near s and s relative to its crossing road's near edge (-1 before the first).
  int intersectionAt(double s, double& local) const;
  void buildCrossSection(const SceneSettings& s);

  double curvature_ = 0.0;
  double radius_ = 0.0;  ///< signed 1 / curvature
  double lane_width_ = 3.6;
  double left_edge_ = 0.0, right_edge_ = 0.0;
  int lanes_left_ = 0, lanes_right_ = 0;
  std::vector<MarkerLine> markers_;
  std::vector<BoundaryDef> boundaries_;
  std::vector<LaneDef> lanes_;
  int road_edge_left_ = -1, road_edge_right_ = -1;
  VerticalProfile profile_;
  double tram_zone_width_ = 0.0;
  double tram_gauge_ = 1.435, tram_head_ = 0.07, tram_groove_ = 0.04, tram_spacing_ = 3.0;
  double side_zone_height_ = 0.0, side_zone_start_ = 0.0;
  double intersection_period_ = 0.0, intersection_start_ = 0.0, crossing_width_ = 0.0;
  bool turn_arrows_ = false;
};

}  // namespace synth
}  // namespace rgbd_lane_detector
