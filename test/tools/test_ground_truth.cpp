// Ground truth JSON (ground_truth.h): format 2 round trip (boundaries, labels, vehicle frame,
// lane model, mount), format 1 files of generator version 1, malformed files.
#include <cstdio>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "rgbd_lane_detector_tools/ground_truth.h"
#include "temp_file.h"

namespace rgbd_lane_detector {
namespace tools {
namespace {

TrueBoundary boundary(BoundaryLabel label, BoundaryKind kind, double x) {
  TrueBoundary b;
  b.label = label;
  b.kind = kind;
  b.style = kind == BoundaryKind::kPaint ? LineStyle::kDoubleSolid : LineStyle::kRoadEdge;
  b.colour = kind == BoundaryKind::kPaint ? LineColour::kYellow : LineColour::kNone;
  b.edge = kind == BoundaryKind::kPaint ? EdgeType::kNone : EdgeType::kKerb;
  for (double z = 3.0; z <= 10.0; z += 0.5) b.points.emplace_back(x, 1.5, z);
  return b;
}

TEST(GroundTruth, JsonRoundTrip) {
  SequenceTruth seq;
  seq.has_mount = true;
  seq.mount.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  seq.mount.translation() = Eigen::Vector3d(0.1, 0.0, 1.5);
  FrameTruth f;
  f.index = 0;
  f.normal = Eigen::Vector3d(0.01, -1, -0.05).normalized();
  f.distance = 1.5;
  f.plane_rms = 0.012;
  f.lane_optional = true;
  f.boundaries = {boundary(BoundaryLabel::kEgoLeft, BoundaryKind::kPaint, -1.8),
                  boundary(BoundaryLabel::kEgoRight, BoundaryKind::kRoadEdge, 1.7),
                  boundary(BoundaryLabel::kRoadEdgeLeft, BoundaryKind::kRoadEdge, -9.0)};
  f.syncEgoLines();
  f.has_vehicle_frame = true;
  f.base_to_camera = seq.mount;
  f.lane = {true, 3.5, -0.2, 0.01, -0.003};
  seq.frames.push_back(f);
  FrameTruth empty;
  empty.index = 1;
  empty.distance = 1.5;
  seq.frames.push_back(empty);
  const std::string path = ::testing::TempDir() + "/rgbd_tools_gt.json";
  std::string error;
  ASSERT_TRUE(writeGroundTruth(path, seq, error)) << error;
  SequenceTruth back;
  ASSERT_TRUE(readGroundTruth(path, back, error)) << error;
  EXPECT_EQ(back.format, 2);
  ASSERT_TRUE(back.has_mount);
  EXPECT_TRUE(back.mount.isApprox(seq.mount, 1e-12));
  ASSERT_EQ(back.frames.size(), 2u);
  const FrameTruth* f0 = back.find(0);
  ASSERT_NE(f0, nullptr);
  EXPECT_TRUE(f0->has_lane);
  EXPECT_TRUE(f0->lane_optional);
  EXPECT_NEAR(f0->plane_rms, 0.012, 1e-15);
  EXPECT_NEAR((f0->normal - f.normal).norm(), 0.0, 1e-15);
  ASSERT_EQ(f0->boundaries.size(), 3u);
  const TrueBoundary* right = f0->egoSide(false);
  ASSERT_NE(right, nullptr);
  EXPECT_EQ(right->kind, BoundaryKind::kRoadEdge);
  EXPECT_EQ(right->style, LineStyle::kRoadEdge);
  EXPECT_EQ(right->colour, LineColour::kNone);
  EXPECT_EQ(right->edge, EdgeType::kKerb);
  EXPECT_EQ(f0->egoSide(true)->style, LineStyle::kDoubleSolid);
  EXPECT_EQ(f0->egoSide(true)->colour, LineColour::kYellow);
  EXPECT_EQ(f0->boundary(BoundaryLabel::kNextLeft), nullptr);
  ASSERT_NE(f0->boundary(BoundaryLabel::kRoadEdgeLeft), nullptr);
  // the ego lines are the ego boundaries' points, written to 0.1 mm
  ASSERT_EQ(f0->left.size(), f.left.size());
  EXPECT_NEAR((f0->left.back() - f.left.back()).norm(), 0.0, 1e-4);
  EXPECT_NEAR((f0->right.front() - f.right.front()).norm(), 0.0, 1e-4);
  // vehicle frame, lane model, base_link points derived from the transform
  ASSERT_TRUE(f0->has_vehicle_frame);
  EXPECT_TRUE(f0->base_to_camera.isApprox(f.base_to_camera, 1e-12));
  EXPECT_TRUE(f0->lane.valid);
  EXPECT_DOUBLE_EQ(f0->lane.width, 3.5);
  EXPECT_DOUBLE_EQ(f0->lane.offset, -0.2);
  EXPECT_DOUBLE_EQ(f0->lane.heading, 0.01);
  EXPECT_DOUBLE_EQ(f0->lane.curvature, -0.003);
  ASSERT_EQ(right->points_base.size(), right->points.size());
  EXPECT_NEAR((right->points_base[3] - seq.mount * f.right[3]).norm(), 0.0, 1e-4);
  // a frame without boundaries
  EXPECT_FALSE(back.find(1)->has_lane);
  EXPECT_TRUE(back.find(1)->right.empty());
  EXPECT_FALSE(back.find(1)->has_vehicle_frame);
  EXPECT_EQ(back.find(7), nullptr);
  std::remove(path.c_str());
  EXPECT_FALSE(readGroundTruth(path, back, error));
  EXPECT_NE(error.find(path), std::string::npos);
}

TEST(GroundTruth, ReadsGeneratorVersionOneFiles) {
  // format 1 (cv::FileStorage JSON of generator version 1): ego lines only
  const std::string path = writeTempFile("rgbd_tools_gt_v1.json", R"({
    "frames": [
      {"index": 0, "plane_normal": [0.0, -0.998629534, -0.0523359562], "plane_distance": 1.5,
       "has_lane": 1, "left": [[-1.8, 1.3, 3.0], [-1.8, 1.2, 5.0]],
       "right": [[1.8, 1.3, 3.0], [1.8, 1.2, 5.0]]},
      {"index": 1, "plane_normal": [0.0, -1.0, 0.0], "plane_distance": 1.5, "has_lane": 0,
       "left": [], "right": []}
    ]
  })");
  SequenceTruth truth;
  std::string error;
  ASSERT_TRUE(readGroundTruth(path, truth, error)) << error;
  EXPECT_EQ(truth.format, 1);
  EXPECT_FALSE(truth.has_mount);
  ASSERT_EQ(truth.frames.size(), 2u);
  const FrameTruth& f = truth.frames[0];
  EXPECT_TRUE(f.has_lane);
  EXPECT_FALSE(f.lane_optional);
  EXPECT_FALSE(f.has_vehicle_frame);
  ASSERT_NE(f.egoSide(true), nullptr);
  EXPECT_EQ(f.egoSide(true)->kind, BoundaryKind::kPaint);
  EXPECT_EQ(f.egoSide(true)->style, LineStyle::kUnknown);
  EXPECT_EQ(f.egoSide(false)->colour, LineColour::kUnknown);
  EXPECT_EQ(f.egoSide(false)->points.size(), 2u);
  EXPECT_EQ(truth.frames[1].egoSide(true), nullptr);
  EXPECT_FALSE(truth.frames[1].has_lane);
  std::remove(path.c_str());
}

TEST(GroundTruth, RefusesMalformedFiles) {
  const std::string head = R"({"format": 2, "frames": [{"index": 0, "plane_normal": [0, -1, 0],
      "plane_distance": 1.5, "plane_rms": 0, "has_lane": 1, "lane_optional": 0, "boundaries": [)";
  const std::string ego = R"({"label": "ego_left", "kind": "paint", "style": "solid",
      "colour": "white", "edge": "none", "points": [[-1.8, 1.5, 3.0]]})";
  SequenceTruth truth;
  std::string error;
  // well-formed first, so the failures below are the edits'
  ASSERT_TRUE(readGroundTruth(writeTempFile("gt_ok.json", head + ego + "]}]}"), truth, error))
      << error;
  EXPECT_NE(truth.frames[0].egoSide(true), nullptr);
  const auto edited = [&ego](const std::string& from, const std::string& to) {
    std::string e = ego;
    return e.replace(e.find(from), from.size(), to);
  };
  for (const std::string& bad :
       {head + ego + "," + ego + "]}]}",                                // label twice
        head + edited("ego_left", "ego_middle") + "]}]}",               // unknown label
        head + edited("solid", "dotted") + "]}]}",                      // unknown style
        head + edited("[[-1.8, 1.5, 3.0]]", "[]") + "]}]}",             // no points
        head + edited("[[-1.8, 1.5, 3.0]]", "[[-1.8, 1.5]]") + "]}]}",  // not 3D
        std::string(R"({"format": 3, "frames": []})")}) {                // a newer format
    EXPECT_FALSE(readGroundTruth(writeTempFile("gt_bad.json", bad), truth, error)) << bad;
    EXPECT_FALSE(error.empty());
  }
}

}  // namespace
}  // namespace tools
}  // namespace rgbd_lane_detector
