// FrameProcessor (src/ros/frame_processor.h) without a roscore: what the core gets from the
// messages is what it gets from the same images directly (bit-identical detections), parameters
// reach the detector at the next frame, cameras are prepared once, bad input is named.
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include <sensor_msgs/image_encodings.h>

#include "../../../src/ros/frame_processor.h"
#include "../../core/synthetic_scene.h"
#include "rgbd_lane_detector/ros/conversions.h"

namespace rgbd_lane_detector {
namespace {

namespace enc = sensor_msgs::image_encodings;

sensor_msgs::Image imageOf(const cv::Mat& m, const std::string& encoding) {
  sensor_msgs::Image msg;
  msg.header.frame_id = "camera_optical";
  msg.width = static_cast<uint32_t>(m.cols);
  msg.height = static_cast<uint32_t>(m.rows);
  msg.encoding = encoding;
  msg.step = static_cast<uint32_t>(m.cols * m.elemSize());
  msg.data.resize(static_cast<size_t>(msg.step) * msg.height);
  for (int y = 0; y < m.rows; ++y)
    std::memcpy(&msg.data[static_cast<size_t>(y) * msg.step], m.ptr(y), msg.step);
  return msg;
}

struct Inputs {
  test::RoadScene scene;
  cv::Mat bgr, depth_mm;
  sensor_msgs::Image colour, depth;
  sensor_msgs::CameraInfo info;
  Inputs() {
    scene.render(bgr, depth_mm);
    colour = imageOf(bgr, enc::BGR8);
    depth = imageOf(depth_mm, enc::TYPE_16UC1);
    info = conversions::cameraInfoFromIntrinsics(scene.K, bgr.cols, bgr.rows, colour.header);
  }
};

constexpr int64_t kFrameNs = 66666667;  // 15 Hz

bool sameTrace(const MarkerTrace& a, const MarkerTrace& b) {
  if (a.found != b.found || a.points.size() != b.points.size()) return false;
  return a.points.empty() ||
         std::memcmp(a.points.data(), b.points.data(), a.points.size() * sizeof(a.points[0])) == 0;
}

TEST(FrameProcessor, DetectsWhatTheCoreDetectsOnTheSameImages) {
  const Inputs in;
  FrameProcessor processor;
  processor.applyParams(nullptr);
  FrameProcessor::Preparation prepared;
  ASSERT_TRUE(processor.prepare(in.info, "rgb/image_rect_color", prepared));
  LaneDetector direct;
  ASSERT_EQ(direct.prepare(in.bgr.size(), in.scene.K), Status::kOk);
  Frame core;
  core.colour = in.bgr;
  core.depth = in.depth_mm;
  core.intrinsics = in.scene.K;
  Result expected;
  for (int i = 0; i < 3; ++i) {  // the carried state (tracks, templates) too
    Frame frame;
    const char* problem = nullptr;
    ASSERT_EQ(processor.load(in.colour, in.depth, in.info, frame, problem), FrameOutcome::kProcessed)
        << problem;
    EXPECT_EQ(frame.colour.data, in.colour.data.data()) << "colour copied, not read in place";
    EXPECT_EQ(frame.depth.data, in.depth.data.data()) << "depth copied, not read in place";
    ASSERT_EQ(processor.detect(frame, i * kFrameNs, nullptr, false, problem),
              FrameOutcome::kProcessed);
    ASSERT_EQ(direct.detect(core, expected), Status::kOk);
    const Result& got = processor.result();
    ASSERT_TRUE(got.plane.valid);
    EXPECT_EQ(got.plane.normal, expected.plane.normal);
    EXPECT_EQ(got.plane.distance, expected.plane.distance);
    EXPECT_TRUE(sameTrace(got.left, expected.left));
    EXPECT_TRUE(sameTrace(got.right, expected.right));
    EXPECT_TRUE(got.left.found && got.right.found);
  }
  EXPECT_TRUE(processor.firstFrameAfterPrepare());
  EXPECT_FALSE(processor.firstFrameAfterPrepare()) << "the first frame is reported once";
}

TEST(FrameProcessor, PreparesEachCameraOnceAndKeepsItThroughCalibrationJitter) {
  Inputs in;
  FrameProcessor processor;
  processor.applyParams(nullptr);
  FrameProcessor::Preparation p;
  ASSERT_TRUE(processor.prepare(in.info, "rgb/image_rect_color", p));
  EXPECT_EQ(p.size, in.bgr.size());
  EXPECT_TRUE(p.warning.empty());
  sensor_msgs::CameraInfo jitter = in.info;
  jitter.P[0] += 0.2;  // a driver re-estimating its calibration: the same camera
  EXPECT_FALSE(processor.prepare(jitter, "rgb/image_rect_color", p));
  Frame frame;
  const char* problem = nullptr;
  ASSERT_EQ(processor.load(in.colour, in.depth, jitter, frame, problem), FrameOutcome::kProcessed);
  EXPECT_EQ(frame.intrinsics.fx, in.scene.K.fx) << "frames keep the prepared intrinsics";
  sensor_msgs::CameraInfo zoomed = in.info;
  zoomed.P[0] *= 1.02;
  zoomed.P[5] *= 1.02;
  EXPECT_TRUE(processor.prepare(zoomed, "rgb/image_rect_color", p));
  EXPECT_DOUBLE_EQ(p.K.fx, zoomed.P[0]);
  // a raw image with a distorted camera on a topic that is not rectified: said
  sensor_msgs::CameraInfo raw = in.info;
  raw.D = {0.1, 0.0, 0.0, 0.0, 0.0};
  raw.P[0] *= 1.1;
  ASSERT_TRUE(processor.prepare(raw, "rgb/image_raw", p));
  EXPECT_NE(p.warning.find("rgb/image_raw"), std::string::npos) << p.warning;
  raw.P[0] *= 1.1;
  ASSERT_TRUE(processor.prepare(raw, "rgb/image_rect_color", p));
  EXPECT_TRUE(p.warning.empty()) << "a rectified topic with its raw lens's D is fine";
}

TEST(FrameProcessor, ReconfiguredParametersApplyAtTheNextFrameWithTheUpAxis) {
  FrameProcessor processor;
  processor.applyParams(nullptr);
  Params p = processor.params();
  p.tau_c = p.tau_c + 7;
  processor.setParams(p);
  EXPECT_NE(processor.params().tau_c, p.tau_c) << "applied before the next frame";
  const Eigen::Vector3d up(0.0, -0.8, 0.6);
  processor.applyParams(&up);
  EXPECT_EQ(processor.params().tau_c, p.tau_c);
  EXPECT_DOUBLE_EQ(processor.params().up_z, 0.6);
  processor.applyParams(nullptr);  // no change since: the up axis stays
  EXPECT_DOUBLE_EQ(processor.params().up_z, 0.6);
}

// Frames dropped for seconds (a paused driver, a missing transform) while the vehicle drove on:
// the lane model, which counts frames, is not carried over such a gap. A frame without lines
// right after a lane was seen keeps the model (one frame unseen); the same frame after a gap
// longer than max_frame_gap finds none.
TEST(FrameProcessor, TheLaneStartsAgainAfterAGapInTheStamps) {
  const Inputs lane;
  Inputs bare;
  bare.scene.left_painted = bare.scene.right_painted = false;
  bare.scene.render(bare.bgr, bare.depth_mm);
  bare.colour = imageOf(bare.bgr, enc::BGR8);
  bare.depth = imageOf(bare.depth_mm, enc::TYPE_16UC1);
  for (const double max_gap : {1.0, 0.0}) {
    FrameProcessor processor;
    processor.applyParams(nullptr);
    ASSERT_TRUE(processor.params().lane_model) << "the default mode tracks a lane model";
    processor.setMaxFrameGap(max_gap);
    FrameProcessor::Preparation prepared;
    ASSERT_TRUE(processor.prepare(lane.info, "rgb/image_rect_color", prepared));
    const auto detect = [&](const Inputs& in, int64_t stamp_ns) {
      Frame frame;
      const char* problem = nullptr;
      EXPECT_EQ(processor.load(in.colour, in.depth, in.info, frame, problem), FrameOutcome::kProcessed);
      EXPECT_EQ(processor.detect(frame, stamp_ns, nullptr, false, problem), FrameOutcome::kProcessed);
      return processor.result().lane_model.valid;
    };
    int64_t t = 1000 * kFrameNs;
    for (int i = 0; i < 5; ++i, t += kFrameNs) ASSERT_TRUE(detect(lane, t)) << "frame " << i;
    EXPECT_EQ(processor.restartGap(), 0.0);
    EXPECT_TRUE(detect(bare, t)) << "one frame without lines keeps the lane";
    EXPECT_EQ(processor.restartGap(), 0.0);
    ASSERT_TRUE(detect(lane, t += kFrameNs));
    t += 2000000000;  // 2 s without a detected frame
    if (max_gap > 0.0) {
      EXPECT_FALSE(detect(bare, t)) << "the old lane was kept across 2 s";
      EXPECT_NEAR(processor.restartGap(), 2.0, 1e-6);
      EXPECT_TRUE(detect(lane, t += kFrameNs)) << "and a lane is found again";
      EXPECT_EQ(processor.restartGap(), 0.0) << "said once";
    } else {
      EXPECT_TRUE(detect(bare, t)) << "max_frame_gap 0: tracks are kept over any gap";
      EXPECT_EQ(processor.restartGap(), 0.0);
    }
  }
}

TEST(FrameProcessor, BadMessagesAndInvalidFramesAreNamed) {
  Inputs in;
  FrameProcessor processor;
  processor.applyParams(nullptr);
  Frame frame;
  const char* problem = nullptr;
  sensor_msgs::Image bad = in.colour;
  bad.encoding = "rgb16";
  EXPECT_EQ(processor.load(bad, in.depth, in.info, frame, problem), FrameOutcome::kBadMessage);
  ASSERT_NE(problem, nullptr);
  EXPECT_NE(std::string(problem).find("colour encoding"), std::string::npos);
  sensor_msgs::CameraInfo zero = in.info;
  zero.K.fill(0.0);
  zero.P.fill(0.0);
  EXPECT_EQ(processor.load(in.colour, in.depth, zero, frame, problem), FrameOutcome::kInvalidFrame);
  EXPECT_STREQ(problem, statusMessage(Status::kInvalidIntrinsics));
}

}  // namespace
}  // namespace rgbd_lane_detector
