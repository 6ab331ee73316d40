// Standalone node: loads the LaneDetectorNodelet into this process (same code, same names).
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "lane_detector");
  nodelet::Loader loader(false);  // no load/unload services: this process runs one nodelet
  const nodelet::M_string remappings(ros::names::getRemappings());
  const nodelet::V_string nodelet_argv(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), "rgbd_lane_detector/LaneDetectorNodelet", remappings,
                   nodelet_argv)) {
    ROS_FATAL("Could not load the rgbd_lane_detector/LaneDetectorNodelet plugin");
    return 1;
  }
  ros::spin();
  return 0;
}
