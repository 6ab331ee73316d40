/**
 * @file lane_outputs.h
 * @brief The nodelet's outputs: advertises every topic (with the owner's connection callback,
 * for lazy subscription), says which ones have subscribers (Wanted) and publishes a frame's
 * results to those only, plus the road-aligned fallback frame on tf. What a frame needs built
 * is planOutputs() (a pure function, tested without a roscore). Private to the nodelet library.
 */
#pragma once

#include <functional>
#include <memory>
#include <string>

#include <Eigen/Geometry>
#include <geometry_msgs/TransformStamped.h>
#include <image_transport/image_transport.h>
#include <ros/ros.h>
#include <std_msgs/Header.h>
#include <tf2_ros/transform_broadcaster.h>

#include "rgbd_lane_detector/lane_grid.h"
#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/// Which outputs have subscribers this frame (lazy publishing).
struct Wanted {
  bool plane = false, markings = false, points = false, markers = false, model = false;
  bool centre = false;  ///< lane_centre_line
  bool grid = false;    ///< lane_grid
  bool left = false, right = false, geometric = false, debug = false;
  bool any() const {
    return plane || markings || points || markers || model || centre || grid || left || right ||
           geometric || debug;
  }
};

/// What one frame's subscribers need built.
struct OutputPlan {
  bool model = false;       ///< the LaneModel message (lane_model and lane_centre_line)
  bool grid = false;        ///< the lane grid (lane_grid, or the debug image's inset)
  bool grid_inset = false;  ///< the inset in debug_image (lane model on)
  bool road_frame = false;  ///< broadcast the road-aligned frame (no vehicle frame from tf)
  /// Broadcast the last road-aligned frame again at this stamp: no vehicle frame and no plane
  /// this frame, and the lane model (predicted in that frame) is published in it.
  bool road_frame_held = false;
};
OutputPlan planOutputs(const Wanted& wanted, bool lane_model_on, bool vehicle_frame_found,
                       bool plane_valid);

/// The road-aligned fallback frame `child` under the optical frame of @p image (REP-103).
geometry_msgs::TransformStamped roadFrameTransform(const PlaneEstimate& plane,
                                                   const std_msgs::Header& image,
                                                   const std::string& child);

class LaneOutputs {
 public:
  /// One frame's frames: see docs/NODELET.md (outputs, lane-model frame, images).
  struct Headers {
    const std_msgs::Header& image;  ///< the colour image's (images: its optical frame)
    std_msgs::Header out;    ///< the geometric outputs' (target_frame)
    std_msgs::Header model;  ///< the lane model's (lane_model_frame or the road frame)
  };

  /// Advertise every output; @p connect runs on every (un)subscription.
  void advertise(ros::NodeHandle& nh, image_transport::ImageTransport& it,
                 const std::function<void()>& connect);
  Wanted wanted() const;
  /// How long rviz shows a frame's markers unless a later frame replaces them (s; 0: until
  /// then): without frames (a stopped camera, frames dropped) the lines do not stay on.
  void setMarkerLifetime(double seconds) { marker_lifetime_ = ros::Duration(seconds); }
  /// Publish what @p wanted asks for; @p T takes optical points into headers.out.frame_id.
  void publish(const Wanted& wanted, const Frame& frame, const Result& result,
               const Params& params, const Headers& headers, const Eigen::Isometry3d& T,
               bool vehicle_frame_found);

 private:
  ros::Publisher plane_, markings_, points_, markers_, model_, centre_, grid_;
  image_transport::Publisher left_, right_, geometric_, debug_;
  LaneGrid lane_grid_;  ///< built from the lane model for lane_grid and the debug inset
  std::unique_ptr<tf2_ros::TransformBroadcaster> road_frame_broadcaster_;
  geometry_msgs::TransformStamped road_frame_;  ///< the last one broadcast (empty: none yet)
  /// Markers' lifetime (0: until replaced), setMarkerLifetime().
  ros::Duration marker_lifetime_;
};

}  // namespace rgbd_lane_detector
