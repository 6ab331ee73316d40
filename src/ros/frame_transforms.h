/**
 * @file frame_transforms.h
 * @brief The nodelet's tf lookups, none of which waits: the output frame (`target_frame`), the
 * road's up axis (`up_frame`), the lane model's vehicle frame (`lane_model_frame`) and the
 * vehicle's motion between frames (`odom_frame`). A transform at the image stamp is used when
 * the buffer has it; else the latest one when it is at most `tf_timeout` older than the image
 * (Lookup::kLatest, for a throttled warning); else none. Private to the nodelet library; needs
 * no roscore (any tf2::BufferCore, filled by a tf2_ros::TransformListener in the nodelet).
 */
#pragma once

#include <string>

#include <Eigen/Geometry>
#include <ros/time.h>
#include <std_msgs/Header.h>
#include <tf2/buffer_core.h>

#include "node_params.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

class FrameTransforms {
 public:
  struct Frames {
    std::string target;       ///< output frame; "": the image's optical frame
    std::string up;           ///< frame whose +z is the road's up axis; "": none (camera -y)
    std::string lane_model;   ///< vehicle frame of the lane model; "": the road frame
    std::string odom;         ///< fixed frame of the vehicle's motion; "": none
    double tolerance = 0.05;  ///< s: how much older than the image the latest transform may be
  };
  /// The frames of the nodelet's parameters (target_frame, up_frame, ..., tf_timeout).
  static Frames framesOf(const NodeParams& params) {
    return {params.target_frame, params.up_frame, params.lane_model_frame, params.odom_frame,
            params.tf_timeout};
  }
  /// How a transform was found.
  enum class Lookup { kAtStamp, kLatest, kMissing };

  /// The lane model's frame for one image (vehicleFrame()).
  struct Vehicle {
    bool found = false;  ///< vehicle_from_camera from tf (else the road frame under the camera)
    Eigen::Isometry3d vehicle_from_camera = Eigen::Isometry3d::Identity();
    std::string frame_id;  ///< lane_model_frame, or "<optical frame>_road"
    Lookup lookup = Lookup::kMissing;
    bool has_motion = false;  ///< motion since the last image, from odometry
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    Lookup motion_lookup = Lookup::kMissing;
    /// For a throttled warning (else empty): the road frame in place of a missing vehicle
    /// frame, or its latest transform in place of one at the stamp; no motion prediction.
    std::string warning, motion_warning;
    /// Into the core frame (has_vehicle_frame, vehicle_from_camera) and the model's header.
    void applyTo(Frame& frame, std_msgs::Header& model) const {
      frame.has_vehicle_frame = found;
      frame.vehicle_from_camera = vehicle_from_camera;
      model.frame_id = frame_id;
    }
  };

  /// Whether these frames need tf at all (an output, up or vehicle frame is named).
  static bool needsTf(const Frames& frames);

  /// @param buffer filled by the caller's listener; may be null when !needsTf(frames).
  FrameTransforms(const Frames& frames, tf2::BufferCore* buffer);

  const Frames& frames() const { return frames_; }

  /// The +z axis of `up` in @p optical_frame (latest transform); false, with @p why, if none.
  bool upAxis(const std::string& optical_frame, Eigen::Vector3d& up, std::string& why) const;

  /**
   * @brief Transform from the image's optical frame into the output frame.
   * @param[out] T identity when there is no target frame (or it is the optical frame).
   * @param[out] frame_id the output frame.
   * @param[out] why what is missing (kMissing: skip the frame) or late (kLatest), for a log.
   */
  Lookup outputTransform(const std_msgs::Header& image, Eigen::Isometry3d& T,
                         std::string& frame_id, std::string& why) const;

  /**
   * @brief The lane model's vehicle frame for this image and the vehicle's motion since the
   * last image that had one. Only when @p lane_model is on; remembers the image's time.
   */
  void vehicleFrame(const std_msgs::Header& image, bool lane_model, Vehicle& out);

  /// Time went back: forget the last image's time and every dynamic transform.
  void reset();

 private:
  /// The time to look @p source up in @p target at for an image at @p stamp.
  /// @p what names the lookup in @p why ("target_frame 'base_link'").
  Lookup usableTime(const std::string& target, const std::string& source, const ros::Time& stamp,
                    const char* what, ros::Time& time, std::string& why) const;

  Frames frames_;
  tf2::BufferCore* buffer_;
  ros::Time last_time_;  ///< the vehicle frame's time at the last image (motion start)
};

}  // namespace rgbd_lane_detector
