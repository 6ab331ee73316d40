#include "opencv_pipeline.h"

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector/response_map.h"

namespace rgbd_lane_detector {
namespace bench {

void OpenCvPipeline::configure(const Frame& frame, const Params& params) {
  params_ = params;
  size_ = frame.colour.size();
  const int top = static_cast<int>(std::lround(params.roi_top * size_.height));
  const int bottom = static_cast<int>(std::lround(params.roi_bottom * size_.height));
  roi = cv::Rect(0, top, size_.width, bottom - top);
  const Intrinsics& k = frame.intrinsics;
  K_ = (cv::Mat_<float>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  fals_ = cv::makePtr<cv::rgbd::RgbdNormals>(size_.height, size_.width, CV_32F, K_,
                                             params.normal_window,
                                             cv::rgbd::RgbdNormals::RGBD_NORMALS_METHOD_FALS);
  fals_->initialize();
  half_binary = cv::Mat::zeros(size_, CV_8UC1);
  geometric = cv::Mat::zeros(size_, CV_32FC1);
}

void OpenCvPipeline::preprocess(const Frame& frame) {
  cv::cvtColor(frame.colour.rowRange(roi.y, roi.br().y), grey, cv::COLOR_BGR2GRAY);
  cv::Mat dst = half_binary.rowRange(roi.y, roi.br().y);
  cv::threshold(grey, dst, params_.tau_c - 1, 255, cv::THRESH_TOZERO);
}

void OpenCvPipeline::points(const Frame& frame) {
  cv::rgbd::depthTo3d(frame.depth, K_, points3d);
}

void OpenCvPipeline::normals() {
  (*fals_)(points3d, normals3d);
}

namespace {
void matchOne(const cv::Mat& image, const cv::Rect& roi, const LineTemplate& t, cv::Mat& out) {
  out = cv::Mat::zeros(image.size(), CV_32FC1);
  cv::Mat scores;
  cv::matchTemplate(image(roi), t.image, scores, cv::TM_CCOEFF_NORMED);
  cv::max(scores, 0.0, scores);
  scores.copyTo(out(cv::Rect(roi.x + t.size / 2, roi.y + t.size / 2, scores.cols, scores.rows)));
}
}  // namespace

void OpenCvPipeline::matching(const LineTemplate& left, const LineTemplate& right) {
  matchOne(half_binary, roi, left, match_left);
  matchOne(half_binary, roi, right, match_right);
}

void OpenCvPipeline::response() {
  const float ux = static_cast<float>(params_.up_x), uy = static_cast<float>(params_.up_y),
              uz = static_cast<float>(params_.up_z), tau = static_cast<float>(params_.tau_g);
  match_left.copyTo(response_left);
  match_right.copyTo(response_right);
  for (int v = roi.y; v < roi.br().y; ++v) {
    const cv::Vec3f* p = points3d.ptr<cv::Vec3f>(v);
    const cv::Vec3f* n = normals3d.ptr<cv::Vec3f>(v);
    float* g = geometric.ptr<float>(v);
    float* rl = response_left.ptr<float>(v);
    float* rr = response_right.ptr<float>(v);
    for (int u = 0; u < size_.width; ++u) {
      g[u] = geometricValue(p[u][2], n[u][0] * ux + n[u][1] * uy + n[u][2] * uz, v, size_.height,
                            params_);
      rl[u] = fusedValue(rl[u], g[u], tau);
      rr[u] = fusedValue(rr[u], g[u], tau);
    }
  }
}

}  // namespace bench
}  // namespace rgbd_lane_detector
