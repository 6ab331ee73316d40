/**
 * @file road_frames.h
 * @brief Deterministic RGB-D road frames for the benchmarks (ray-cast, no external data).
 */
#pragma once

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {
namespace bench {

/// One rendered frame: bgr8 colour, uint16 depth in millimetres, SYNTHIA-like intrinsics.
struct RoadFrame {
  cv::Mat bgr;
  cv::Mat depth_mm;
  Intrinsics K;
  Frame frame() const;
};

/**
 * @brief Render frame @p index of a straight two-lane road at @p width x @p height.
 *
 * The camera (1.5 m high, pitched down 0.08 rad, f = 0.832 width) drives forward 1.5 m per
 * frame and sways laterally, so the dashed right marker moves between frames. The asphalt
 * carries a textured grey around the half-binary threshold (about 10% of its pixels survive
 * tau_c = 100, so the matcher cannot skip the road), a car stands in the next lane (a vertical
 * surface for the normals), the sky is bright, depth has 1 mm noise, is 0 beyond 60 m and
 * has a dozen hole blobs (3 to 9 px radius at 640 x 380).
 */
void renderRoadFrame(int width, int height, int index, RoadFrame& out);

}  // namespace bench
}  // namespace rgbd_lane_detector
