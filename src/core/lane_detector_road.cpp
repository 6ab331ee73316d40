// The detector's road-surface stage: the road plane from depth (RoadSurface), the camera mount
// as its first guess and its stand-in where the depth shows no road, the last plane held over a
// fit that jumps, and the road extended toward the camera where depth is missing.
#include "rgbd_lane_detector/lane_detector.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "rgbd_lane_detector/stage_timer.h"

namespace rgbd_lane_detector {
namespace {

constexpr int kPlaneHoldFrames = 5;       // frames the last plane is kept over jumping fits
constexpr double kPlaneDropPerDeg = 0.05; // m of height change per degree of plane_max_change_deg
// The mount's height against the fitted planes: a fit this close agrees with it, one this far
// says the vehicle frame's origin is not on the road (the mount's plane then never stands in)
constexpr double kMountAgrees = 0.1;      // m
constexpr double kMountDisagrees = 0.3;   // m
constexpr int kMountEvidence = 10;        // frames of evidence kept (either way)

}  // namespace

void LaneDetector::fitRoadSurface(const Frame& frame) {
  const StageTimer timer(timings_.road);
  road_.valid = false;
  road_filled_valid_ = false;
  if (params_.plane_fit != PlaneFit::kRoadSurface) return;
  RoadSurfaceSettings s;
  s.up = Eigen::Vector3d(params_.up_x, params_.up_y, params_.up_z);
  s.max_tilt_deg = params_.plane_max_tilt_deg;
  if (frame.has_vehicle_frame) {
    // the vehicle sits on the road: its up axis is the road's, within the mount's tolerance
    s.up = frame.vehicle_from_camera.linear().transpose() * Eigen::Vector3d::UnitZ();
    s.max_tilt_deg = std::min(s.max_tilt_deg, params_.mount_tilt_deg);
    s.mount_height = frame.vehicle_from_camera.translation().z();  // its origin on the road
  }
  s.height_min = params_.plane_distance_min;
  s.height_max = params_.plane_distance_max;
  s.fit_range = params_.road_fit_range;
  s.inlier_distance = params_.road_inlier_distance;
  s.noise_growth = params_.road_noise_growth;
  s.max_range = params_.max_depth;
  const double sx = static_cast<double>(proc_size_.width) / input_size_.width;
  s.far_columns =
      RoadSurface::corridorColumns(proc_K_.fx * sx, (proc_K_.cx + 0.5) * sx - 0.5, s.fit_range);
  const PlaneEstimate& previous = fitter_.previousPlane();
  if (!road_surface_.fit(points_, roi_rows_, s, previous, road_)) {
    // no road in the depth within the mount's tolerance (too sparse, or short-baseline stereo
    // whose depth is off): the vehicle stands on the road, the mount's plane is it (unless the
    // depth's planes have shown that the vehicle frame's origin is not on the road)
    if (!(s.mount_height > s.height_min && s.mount_height < s.height_max) ||
        mount_evidence_ < 0) {
      plane_holds_ = 0;
      return;
    }
    road_.valid = true;
    road_.normal = s.up;
    road_.distance = s.mount_height;
    road_.rms = 0.0;
    road_.range = s.fit_range;
    road_.fit_method = static_cast<int>(PlaneFit::kRoadSurface);
  } else if (s.mount_height > 0.0) {
    const double off = std::fabs(road_.distance - s.mount_height);
    if (off <= kMountAgrees) mount_evidence_ = std::min(kMountEvidence, mount_evidence_ + 1);
    if (off > kMountDisagrees) mount_evidence_ = std::max(-kMountEvidence, mount_evidence_ - 1);
  }
  // a road does not tilt or drop within a frame: a plane that jumps from the last one is depth
  // that fooled the fit (sparse returns, the paint alone, a wet road); the last plane is kept
  // instead, for kPlaneHoldFrames frames at most (then the new one holds)
  if (params_.plane_max_change_deg > 0.0 && previous.valid) {
    const double change =
        std::acos(std::min(1.0, std::fabs(previous.normal.dot(road_.normal)))) * 180.0 / M_PI;
    const double drop = std::fabs(previous.distance - road_.distance);
    if ((change > params_.plane_max_change_deg ||
         drop > kPlaneDropPerDeg * params_.plane_max_change_deg) &&
        plane_holds_ < kPlaneHoldFrames) {
      ++plane_holds_;
      road_.normal = previous.normal;
      road_.distance = previous.distance;
      road_.support.clear();
      road_.rms = 0.0;
      road_.range = std::min(road_.range, s.fit_range);
    } else {
      plane_holds_ = 0;
    }
  } else {
    plane_holds_ = 0;
  }
  // LiDAR and stereo often see nothing near the car: where a column's nearest depth is road, the
  // road continues toward the camera (its points give seeds there a road's normal and depth)
  const int h = params_.normal_window / 2;
  road_surface_.extendToCamera(
      points_, cv::Range(roi_rows_.start, std::min(proc_size_.height, roi_rows_.end + h)), proc_K_,
      road_, s.inlier_distance, road_surface_.noiseGrowth(), road_filled_, col_map_, row_map_);
  road_filled_valid_ = true;
}

}  // namespace rgbd_lane_detector
