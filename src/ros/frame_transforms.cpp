#include "frame_transforms.h"

#include <cstdio>

#include <tf2/exceptions.h>
#include <tf2_eigen/tf2_eigen.h>

#include "rgbd_lane_detector/ros/conversions.h"

namespace rgbd_lane_detector {
namespace {

std::string seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3f", s);
  return text;
}

}  // namespace

bool FrameTransforms::needsTf(const Frames& frames) {
  return !frames.target.empty() || !frames.up.empty() || !frames.lane_model.empty();
}

FrameTransforms::FrameTransforms(const Frames& frames, tf2::BufferCore* buffer)
    : frames_(frames), buffer_(buffer) {}

FrameTransforms::Lookup FrameTransforms::usableTime(const std::string& target,
                                                    const std::string& source,
                                                    const ros::Time& stamp, const char* what,
                                                    ros::Time& time, std::string& why) const {
  const std::string lookup = "transform from '" + source + "' to " + what + " '" + target + "'";
  std::string error = "no tf buffer";
  // non-blocking: BufferCore's own calls never wait (a static chain is there at any stamp)
  if (buffer_ != nullptr && buffer_->canTransform(target, source, stamp, &error)) {
    time = stamp;
    return Lookup::kAtStamp;
  }
  try {
    if (buffer_ != nullptr) {
      const ros::Time latest = buffer_->lookupTransform(target, source, ros::Time(0)).header.stamp;
      const double age = (stamp - latest).toSec();
      if (age > 0.0 && age <= frames_.tolerance) {
        time = latest;
        why = "no " + lookup + " at the image stamp " + seconds(stamp.toSec()) +
              " yet: using the latest one, " + seconds(age) + " s older (tf_timeout " +
              seconds(frames_.tolerance) + ")";
        return Lookup::kLatest;
      }
      error += " (the latest one, at " + seconds(latest.toSec()) + ", is not within tf_timeout " +
               seconds(frames_.tolerance) + " s before the image)";
    }
  } catch (const tf2::TransformException& e) {
    error = e.what();
  }
  why = "no " + lookup + " at " + seconds(stamp.toSec()) + ": " + error;
  return Lookup::kMissing;
}

bool FrameTransforms::upAxis(const std::string& optical_frame, Eigen::Vector3d& up,
                             std::string& why) const {
  try {
    if (buffer_ == nullptr || frames_.up.empty()) throw tf2::LookupException("no up_frame");
    up = conversions::upAxisFromTransform(
        tf2::transformToEigen(buffer_->lookupTransform(optical_frame, frames_.up, ros::Time(0))));
    return true;
  } catch (const tf2::TransformException& e) {
    why = "no transform from up_frame '" + frames_.up + "' to '" + optical_frame + "': " + e.what();
    return false;
  }
}

FrameTransforms::Lookup FrameTransforms::outputTransform(const std_msgs::Header& image,
                                                         Eigen::Isometry3d& T,
                                                         std::string& frame_id,
                                                         std::string& why) const {
  T.setIdentity();
  frame_id = image.frame_id;
  if (frames_.target.empty() || frames_.target == image.frame_id) return Lookup::kAtStamp;
  ros::Time time;
  const Lookup lookup =
      usableTime(frames_.target, image.frame_id, image.stamp, "target_frame", time, why);
  if (lookup == Lookup::kMissing) return lookup;
  try {
    T = tf2::transformToEigen(buffer_->lookupTransform(frames_.target, image.frame_id, time));
  } catch (const tf2::TransformException& e) {  // gone meanwhile (the listener's thread)
    why = std::string("no transform to target_frame: ") + e.what();
    return Lookup::kMissing;
  }
  frame_id = frames_.target;
  return lookup;
}

void FrameTransforms::vehicleFrame(const std_msgs::Header& image, bool lane_model, Vehicle& out) {
  out = Vehicle();
  out.frame_id = image.frame_id + "_road";
  if (!lane_model) return;
  if (!frames_.lane_model.empty() && buffer_ != nullptr) {
    ros::Time time;
    std::string why;
    out.lookup =
        usableTime(frames_.lane_model, image.frame_id, image.stamp, "lane_model_frame", time, why);
    try {
      if (out.lookup != Lookup::kMissing) {
        out.vehicle_from_camera = tf2::transformToEigen(
            buffer_->lookupTransform(frames_.lane_model, image.frame_id, time));
        out.found = true;
        out.frame_id = frames_.lane_model;
      }
    } catch (const tf2::TransformException& e) {
      out.lookup = Lookup::kMissing;
      why = e.what();
    }
    if (out.lookup == Lookup::kMissing)
      out.warning = "lane_model in the road frame '" + out.frame_id + "' under the camera: " + why;
    else if (out.lookup == Lookup::kLatest)
      out.warning = why;
  }
  // the vehicle's motion since the last image, from odometry, moves the model
  ros::Time now = image.stamp;
  if (out.found && !frames_.odom.empty()) {
    ros::Time odom_time;
    std::string why;
    out.motion_lookup =
        usableTime(frames_.odom, frames_.lane_model, image.stamp, "odom_frame", odom_time, why);
    if (out.motion_lookup != Lookup::kMissing) now = odom_time;
    if (!last_time_.isZero() && now > last_time_) {
      try {
        if (out.motion_lookup == Lookup::kMissing) throw tf2::LookupException(why);
        out.motion = tf2::transformToEigen(buffer_->lookupTransform(
            frames_.lane_model, last_time_, frames_.lane_model, now, frames_.odom));
        out.has_motion = true;
      } catch (const tf2::TransformException& e) {
        out.motion_lookup = Lookup::kMissing;
        out.motion_warning = std::string("lane_model without motion prediction: ") + e.what();
      }
    }
  }
  last_time_ = now;
}

void FrameTransforms::reset() {
  last_time_ = ros::Time();
  if (buffer_ != nullptr) buffer_->clear();  // dynamic transforms only: static ones stay
}

}  // namespace rgbd_lane_detector
