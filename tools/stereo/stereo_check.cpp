#include "rgbd_lane_detector_tools/stereo/stereo_check.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rgbd_lane_detector {
namespace tools {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double ratio(long a, long b) { return b > 0 ? static_cast<double>(a) / b : kNaN; }

double referenceAt(const cv::Mat& ref, double scale, int y, int x) {
  if (ref.type() == CV_16UC1) {
    const uint16_t v = ref.at<uint16_t>(y, x);
    return v ? v * scale : kNaN;
  }
  return ref.at<float>(y, x);
}

}  // namespace

constexpr std::array<double, 3> StereoCheck::kBins;

bool StereoCheck::add(const cv::Mat& estimate, const cv::Mat& reference, double reference_scale,
                      double fb, const cv::Rect& road) {
  if (estimate.type() != CV_32FC1 || estimate.size() != reference.size() ||
      (reference.type() != CV_16UC1 && reference.type() != CV_32FC1) || !(fb > 0.0))
    return false;
  const cv::Rect region = road & cv::Rect(0, 0, estimate.cols, estimate.rows);
  for (int y = 0; y < estimate.rows; ++y) {
    for (int x = 0; x < estimate.cols; ++x) {
      const double z_est = estimate.at<float>(y, x);
      const double z_ref = referenceAt(reference, reference_scale, y, x);
      const bool has_est = std::isfinite(z_est) && z_est > 0.0;
      const bool has_ref = std::isfinite(z_ref) && z_ref > 0.0;
      ++pixels_;
      estimated_ += has_est;
      if (!has_ref) continue;
      ++reference_;
      const bool in_road = region.contains(cv::Point(x, y)) && z_ref <= kBins.back();
      road_reference_ += in_road;
      if (!has_est) continue;
      ++matched_;
      const double d_ref = fb / z_ref, err = std::fabs(fb / z_est - d_ref);
      outliers_3px_ += err > 3.0;
      outliers_d1_ += err > 3.0 && err > 0.05 * d_ref;
      if (in_road) {
        const int bin = static_cast<int>(std::lower_bound(kBins.begin(), kBins.end(), z_ref) -
                                         kBins.begin());
        road_.push_back({static_cast<float>(z_est - z_ref), static_cast<float>(z_ref), bin});
      }
    }
  }
  return true;
}

double StereoCheck::density() const { return ratio(estimated_, pixels_); }
double StereoCheck::coverage() const { return ratio(matched_, reference_); }
double StereoCheck::outliers3px() const { return ratio(outliers_3px_, matched_); }
double StereoCheck::d1Matched() const { return ratio(outliers_d1_, matched_); }
double StereoCheck::d1All() const {
  return ratio(outliers_d1_ + (reference_ - matched_), reference_);
}
double StereoCheck::roadCoverage() const {
  return ratio(static_cast<long>(road_.size()), road_reference_);
}

long StereoCheck::roadPoints(int bin) const {
  return std::count_if(road_.begin(), road_.end(),
                       [bin](const Sample& s) { return bin < 0 || s.bin == bin; });
}

double StereoCheck::roadMeanError(int bin) const {
  double sum = 0;
  long n = 0;
  for (const Sample& s : road_)
    if (bin < 0 || s.bin == bin) sum += std::fabs(s.error), ++n;
  return n ? sum / n : kNaN;
}

double StereoCheck::roadMedianError(int bin) const {
  std::vector<float> e;
  for (const Sample& s : road_)
    if (bin < 0 || s.bin == bin) e.push_back(std::fabs(s.error));
  if (e.empty()) return kNaN;
  std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
  return e[e.size() / 2];
}

double StereoCheck::roadBias(int bin) const {
  double sum = 0;
  long n = 0;
  for (const Sample& s : road_)
    if (bin < 0 || s.bin == bin) sum += s.error, ++n;
  return n ? sum / n : kNaN;
}

double StereoCheck::roadRelativeError(int bin) const {
  double sum = 0;
  long n = 0;
  for (const Sample& s : road_)
    if (bin < 0 || s.bin == bin) sum += std::fabs(s.error) / s.z_ref, ++n;
  return n ? sum / n : kNaN;
}

}  // namespace tools
}  // namespace rgbd_lane_detector
