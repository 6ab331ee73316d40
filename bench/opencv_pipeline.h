/**
 * @file opencv_pipeline.h
 * @brief The straightforward OpenCV implementation of stages 1-5, the benchmarks' baseline.
 */
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/rgbd.hpp>

#include "rgbd_lane_detector/line_template.h"
#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {
namespace bench {

/**
 * @brief What a plain OpenCV implementation of the method does per frame: cvtColor and
 * threshold (TOZERO) on the searched rows, rgbd::depthTo3d, rgbd::RgbdNormals (FALS, 5x5,
 * CV_32F) over the frame, cv::matchTemplate (TM_CCOEFF_NORMED) with both templates over the
 * searched rows, and per-pixel loops for G (Eq. 2) and R (Eq. 3). Detection proper (seeds,
 * PCA, tracing, plane) is not included, so ratios against the full detect() are conservative.
 */
class OpenCvPipeline {
 public:
  void configure(const Frame& frame, const Params& params);
  void preprocess(const Frame& frame);
  void points(const Frame& frame);
  void normals();
  void matching(const LineTemplate& left, const LineTemplate& right);
  void response();
  void run(const Frame& frame, const LineTemplate& left, const LineTemplate& right) {
    preprocess(frame);
    points(frame);
    normals();
    matching(left, right);
    response();
  }

  cv::Rect roi;
  cv::Mat grey, half_binary, points3d, normals3d, match_left, match_right, geometric, response_left,
      response_right;

 private:
  Params params_;
  cv::Size size_;
  cv::Mat K_;
  cv::Ptr<cv::rgbd::RgbdNormals> fals_;
};

}  // namespace bench
}  // namespace rgbd_lane_detector
