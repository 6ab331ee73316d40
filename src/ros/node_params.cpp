#include "node_params.h"

#include <algorithm>

#include <ros/node_handle.h>

#include "rgbd_lane_detector/ros/conversions.h"

namespace rgbd_lane_detector {

NodeParams NodeParams::read(const ros::NodeHandle& pnh) {
  NodeParams p;
#define RLD_NODE_PARAM(type, name, default_value, description) pnh.param<type>(#name, p.name, p.name);
#include "node_params.def"
#undef RLD_NODE_PARAM
  return p.sanitized();
}

NodeParams NodeParams::sanitized() const {
  NodeParams p = *this;
  p.queue_size = std::max(1, p.queue_size);
  p.tf_timeout = std::max(0.0, p.tf_timeout);
  p.max_sync_interval = std::max(0.0, p.max_sync_interval);
  p.max_frame_gap = std::max(0.0, p.max_frame_gap);
  p.diagnostic_period = std::max(0.05, p.diagnostic_period);
  // tf2 names frames without tf1's leading '/' (it refuses "/base_link" in a lookup)
  for (std::string* frame : {&p.target_frame, &p.up_frame, &p.lane_model_frame, &p.odom_frame})
    *frame = conversions::tfFrameId(*frame);
  return p;
}

}  // namespace rgbd_lane_detector
