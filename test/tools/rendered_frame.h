// A frame of the synthetic renderer as the detector gets it from a SYNTHIA reader: depth as
// uint16 centimetres (channel 0 of the written PNG), scale 0.01.
#pragma once

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/types.h"
#include "rgbd_lane_detector_tools/synth/renderer.h"
#include "rgbd_lane_detector_tools/synth/sequence_writer.h"

namespace rgbd_lane_detector {
namespace test {

/// @p f as a Frame with intrinsics @p K; @p cm3 and @p cm hold the depth (reused buffers).
inline Frame synthiaFrame(const synth::RenderedFrame& f, const Intrinsics& K, cv::Mat& cm3,
                          cv::Mat& cm) {
  synth::encodeDepthCentimetres(f.depth, cm3);
  cv::extractChannel(cm3, cm, 0);
  Frame frame;
  frame.colour = f.bgr;
  frame.depth = cm;
  frame.depth_scale = 0.01;
  frame.intrinsics = K;
  return frame;
}

}  // namespace test
}  // namespace rgbd_lane_detector
