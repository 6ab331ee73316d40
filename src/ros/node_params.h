/**
 * @file node_params.h
 * @brief The nodelet's own parameters (topics' queues, sync policy, transports, frames, tf,
 * diagnostics): one field per line of node_params.def, read once at start-up. Private to the
 * nodelet library.
 */
#pragma once

#include <string>

namespace ros {
class NodeHandle;
}

namespace rgbd_lane_detector {

struct NodeParams {
#define RLD_NODE_PARAM(type, name, default_value, description) type name = default_value;
#include "node_params.def"
#undef RLD_NODE_PARAM

  /// Every parameter from the private namespace (its default when unset), then repaired:
  /// queue_size >= 1; tf_timeout, max_sync_interval and max_frame_gap >= 0
  /// (0: no limit); diagnostic_period >= 0.05; the frames without tf1's leading '/'.
  static NodeParams read(const ros::NodeHandle& pnh);
  /// The repairs of read() on their own.
  NodeParams sanitized() const;
};

}  // namespace rgbd_lane_detector
