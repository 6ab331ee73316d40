#include "rgbd_lane_detector_tools/stereo/stereo_matcher.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include <opencv2/imgproc.hpp>

namespace rgbd_lane_detector {
namespace tools {
namespace {

constexpr float kNoMatch = -1.f;  // min_disparity (0) - 1

int sgbmMode(const std::string& mode) {
  if (mode == "sgbm") return cv::StereoSGBM::MODE_SGBM;
  if (mode == "hh") return cv::StereoSGBM::MODE_HH;
  if (mode == "3way") return cv::StereoSGBM::MODE_SGBM_3WAY;
  if (mode == "hh4") return cv::StereoSGBM::MODE_HH4;
  return -1;
}

bool parseInt(const std::string& text, int lo, int hi, int& out) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < lo || v > hi) return false;
  out = static_cast<int>(v);
  return true;
}

bool parseBool(const std::string& text, bool& out) {
  if (text == "true" || text == "1") {
    out = true;
  } else if (text == "false" || text == "0") {
    out = false;
  } else {
    return false;
  }
  return true;
}

}  // namespace

bool setSgbmParam(SgbmParams& p, const std::string& key, const std::string& value,
                  std::string& error) {
  bool ok = true;
  std::string expected;
  if (key == "num_disparities") {
    ok = parseInt(value, 16, 1024, p.num_disparities) && p.num_disparities % 16 == 0;
    expected = "a multiple of 16 in 16..1024";
  } else if (key == "block_size") {
    ok = parseInt(value, 1, 31, p.block_size) && p.block_size % 2 == 1;
    expected = "an odd number in 1..31";
  } else if (key == "mode") {
    ok = sgbmMode(value) >= 0;
    if (ok) p.mode = value;
    expected = "sgbm, hh, 3way or hh4";
  } else if (key == "grey" || key == "pad_left") {
    ok = parseBool(value, key == "grey" ? p.grey : p.pad_left);
    expected = "true or false";
  } else if (key == "uniqueness_ratio") {
    ok = parseInt(value, 0, 100, p.uniqueness_ratio);
    expected = "0..100";
  } else if (key == "speckle_window") {
    ok = parseInt(value, 0, 100000, p.speckle_window);
    expected = "0..100000";
  } else if (key == "speckle_range") {
    ok = parseInt(value, 0, 1000, p.speckle_range);
    expected = "0..1000";
  } else if (key == "disp12_max_diff") {
    ok = parseInt(value, -1, 1000, p.disp12_max_diff);
    expected = "-1 (off) ..1000";
  } else if (key == "pre_filter_cap") {
    ok = parseInt(value, 1, 63, p.pre_filter_cap);
    expected = "1..63";
  } else if (key == "lr_check") {
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    ok = !value.empty() && *end == '\0' && std::isfinite(v) && v >= 0.0;
    if (ok) p.lr_check = v;
    expected = "a tolerance in pixels >= 0 (0: off)";
  } else {
    error = "unknown StereoSGBM parameter '" + key +
            "' (num_disparities, block_size, mode, grey, uniqueness_ratio, speckle_window, "
            "speckle_range, disp12_max_diff, pre_filter_cap, lr_check, pad_left)";
    return false;
  }
  if (!ok) error = "StereoSGBM parameter " + key + "=" + value + ": expected " + expected;
  return ok;
}

std::string sgbmParamsText(const SgbmParams& p) {
  std::ostringstream s;
  s << "num_disparities=" << p.num_disparities << " block_size=" << p.block_size
    << " mode=" << p.mode << " grey=" << (p.grey ? "true" : "false")
    << " uniqueness_ratio=" << p.uniqueness_ratio << " speckle_window=" << p.speckle_window
    << " speckle_range=" << p.speckle_range << " disp12_max_diff=" << p.disp12_max_diff
    << " pre_filter_cap=" << p.pre_filter_cap << " lr_check=" << p.lr_check
    << " pad_left=" << (p.pad_left ? "true" : "false");
  return s.str();
}

StereoMatcher::StereoMatcher(const SgbmParams& params) : params_(params) {
  const int cn = params_.grey ? 1 : 3;
  const int area = params_.block_size * params_.block_size;
  sgbm_ = cv::StereoSGBM::create(0, params_.num_disparities, params_.block_size, 8 * cn * area,
                                 32 * cn * area, params_.disp12_max_diff, params_.pre_filter_cap,
                                 params_.uniqueness_ratio, params_.speckle_window,
                                 params_.speckle_range, sgbmMode(params_.mode));
}

DisparityModel StereoMatcher::model(double focal, double baseline) const {
  DisparityModel m;
  m.focal = focal;
  m.baseline = baseline;
  m.min_disparity = 0.0;
  m.max_disparity = params_.num_disparities - 1;
  m.delta_d = 1.0 / cv::StereoMatcher::DISP_SCALE;
  return m;
}

const char* StereoMatcher::disparity(const cv::Mat& left, const cv::Mat& right,
                                     cv::Mat& disparity) {
  if (left.empty() || right.empty()) return "empty stereo image";
  if (left.size() != right.size() || left.type() != right.type())
    return "left and right images differ in size or type";
  if (left.type() != CV_8UC3 && left.type() != CV_8UC1)
    return "stereo images must be 8-bit BGR or grey";
  const bool lr = params_.lr_check > 0.0;
  // OpenCV leaves the first num_disparities columns of the matched left view unmatched. Left
  // padding gives the left border disparities; for the mirrored match of the right view, whose
  // left border is the right image's right border, padding on the right does the same, so that
  // the check does not reject the left image's right border for want of a right disparity.
  // (Both sides are padded with either option, so that the left view's disparities do not
  // depend on whether the check runs.)
  const int pad = params_.pad_left ? params_.num_disparities : 0;
  const int pad_right = params_.pad_left || lr ? params_.num_disparities : 0;
  const cv::Mat* in[2] = {&left, &right};
  for (int i = 0; i < 2; ++i) {
    if (params_.grey && in[i]->channels() == 3) {
      cv::cvtColor(*in[i], grey_[i], cv::COLOR_BGR2GRAY);
      in[i] = &grey_[i];
    }
    if (pad > 0 || pad_right > 0) {
      cv::copyMakeBorder(*in[i], padded_[i], 0, 0, pad, pad_right, cv::BORDER_REPLICATE);
      in[i] = &padded_[i];
    }
  }
  sgbm_->compute(*in[0], *in[1], raw_left_);  // CV_16S, disparity * 16
  if (lr) {
    // the right image's disparities: match the mirrored pair (mirrored right as the left view)
    cv::flip(*in[1], flipped_[0], 1);
    cv::flip(*in[0], flipped_[1], 1);
    sgbm_->compute(flipped_[0], flipped_[1], raw_right_);
    cv::flip(raw_right_, raw_right_, 1);
  }
  const float scale = 1.f / cv::StereoMatcher::DISP_SCALE;
  const float tolerance = static_cast<float>(params_.lr_check);
  disparity.create(left.size(), CV_32FC1);
  for (int y = 0; y < left.rows; ++y) {
    const int16_t* dl = raw_left_.ptr<int16_t>(y);
    const int16_t* dr = lr ? raw_right_.ptr<int16_t>(y) : nullptr;
    float* out = disparity.ptr<float>(y);
    for (int x = 0; x < left.cols; ++x) {
      const int xp = x + pad;  // column in the (padded) matched images
      const float d = dl[xp] * scale;
      bool ok = dl[xp] >= 0;
      if (ok && lr) {
        // where the right camera sees this pixel: inside its image, not in the padding
        const int xr = cvRound(xp - d);
        ok = xr >= pad && dr[xr] >= 0 && std::fabs(dr[xr] * scale - d) <= tolerance;
      }
      out[x] = ok ? d : kNoMatch;
    }
  }
  return nullptr;
}

const char* StereoMatcher::depth(const cv::Mat& left, const cv::Mat& right, double focal,
                                 double baseline, cv::Mat& depth) {
  if (const char* problem = disparity(left, right, disparity_)) return problem;
  return disparityToDepth(disparity_, model(focal, baseline), depth);
}

}  // namespace tools
}  // namespace rgbd_lane_detector
