#include "rgbd_lane_detector/template_matching.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace rgbd_lane_detector {

bool NccMatcher::match(const cv::Mat& image, const cv::Rect& region_in, const LineTemplate& left,
                       const LineTemplate& right, cv::Mat& response_left,
                       cv::Mat& response_right) {
  CV_Assert(image.type() == CV_8UC1 && left.size == right.size);
  response_left.create(image.size(), CV_32FC1);
  response_right.create(image.size(), CV_32FC1);
  response_left.setTo(0);
  response_right.setTo(0);
  const cv::Rect region = region_in & cv::Rect(0, 0, image.cols, image.rows);
  const int s = left.size;
  if (region.width < s || region.height < s) return false;

  const int w = region.width, h = region.height;
  const int ow = w - s + 1, oh = h - s + 1;  // output positions
  prefix_.create(h, w + 1, CV_32SC1);
  row_sum_.create(h, ow, CV_32SC1);
  row_sq_.create(h, ow, CV_32SC1);
  win_sum_.create(oh, ow, CV_32SC1);
  win_sq_.create(oh, ow, CV_64FC1);
  acc_.create(1, ow, CV_32SC1);

  // Row prefix sums, and horizontal window sums of I and I^2 (exact integers).
  for (int r = 0; r < h; ++r) {
    const uint8_t* src = image.ptr<uint8_t>(region.y + r) + region.x;
    int* P = prefix_.ptr<int>(r);
    P[0] = 0;
    for (int c = 0; c < w; ++c) P[c + 1] = P[c] + src[c];
    int* rs = row_sum_.ptr<int>(r);
    int* rq = row_sq_.ptr<int>(r);
    int sq = 0;
    for (int c = 0; c < s; ++c) sq += src[c] * src[c];
    rq[0] = sq;
    for (int x = 0; x < ow; ++x) rs[x] = P[x + s] - P[x];
    for (int x = 1; x < ow; ++x) {
      sq += src[x + s - 1] * src[x + s - 1] - src[x - 1] * src[x - 1];
      rq[x] = sq;
    }
  }
  // Vertical window sums of I and I^2.
  int* S = win_sum_.ptr<int>(0);
  double* Q = win_sq_.ptr<double>(0);
  for (int x = 0; x < ow; ++x) {
    int a = 0, b = 0;
    for (int r = 0; r < s; ++r) {
      a += row_sum_.at<int>(r, x);
      b += row_sq_.at<int>(r, x);
    }
    S[x] = a;
    Q[x] = b;
  }
  for (int y = 1; y < oh; ++y) {
    const int* Sp = win_sum_.ptr<int>(y - 1);
    const double* Qp = win_sq_.ptr<double>(y - 1);
    int* Sy = win_sum_.ptr<int>(y);
    double* Qy = win_sq_.ptr<double>(y);
    const int* add_s = row_sum_.ptr<int>(y + s - 1);
    const int* sub_s = row_sum_.ptr<int>(y - 1);
    const int* add_q = row_sq_.ptr<int>(y + s - 1);
    const int* sub_q = row_sq_.ptr<int>(y - 1);
    for (int x = 0; x < ow; ++x) {
      Sy[x] = Sp[x] + add_s[x] - sub_s[x];
      Qy[x] = Qp[x] + (add_q[x] - sub_q[x]);
    }
  }
  // Replace the window energy by 1 / sqrt(sum (I - mean)^2), or 0 for flat windows
  // (OpenCV: diff2 <= min(0.5, 10 FLT_EPSILON wndSum2) gives 0).
  const double inv_area = 1.0 / (static_cast<double>(s) * s);
  for (int y = 0; y < oh; ++y) {
    const int* Sy = win_sum_.ptr<int>(y);
    double* Qy = win_sq_.ptr<double>(y);
    for (int x = 0; x < ow; ++x) {
      const double sum = Sy[x], sum2 = Qy[x];
      const double diff2 = std::max(sum2 - sum * sum * inv_area, 0.0);
      Qy[x] = diff2 <= std::min(0.5, 10 * FLT_EPSILON * sum2) ? 0.0 : 1.0 / std::sqrt(diff2);
    }
  }
  correlate(left, region, response_left);
  correlate(right, region, response_right);
  return true;
}

void NccMatcher::correlate(const LineTemplate& t, const cv::Rect& region, cv::Mat& response) {
  const int s = t.size;
  const int ow = region.width - s + 1, oh = region.height - s + 1;
  const double area = static_cast<double>(s) * s;
  const double n_t = t.count;
  // sum (T - mean T)^2 for a binary template, in units where T is 1 on the line.
  const double templ_var = n_t - n_t * n_t / area;
  if (templ_var <= 0.0) return;  // empty or full template: no correlation defined, leave 0
  const double templ_norm = std::sqrt(templ_var);
  const double mean_t = n_t / area;
  int* acc = acc_.ptr<int>();
  const int off = s / 2;
  for (int y = 0; y < oh; ++y) {
    std::fill(acc, acc + ow, 0);
    for (int r = 0; r < s; ++r) {
      const int b = t.run_begin[r], e = t.run_end[r];
      if (e <= b) continue;
      const int* P = prefix_.ptr<int>(y + r);
      const int* Pe = P + e;
      const int* Pb = P + b;
      for (int x = 0; x < ow; ++x) acc[x] += Pe[x] - Pb[x];
    }
    const int* Sy = win_sum_.ptr<int>(y);
    const double* inv_sd = win_sq_.ptr<double>(y);
    float* out = response.ptr<float>(region.y + y + off) + region.x + off;
    for (int x = 0; x < ow; ++x) {
      const double num = acc[x] - mean_t * Sy[x];
      double v = num * inv_sd[x] / templ_norm;
      v = v > 1.0 ? 1.0 : v;
      out[x] = v > 0.0 ? static_cast<float>(v) : 0.f;
    }
  }
}

void matchTemplateReference(const cv::Mat& image, const cv::Rect& region_in, const LineTemplate& t,
                            cv::Mat& response) {
  response.create(image.size(), CV_32FC1);
  response.setTo(0);
  const cv::Rect region = region_in & cv::Rect(0, 0, image.cols, image.rows);
  const int s = t.size;
  if (region.width < s || region.height < s) return;
  cv::Mat scores;
  cv::matchTemplate(image(region), t.image, scores, cv::TM_CCOEFF_NORMED);
  cv::max(scores, 0.0, scores);
  scores.copyTo(response(cv::Rect(region.x + s / 2, region.y + s / 2, scores.cols, scores.rows)));
}

}  // namespace rgbd_lane_detector
