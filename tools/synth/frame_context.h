// Per-frame state of the renderer and the ray tracing / shading of one sample (private to the
// synth library). Read-only while rows are rendered in parallel.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector_tools/synth/renderer.h"
#include "scene_objects.h"

namespace rgbd_lane_detector {
namespace synth {

/// What a ray hit first.
struct Hit {
  /// kGround: any top surface (road, kerb top, sidewalk, gravel, grass); kKerbFace: the
  /// vertical face of a kerb; kRail / kRailPost: guard rails.
  enum Kind { kNone, kGround, kBox, kRail, kRailPost, kKerbFace } kind = kNone;
  double lambda = 0.0;  ///< ray parameter = optical-frame depth z (ray z component is 1)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< world
  int box = -1;
  BoxHit box_hit;
  int rail_side = 0;        ///< -1 left, +1 right
  double s = 0.0, t = 0.0;  ///< road coordinates of ground / rail / kerb face hits
};

/// Everything one frame needs, computed once before the parallel loop.
struct FrameContext {
  const SceneSettings* settings = nullptr;
  const RoadGeometry* road = nullptr;
  int index = 0;
  uint32_t seed = 0;
  CameraPose pose;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<Box> boxes;
  Eigen::Vector3d sun = Eigen::Vector3d::UnitY();  ///< unit vector toward the sun (world)
  cv::Vec3d ambient_light, sun_light;              ///< RGB
  double gain = 1.0;                               ///< exposure of this frame
  cv::Vec3d headlight_light{0, 0, 0};  ///< RGB irradiance of the road in the beam (0: off)
  Eigen::Vector3d lamp = Eigen::Vector3d::Zero();  ///< world: between the two headlights
  Eigen::Vector3d ahead = Eigen::Vector3d::UnitZ(), up = Eigen::Vector3d::UnitY();  ///< vehicle
  double rail_left = 0.0, rail_right = 0.0;        ///< lateral offsets of the rails
  bool flat_ground = true;  ///< plane y = 0 everywhere (every scenario of generator version 1)
  bool urban = false;       ///< kerb, asphalt edge, tram tracks or intersections present

  /// Prepare culling rectangles and shadow footprints of the boxes.
  void prepare(int width, int height);
  /// World direction of the ray through image point (u, v) (optical z component = 1).
  Eigen::Vector3d rayDirection(double u, double v) const;
  /// First hit of the ray through (u, v).
  void trace(double u, double v, Hit& hit) const;
  /// Linear RGB radiance (before exposure) of a hit seen along @p dir; @p footprint in m.
  cv::Vec3d shade(const Hit& hit, const Eigen::Vector3d& dir, double footprint) const;
  /// Class id of a hit.
  uint8_t label(const Hit& hit) const;
  /**
   * @brief Identity of what a sample sees (class, object, sunlit or not): a pixel whose samples
   * all share it is shaded once with the pixel's footprint (adaptive supersampling).
   */
  uint32_t sampleKey(const Hit& hit) const;

 private:
  cv::Vec3d sky(const Eigen::Vector3d& dir) const;
  cv::Vec3d groundAlbedo(const Hit& hit, double footprint) const;
  cv::Vec3d boxAlbedo(const Box& box, const BoxHit& h) const;
  double sunVisibility(const Eigen::Vector3d& p, int self_box) const;
  /// Irradiance factor of the low beams at @p p on a surface of normal @p n (0 outside them).
  double headlightFactor(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const;
  double canopyShadow(double x, double z, double t) const;
  /// Ground hit on a non-planar ground (vertical profile, kerb or asphalt edge zone).
  void traceGround(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double& best,
                   Hit& hit) const;
  /**
   * @brief First crossing of the ray o + l d (l in (0, max_l)) with the surface
   * y = profile height(s) + @p offset. @return false when it does not reach it.
   */
  bool surfaceHit(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double offset, double max_l,
                  double& l, double& s, double& t) const;
  /// Unit normal (world) of the ground's top surface at road position @p s.
  Eigen::Vector3d groundNormal(double s) const;
  /// Albedo of the kerb / sidewalk or gravel zone right of the ego lane (t beyond its start).
  cv::Vec3d sideZoneAlbedo(const Hit& hit, double footprint) const;
  /// Kerb stones (face and top) at road position @p s, with joints every metre.
  cv::Vec3d kerbAlbedo(double s, double footprint) const;
  cv::Vec3d grassAlbedo(double x, double z, double footprint) const;
  cv::Vec3d gravelAlbedo(double x, double z, double footprint) const;
  /// 1 when a kerb shades this road point from the sun, else 0.
  double kerbShadow(const Hit& hit) const;
  /// Sample-key bits of the urban materials of a ground hit (0 for the version-1 scenarios).
  uint32_t urbanKey(const Hit& hit) const;
};

}  // namespace synth
}  // namespace rgbd_lane_detector
