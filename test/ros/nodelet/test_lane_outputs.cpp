// LaneOutputs' pure part (src/ros/lane_outputs.h) and the diagnostics' processing status
// (src/ros/node_diagnostics.h), no roscore: what a frame's subscribers need built, the road
// frame, and the accounting as it is reported.
#include <map>
#include <string>

#include <gtest/gtest.h>

#include <tf2_eigen/tf2_eigen.h>

#include "../../../src/ros/lane_outputs.h"
#include "../../../src/ros/node_diagnostics.h"
#include "rgbd_lane_detector/lane_model.h"

namespace rgbd_lane_detector {
namespace {

TEST(LaneOutputs, NothingWantedIsNothingBuilt) {
  const Wanted none;
  EXPECT_FALSE(none.any());
  const OutputPlan plan = planOutputs(none, true, false, true);
  EXPECT_FALSE(plan.model || plan.grid || plan.grid_inset || plan.road_frame);
}

TEST(LaneOutputs, EachOutputAloneIsWanted) {
  bool Wanted::*fields[] = {&Wanted::plane, &Wanted::markings, &Wanted::points, &Wanted::markers,
                            &Wanted::model, &Wanted::centre,   &Wanted::grid,   &Wanted::left,
                            &Wanted::right, &Wanted::geometric, &Wanted::debug};
  for (bool Wanted::*f : fields) {
    Wanted w;
    w.*f = true;
    EXPECT_TRUE(w.any());
  }
}

TEST(LaneOutputs, TheLaneModelMessageServesTheModelAndTheCentreLine) {
  Wanted w;
  w.centre = true;
  EXPECT_TRUE(planOutputs(w, true, true, true).model);
  w = Wanted();
  w.plane = true;
  EXPECT_FALSE(planOutputs(w, true, true, true).model);
}

TEST(LaneOutputs, TheGridIsBuiltForLaneGridOrTheDebugInsetWithALaneModel) {
  Wanted w;
  w.debug = true;
  EXPECT_TRUE(planOutputs(w, true, false, false).grid_inset);
  EXPECT_TRUE(planOutputs(w, true, false, false).grid);
  EXPECT_FALSE(planOutputs(w, false, false, false).grid) << "paper mode: no lane model, no inset";
  w = Wanted();
  w.grid = true;
  EXPECT_TRUE(planOutputs(w, false, false, false).grid);
  EXPECT_FALSE(planOutputs(w, false, false, false).grid_inset);
}

TEST(LaneOutputs, TheRoadFrameIsBroadcastOnlyWithoutAVehicleFrameAndWithAPlane) {
  for (bool Wanted::*f : {&Wanted::model, &Wanted::centre, &Wanted::markers, &Wanted::grid}) {
    Wanted w;
    w.*f = true;
    EXPECT_TRUE(planOutputs(w, true, false, true).road_frame);
    EXPECT_FALSE(planOutputs(w, true, true, true).road_frame) << "tf has the vehicle frame";
    EXPECT_FALSE(planOutputs(w, true, false, false).road_frame) << "no plane, no road frame";
    EXPECT_TRUE(planOutputs(w, true, false, false).road_frame_held)
        << "no plane: the last road frame again, where the lane model was predicted";
    EXPECT_FALSE(planOutputs(w, true, false, true).road_frame_held);
    EXPECT_FALSE(planOutputs(w, true, true, false).road_frame_held) << "tf has the vehicle frame";
  }
  Wanted w;
  w.plane = w.markings = w.points = w.left = w.right = w.geometric = w.debug = true;
  EXPECT_FALSE(planOutputs(w, true, false, true).road_frame) << "nothing in the model's frame";
  EXPECT_FALSE(planOutputs(w, true, false, false).road_frame_held);
}

TEST(LaneOutputs, RoadFrameIsUnderTheCameraOnTheRoad) {
  PlaneEstimate plane;
  plane.valid = true;
  plane.normal = Eigen::Vector3d(0, -1, 0);  // camera level, 1.5 m above the road
  plane.distance = 1.5;
  std_msgs::Header image;
  image.frame_id = "camera_optical";
  image.stamp = ros::Time(12.5);
  const geometry_msgs::TransformStamped t = roadFrameTransform(plane, image, "camera_optical_road");
  EXPECT_EQ(t.header.frame_id, "camera_optical");
  EXPECT_EQ(t.header.stamp, image.stamp);
  EXPECT_EQ(t.child_frame_id, "camera_optical_road");
  const Eigen::Isometry3d T = tf2::transformToEigen(t);  // road points into the optical frame
  EXPECT_TRUE(T.translation().isApprox(Eigen::Vector3d(0, 1.5, 0), 1e-9)) << T.translation();
  EXPECT_TRUE((T.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d(0, -1, 0), 1e-9))
      << "the road's up is the plane normal";
  EXPECT_TRUE((T.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d(0, 0, 1), 1e-9))
      << "forward is the optical axis on the road";
}

std::map<std::string, std::string> values(const diagnostic_updater::DiagnosticStatusWrapper& s) {
  std::map<std::string, std::string> kv;
  for (const auto& v : s.values) kv[v.key] = v.value;
  return kv;
}

TEST(NodeDiagnostics, ProcessingStatusReportsTheAccounting) {
  FrameAccounting a;
  static const char ids[4] = {};
  for (int i = 0; i < 4; ++i) a.received(&ids[i], 100 + i, static_cast<uint32_t>(i));
  a.synchronised(&ids[0], 100, FrameOutcome::kProcessed, nullptr, 4.0, 3.0);
  a.synchronised(&ids[1], 101, FrameOutcome::kProcessed, nullptr, 6.0, 5.0);
  diagnostic_updater::DiagnosticStatusWrapper ok;
  processingStatus(a.report(), true, ok);
  EXPECT_EQ(ok.level, diagnostic_msgs::DiagnosticStatus::OK);
  EXPECT_EQ(ok.message, "5.0 ms per frame");
  auto kv = values(ok);
  EXPECT_EQ(kv["Frames received"], "4");
  EXPECT_EQ(kv["Frames processed"], "2");
  EXPECT_EQ(kv["Frames waiting"], "2");
  EXPECT_EQ(kv["Frames unaccounted"], "0");
  EXPECT_EQ(kv["Mean ROS overhead (ms)"], "1.000");
  EXPECT_EQ(kv["Inputs subscribed"], "True");

  a.synchronised(&ids[3], 103, FrameOutcome::kBadMessage, "image step is too small", 1.0, 0.0);
  diagnostic_updater::DiagnosticStatusWrapper warn;
  processingStatus(a.report(), true, warn);
  EXPECT_EQ(warn.level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_NE(warn.message.find("1 frame(s) dropped: image step is too small"), std::string::npos)
      << warn.message;
  kv = values(warn);
  EXPECT_EQ(kv["Frames not synchronised"], "1") << "the colour image passed over";
  EXPECT_EQ(kv["Frames unaccounted"], "0");

  diagnostic_updater::DiagnosticStatusWrapper idle;
  processingStatus(FrameAccounting().report(), false, idle);
  EXPECT_EQ(idle.message, "Idle: no subscribers");
  diagnostic_updater::DiagnosticStatusWrapper waiting;
  processingStatus(FrameAccounting().report(), true, waiting);
  EXPECT_EQ(waiting.message, "Waiting for frames");
}

}  // namespace
}  // namespace rgbd_lane_detector
