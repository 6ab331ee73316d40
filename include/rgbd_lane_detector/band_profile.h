/**
 * @file band_profile.h
 * @brief What one image row shows across a traced line: the grey profile, the road's brightness
 * and colour on both sides, and the bright bands near the line (paint, a rail head, a zebra
 * stripe) by their half-peak width; the centre of the bright band near a column; where the road
 * ends on a row (the boundary classifier's measurements, row by row).
 */
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/classifier_input.h"
#include "rgbd_lane_detector/params.h"

namespace rgbd_lane_detector {

/// A bright band of a row profile: half-peak edges (offsets from the line's column, sub-pixel).
struct Band {
  double lo = 0.0, hi = 0.0;
  float peak = 0.0f;
  bool open = false;  ///< reaches the end of the profile (width unknown)
};

/// What one image row across a line shows (BandProfile::measureRow()).
struct RowMeasure {
  int v = 0, u0 = 0, W = 0;       ///< row, the line's column, profile half width (px)
  int outer_dir = 1;              ///< image direction away from the vehicle
  double depth = 0.0, ppm = 0.0;  ///< the road's depth at the row, pixels per metre across
  float bg[2] = {0.f, 0.f};       ///< grey of the road beside the line: inner, outer
  float chroma[2][2] = {{0.f, 0.f}, {0.f, 0.f}};  ///< rg chromaticity of both sides
  /// the brighter side's grey, the contrast a band needs, the brightest grey near the line
  float top = 0.f, contrast = 0.f, peak = 0.f;
  float noise = 0.f;  ///< grey noise of the row: the robust sigma of the smoother side
  const Band* paint = nullptr;   ///< nearest band of paint width (where resolved)
  const Band* narrow = nullptr;  ///< nearest narrower band
  const Band* wide = nullptr;    ///< nearest wider band
};

/**
 * @brief Profiles of single image rows across a line. The bands a measureRow() points to live
 * until the next call. Reuses its buffers (no allocation in steady state).
 */
class BandProfile {
 public:
  /// Rows are measured where a pixel spans at most 1/kMinPixelsPerMetre m across the road, the
  /// band's width where it spans at most 1/kWidthPixelsPerMetre m.
  static constexpr double kMinPixelsPerMetre = 12.0;
  static constexpr double kWidthPixelsPerMetre = 25.0;
  static constexpr int kMaxProfileHalf = 160;  ///< px each side of the line at most (near rows)
  /// m from the line where the sides' backgrounds start, and where they end
  static constexpr double kSideNear = 0.22;
  static constexpr double kSideFar = 0.5;
  static constexpr float kMinContrast = 10.0f;  ///< grey levels: below this a band is sensor noise
  static constexpr int kMinRows = 3;            ///< rows a line's measurement needs at least
  static constexpr size_t kMaxMeasuredRows = 48;  ///< rows of a line a measurement reads at most
  /// m inside a road edge where the road's look is read (edgeInRow())
  static constexpr double kEdgeReference[2] = {0.7, 1.0};

  BandProfile();

  /**
   * @brief Profile of the row through @p c across the line: the backgrounds and colours of both
   * sides, the brightest pixel near the line and, where the pixels resolve widths, the nearest
   * bands of paint width, narrower and wider (widths across the line: times @p cos_heading).
   * Where a pixel spans a few millimetres of road, the profile is averaged over a centimetre and a
   * half (a line's texture is not its width).
   * @return false where the row is not measurable (off the road, too far, at the image border).
   */
  bool measureRow(const ClassifierInput& in, const cv::Point2f& c, bool left, const Params& p,
                  double cos_heading, RowMeasure& m);

  /**
   * @brief Centre of the bright band on row @p v within @p half px of column @p u (sub-pixel,
   * brightness-weighted over the band at half its contrast).
   * @p width (if given): the band's width at half its contrast (px).
   * @return false when no band stands out by the paint contrast or it is wider than @p max_px.
   */
  bool bandCentre(const ClassifierInput& in, int v, double u, int half, double max_px,
                  const Params& p, double& centre, int* width = nullptr);

  /**
   * @brief Where the road ends on row @p v (@p ppm pixels per metre across the road), scanning
   * outward from @p inside metres inside column @p u: the first stretch of 12 cm that is mostly
   * not road (brighter by the paint contrast, or of another colour by edge_chroma).
   */
  bool edgeInRow(const ClassifierInput& in, int v, double u, double ppm, bool left, const Params& p,
                 double inside, double& edge);

 private:
  /// Segment profile_ (centre index @p W) into bands above @p low over the background @p base;
  /// only the runs above @p low that may hold a band centred within @p reach px of the line.
  void findBands(int W, float base, float low, double reach);
  /// Append the band of profile offsets [a, b] (its peak and half-peak edges).
  void addBand(int a, int b, float base, bool open, int W);

  std::vector<float> profile_;
  std::vector<float> run_max_;        ///< findBands(): the highest grey to a run's end
  std::vector<uint8_t> grey_row_;     ///< grey of the columns a row's profile reads
  std::vector<int> prefix_;           ///< their running sum (measureRow()'s averaging boxes)
  std::vector<Band> bands_;
  std::vector<float> side_;           ///< grey values of a row's sides (medians)
  std::vector<float> dev_;            ///< their absolute deviations (the row's noise)
  std::vector<unsigned char> other_;  ///< edgeInRow(): pixels of a row that are not road
};

}  // namespace rgbd_lane_detector
