#include "lane_outputs.h"

#include <utility>

#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_eigen/tf2_eigen.h>
#include <visualization_msgs/MarkerArray.h>
#include <boost/make_shared.hpp>

#include <rgbd_lane_detector/LaneMarkings.h>
#include <rgbd_lane_detector/LaneModel.h>
#include <rgbd_lane_detector/LanePlane.h>

#include "rgbd_lane_detector/geometry.h"
#include "rgbd_lane_detector/lane_model.h"
#include "rgbd_lane_detector/overlay.h"
#include "rgbd_lane_detector/ros/conversions.h"

namespace rgbd_lane_detector {
namespace conv = conversions;

OutputPlan planOutputs(const Wanted& wanted, bool lane_model_on, bool vehicle_frame_found,
                       bool plane_valid) {
  OutputPlan plan;
  plan.model = wanted.model || wanted.centre;
  plan.grid_inset = wanted.debug && lane_model_on;
  plan.grid = wanted.grid || plan.grid_inset;
  // the road-aligned fallback frame, so that rviz and users can place the model
  const bool in_road_frame =
      (wanted.model || wanted.centre || wanted.markers || wanted.grid) && !vehicle_frame_found;
  plan.road_frame = in_road_frame && plane_valid;
  plan.road_frame_held = in_road_frame && !plane_valid;
  return plan;
}

geometry_msgs::TransformStamped roadFrameTransform(const PlaneEstimate& plane,
                                                   const std_msgs::Header& image,
                                                   const std::string& child) {
  geometry_msgs::TransformStamped tf = tf2::eigenToTransform(RoadFrame::fromPlane(plane).roadFromCamera().inverse());
  tf.header = image;
  tf.child_frame_id = child;
  return tf;
}

void LaneOutputs::advertise(ros::NodeHandle& nh, image_transport::ImageTransport& it,
                            const std::function<void()>& connect) {
  const ros::SubscriberStatusCallback cb = [connect](const ros::SingleSubscriberPublisher&) {
    connect();
  };
  const image_transport::SubscriberStatusCallback image_cb =
      [connect](const image_transport::SingleSubscriberPublisher&) { connect(); };
  plane_ = nh.advertise<LanePlane>("lane_plane", 5, cb, cb);
  markings_ = nh.advertise<LaneMarkings>("lane_markings", 5, cb, cb);
  points_ = nh.advertise<sensor_msgs::PointCloud2>("lane_points", 5, cb, cb);
  markers_ = nh.advertise<visualization_msgs::MarkerArray>("lane_visualization", 5, cb, cb);
  model_ = nh.advertise<LaneModel>("lane_model", 5, cb, cb);
  centre_ = nh.advertise<nav_msgs::Path>("lane_centre_line", 5, cb, cb);
  grid_ = nh.advertise<nav_msgs::OccupancyGrid>("lane_grid", 5, cb, cb);
  left_ = it.advertise("response/left", 1, image_cb, image_cb);
  right_ = it.advertise("response/right", 1, image_cb, image_cb);
  geometric_ = it.advertise("response/geometric", 1, image_cb, image_cb);
  debug_ = it.advertise("debug_image", 1, image_cb, image_cb);
}

Wanted LaneOutputs::wanted() const {
  Wanted w;
  w.plane = plane_.getNumSubscribers() > 0;
  w.markings = markings_.getNumSubscribers() > 0;
  w.points = points_.getNumSubscribers() > 0;
  w.markers = markers_.getNumSubscribers() > 0;
  w.model = model_.getNumSubscribers() > 0;
  w.centre = centre_.getNumSubscribers() > 0;
  w.grid = grid_.getNumSubscribers() > 0;
  w.left = left_.getNumSubscribers() > 0;
  w.right = right_.getNumSubscribers() > 0;
  w.geometric = geometric_.getNumSubscribers() > 0;
  w.debug = debug_.getNumSubscribers() > 0;
  return w;
}

void LaneOutputs::publish(const Wanted& wanted, const Frame& frame, const Result& result,
                          const Params& params, const Headers& headers,
                          const Eigen::Isometry3d& T, bool vehicle_frame_found) {
  const OutputPlan plan =
      planOutputs(wanted, params.lane_model, vehicle_frame_found, result.plane.valid);
  // The road frame first: a subscriber of the messages in it may look it up at their stamp.
  if (plan.road_frame || (plan.road_frame_held && !road_frame_.child_frame_id.empty())) {
    if (plan.road_frame)
      road_frame_ = roadFrameTransform(result.plane, headers.image, headers.model.frame_id);
    road_frame_.header.stamp = headers.image.stamp;  // held: the model stays in the last one
    if (!road_frame_broadcaster_) road_frame_broadcaster_.reset(new tf2_ros::TransformBroadcaster);
    road_frame_broadcaster_->sendTransform(road_frame_);
  }
  // Messages are allocated per publish (ROS 1 shares them with intra-process subscribers).
  if (wanted.plane) {
    auto msg = boost::make_shared<LanePlane>();
    conv::fillLanePlane(result, headers.out, T, *msg);
    plane_.publish(msg);
  }
  if (wanted.markings) {
    auto msg = boost::make_shared<LaneMarkings>();
    conv::fillLaneMarkings(result, headers.out, T, *msg);
    markings_.publish(msg);
  }
  if (wanted.points) {
    auto msg = boost::make_shared<sensor_msgs::PointCloud2>();
    conv::fillLanePoints(result, headers.out, T, *msg);
    points_.publish(msg);
  }
  if (plan.model) {
    auto msg = boost::make_shared<LaneModel>();
    conv::fillLaneModel(result.lane_model, headers.model, *msg);
    // the centre line on its own topic, for rviz's Path display and path followers
    if (wanted.centre) centre_.publish(boost::make_shared<nav_msgs::Path>(msg->centre_line));
    if (wanted.model) model_.publish(msg);
  }
  if (plan.grid) lane_grid_.build(result.lane_model, laneGridSettings(params));  // reused buffer
  if (wanted.grid) {
    auto msg = boost::make_shared<nav_msgs::OccupancyGrid>();
    conv::fillOccupancyGrid(lane_grid_, headers.model, *msg);
    grid_.publish(msg);
  }
  if (wanted.markers) {
    auto msg = boost::make_shared<visualization_msgs::MarkerArray>();
    conv::fillLaneMarkers(result, headers.out, T, *msg);
    conv::appendLaneModelMarkers(result.lane_model, headers.model, *msg);
    for (visualization_msgs::Marker& m : msg->markers) m.lifetime = marker_lifetime_;
    markers_.publish(msg);
  }
  // Images stay in the camera's optical frame (they are pixels of that camera), at the
  // processing resolution for the response maps.
  const std::pair<bool, std::pair<const cv::Mat*, const image_transport::Publisher*>> maps[] = {
      {wanted.left, {&result.response_left, &left_}},
      {wanted.right, {&result.response_right, &right_}},
      {wanted.geometric, {&result.geometric, &geometric_}}};
  for (const auto& m : maps) {
    if (!m.first) continue;
    auto msg = boost::make_shared<sensor_msgs::Image>();
    conv::floatMapToImage(*m.second.first, headers.image, *msg);
    m.second.second->publish(msg);
  }
  if (!wanted.debug) return;
  namespace enc = sensor_msgs::image_encodings;
  auto msg = boost::make_shared<sensor_msgs::Image>();
  cv::Mat out = conv::prepareImage(frame.colour.rows, frame.colour.cols, CV_8UC3, enc::BGR8,
                                   headers.image, *msg);
  const uchar* data = out.data;
  drawOverlay(frame.colour, frame.format, frame.intrinsics, result, params, out);
  if (plan.grid_inset) drawLaneGridInset(lane_grid_, out);
  if (out.data != data) {  // drawn elsewhere (size changed): copy into the message
    const cv::Mat drawn = out;
    out = conv::prepareImage(drawn.rows, drawn.cols, CV_8UC3, enc::BGR8, headers.image, *msg);
    drawn.copyTo(out);
  }
  debug_.publish(msg);
}

}  // namespace rgbd_lane_detector
