/**
 * @file bench_real_frames.h
 * @brief detect() on real corpus frames at their native sizes (../shared/realdata), beside the
 * generated frames: the default mode (automatic processing scale), the same at full scale, and
 * the OpenCV pipeline on the same frame, one thread. Skipped, with a message, without the data.
 */
#pragma once

namespace rgbd_lane_detector {
namespace bench {

/**
 * @brief Register BM_Real_Detect/<frame>, BM_Real_DetectFullScale/<frame> and
 * BM_Real_OpenCV/<frame> for each real frame found under $RLD_REALDATA (default: the
 * repository's ../shared/realdata).
 * @return number of frames registered (0: data absent; a line on stderr says so).
 */
int registerRealFrameBenchmarks();

}  // namespace bench
}  // namespace rgbd_lane_detector
