/**
 * @file classifier_input.h
 * @brief The frame the boundary classifier reads (views on the detector's images, the road
 * plane) and what it reads of it: the road under a pixel, the height of the depth above the road,
 * a line's heading on the road, one image row's grey values and colours.
 */
#pragma once

#include <cstdint>
#include <cstring>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/geometry.h"
#include "rgbd_lane_detector/half_binary.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/// The frame a classifier reads (views; nothing is copied).
struct ClassifierInput {
  const cv::Mat* colour = nullptr;  ///< input colour image
  PixelFormat format = PixelFormat::kBgr8;
  /// optional CV_8UC1 grey of the input image (greyValue() weights) in the rows @c grey_rows;
  /// without it the grey values are computed from the colour. The classifier measures nothing
  /// outside grey_rows.
  const cv::Mat* grey = nullptr;
  cv::Range grey_rows;
  Intrinsics K;                     ///< of the input image
  const cv::Mat* points = nullptr;  ///< CV_32FC3 organised points at the processing scale
  /// optional CV_8UC1 of the points' size: non-zero where a point is the road plane extended
  /// over missing depth, not a measurement (no height is read there)
  const cv::Mat* filled = nullptr;
  double scale_x = 1.0, scale_y = 1.0;   ///< processing / input resolution
  PlaneEstimate const* plane = nullptr;  ///< road plane (valid)
  RoadFrame frame;  ///< its road frame (REP-103: x forward, y left)

  /// The road under input pixel (u, v): its forward distance @p f in the road frame and the
  /// pixels per metre @p ppm across the road there; false where the pixel's ray does not meet it.
  bool roadAt(double u, double v, double& f, double& ppm) const;
  /// Height above the road of the depth at an input pixel: its own depth, else the nearest in
  /// its column within a few rows (sparse LiDAR rows); NaN without depth or on filled points.
  float heightAt(int u, int v) const;
  /// Depth point (optical frame) at an input pixel, NaN without depth.
  Eigen::Vector3f pointAt(int u, int v) const;
  /// cos of the heading on the road of a line of input pixels (near to far), from its first and
  /// last points on the road: at least 0.5, and 1 when they are less than 0.5 m apart.
  double cosHeading(const std::vector<cv::Point2f>& pixels) const;
};

/// One row of the input image: its grey values and its colours, read in place.
class ImageRow {
 public:
  /// Row @p v of @p in; valid() is false outside the grey image's rows.
  ImageRow(const ClassifierInput& in, int v) {
    if (v < in.grey_rows.start || v >= in.grey_rows.end || v < 0 || v >= in.colour->rows ||
        (in.grey && v >= in.grey->rows))
      return;
    grey_ = in.grey ? in.grey->ptr<uint8_t>(v) : nullptr;
    colour_ = in.colour->ptr<uint8_t>(v);
    cn_ = in.colour->channels();
    const PixelLayout layout = pixelLayout(in.format);
    r_ = layout.r, g_ = layout.g, b_ = layout.b;
    format_ = in.format;
    layout_channels_ = layout.channels;
  }
  bool valid() const { return colour_ != nullptr; }
  /// Grey value (BT.601 luma, greyValue()) at column @p u.
  float grey(int u) const {
    if (grey_) return grey_[u];
    const uint8_t* px = colour_ + static_cast<size_t>(u) * cn_;
    return cn_ == 1 ? px[0] : greyValue(px[r_], px[g_], px[b_]);
  }
  /// grey() of the @p n columns from @p u0 on, into @p out (the row's pixels converted at once:
  /// a profile reads a few hundred of them per row).
  void greyRun(int u0, int n, uint8_t* out) const {
    if (n <= 0) return;
    if (grey_) {
      std::memcpy(out, grey_ + u0, static_cast<size_t>(n));
    } else if (cn_ == 1) {
      std::memcpy(out, colour_ + u0, static_cast<size_t>(n));
    } else if (cn_ == layout_channels_) {
      greyPixels(colour_ + static_cast<size_t>(u0) * cn_, format_, n, out);
    } else {
      for (int i = 0; i < n; ++i) out[i] = static_cast<uint8_t>(grey(u0 + i));
    }
  }
  /// Colour at column @p u (0-255).
  void rgb(int u, float& R, float& G, float& B) const {
    const uint8_t* px = colour_ + static_cast<size_t>(u) * cn_;
    R = px[r_], G = px[g_], B = px[b_];
  }
  /// Sums of the red, green and blue of the @p n columns from @p u0 on (0-255 each).
  void rgbSums(int u0, int n, int& R, int& G, int& B) const {
    const uint8_t* px = colour_ + static_cast<size_t>(u0) * cn_;
    if (cn_ == 3 && r_ < 3 && g_ < 3 && b_ < 3) {  // (3 channels: each slot's sum, then named)
      int s[3] = {0, 0, 0};
      for (int i = 0; i < n; ++i, px += 3) s[0] += px[0], s[1] += px[1], s[2] += px[2];
      R = s[r_], G = s[g_], B = s[b_];
      return;
    }
    const int cn = cn_, r = r_, g = g_, b = b_;
    int sr = 0, sg = 0, sb = 0;
    for (int i = 0; i < n; ++i, px += cn) sr += px[r], sg += px[g], sb += px[b];
    R = sr, G = sg, B = sb;
  }
  /// rg chromaticity at column @p u.
  void chroma(int u, float& r, float& g) const {
    float R, G, B;
    rgb(u, R, G, B);
    const float sum = R + G + B + 1e-3f;
    r = R / sum;
    g = G / sum;
  }

 private:
  const uint8_t* grey_ = nullptr;
  const uint8_t* colour_ = nullptr;
  int cn_ = 1, r_ = 0, g_ = 0, b_ = 0;
  PixelFormat format_ = PixelFormat::kBgr8;
  int layout_channels_ = 3;
};

}  // namespace rgbd_lane_detector
