#include "node_params.h"

#include <algorithm>

#include <ros/node_handle.h>

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
  return p;
}

}  // namespace rgbd_lane_detector
