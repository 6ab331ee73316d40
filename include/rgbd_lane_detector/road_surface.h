/**
 * @file road_surface.h
 * @brief The road surface from depth: a robust plane fitted every frame to the depth of the
 * searched rows, markers or not (the improved mode; the paper fits its plane to three marker
 * points, lane_plane.h).
 *
 * Real roads are not one plane (crests, sags, camber). The plane is fitted to the depth within
 * RoadSurfaceSettings::fit_range ahead of the camera, where one plane holds for any road a
 * vehicle drives on, and the range over which it holds is measured beyond that: the distance at
 * which the road's depth first leaves the plane by more than the inlier band (validRange()).
 * Marker pixels are placed on the plane only within that range. The range check looks at the
 * most frequent height of the depth ahead of the camera in 5 m steps: the plane holds while
 * that stays within 8 cm of it (and can be told: a noisy depth sensor ends it, too).
 */
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/// Settings of the road surface fit (filled from Params by the detector).
struct RoadSurfaceSettings {
  Eigen::Vector3d up = Eigen::Vector3d(0.0, -1.0, 0.0);  ///< road up axis, optical frame
  double max_tilt_deg = 30.0;   ///< largest angle between the plane normal and @c up
  /// Height of the camera above the road from its mount (the vehicle frame's tf: its origin on
  /// the road), m; with it the fit starts from the mount's plane (normal @c up); 0 = unknown.
  double mount_height = 0.0;
  double height_min = 0.3;      ///< camera height above the road, lower bound (m)
  double height_max = 5.0;      ///< upper bound (m)
  double fit_range = 20.0;      ///< points up to this distance ahead fit the plane (m)
  double inlier_distance = 0.04;  ///< residual bound of an inlier at the camera (m)
  double noise_growth = 0.0015;   ///< the bound grows by at most this times z^2 (depth noise, 1/m);
                                  ///< the fit measures the depth's own growth and uses that
  double max_range = 80.0;      ///< farthest depth looked at for the valid range (m)
  int target_samples = 1500;    ///< depth samples drawn from the searched rows (grid; finer where
                                ///< the depth is sparse: at least half as many near samples)
  /// Columns of the points whose pixels can lie in the corridor ahead beyond fit_range (from
  /// the intrinsics); every column when empty.
  cv::Range far_columns;
};

/**
 * @brief Robust road plane from an organised point matrix.
 *
 * Samples the points of the searched rows on a regular grid. When the previous frame's plane is
 * given, the samples within a wide band of it are refitted (iteratively reweighted least
 * squares, Tukey weights); when that fails, or without a previous plane, RANSAC over the near
 * samples (deterministic sequence, hypotheses must be road-like: tilt and height bounds) finds
 * the plane, then the same refit. Samples in the central corridor ahead of the camera weigh
 * more: the road lies ahead, sidewalks and cars to the sides. No allocation once the sample
 * buffers have grown.
 */
class RoadSurface {
 public:
  /**
   * @brief Fit the road plane.
   * @param[in] points CV_32FC3 organised points (optical frame, NaN = no depth).
   * @param[in] rows rows of @p points that show the road (the searched rows).
   * @param[in] settings fit settings.
   * @param[in] previous previous frame's road plane (invalid: none).
   * @param[out] plane the plane (support = a subsample of its inliers, rms their residual);
   *             invalid when the depth shows no road.
   * @return plane.valid.
   */
  bool fit(const cv::Mat& points, const cv::Range& rows, const RoadSurfaceSettings& settings,
           const PlaneEstimate& previous, PlaneEstimate& plane);

  /**
   * @brief Extend the road surface toward the camera where depth is missing (LiDAR and stereo
   * often see nothing in the bottom rows): in every column, below the nearest pixel whose depth
   * lies on the road plane (within @p band0 + @p growth z^2), the pixels without depth get the
   * point where their ray meets the plane. A column whose nearest depth is not road (a car, a
   * wall) or that has no depth at all is left as it is: only a road seen to continue is extended.
   * @param[in,out] points CV_32FC3 organised points.
   * @param[in] rows rows to process.
   * @param[in] K intrinsics of the depth image the points come from.
   * @param[in] plane road plane (valid), n . p + d = 0, optical frame.
   * @param[in] band0,growth inlier band of the plane at depth z: band0 + growth z^2 (m).
   * @param[out] filled CV_8UC1 of the points' size, 255 where a point was filled, 0 elsewhere
   *             (allocated when its size differs); a filled point is no measurement of height.
   * @param[in] col_map,row_map optional: source column / row of each output column / row (see
   *            depthToPoints()).
   * @return pixels filled.
   */
  int extendToCamera(cv::Mat& points, const cv::Range& rows, const Intrinsics& K,
                       const PlaneEstimate& plane, double band0, double growth, cv::Mat& filled,
                       const cv::Mat& col_map = cv::Mat(), const cv::Mat& row_map = cv::Mat());

  /**
   * @brief The depthBlocks() map of the points the next fit() and extendToCamera() get (null:
   * none): their scans pass over the blocks without depth instead of reading every point. Kept
   * by pointer; the caller keeps it equal to the points (a map of another size is not used).
   */
  void setDepthBlocks(const cv::Mat* blocks) { blocks_ = blocks; }

  /// Half width of the corridor ahead of the camera whose samples weigh more (m).
  static constexpr double kCorridorHalfWidth = 2.5;

  /**
   * @brief Columns that can show the corridor beyond @p fit_range (for
   * RoadSurfaceSettings::far_columns).
   * @param[in] fx,cx focal length and principal point of the points' pixel grid (px).
   * @param[in] fit_range the fit's range (m).
   * @return columns [start, end) with a pixel of margin either side.
   */
  static cv::Range corridorColumns(double fx, double cx, double fit_range);

  /// Distance ahead (m, along the optical axis) up to which the last plane holds.
  double validRange() const { return valid_range_; }
  /// Inlier samples of the last fit (of those within fit_range).
  int inliers() const { return inliers_; }
  /// Inlier band (m) of the last fit at depth @p z.
  double bandAt(const RoadSurfaceSettings& s, double z) const {
    return s.inlier_distance + growth_ * z * z;
  }
  /// Growth of the inlier band with z^2 measured on the last frame's depth (1/m).
  double noiseGrowth() const { return growth_; }

 private:
  /// The tests' look at the grid's samples and their counts (test_road_surface.cpp).
  friend struct RoadSurfaceProbe;

  void collect(const cv::Mat& points, const cv::Range& rows, const RoadSurfaceSettings& s);
  /// near_ and far_ from every @p stride-th pixel of every stride-th row (and the corridor);
  /// its sampling rules (GridRules, road_surface.cpp) are the counts' below.
  void collectGrid(const cv::Mat& points, const cv::Range& rows, const RoadSurfaceSettings& s,
                   int stride);
  /// The samples within fit_range collectGrid() would find on the grid of @p stride.
  int nearGridCount(const cv::Mat& points, const cv::Range& rows, const RoadSurfaceSettings& s,
                    int stride) const;
  /// The near samples collectGrid() would find on the grid of @p stride where fewer than
  /// kMinSamples lie within fit_range (its far samples within twice fit_range join them),
  /// counted, not collected: the corridor's pixels are counted once for every stride in
  /// @p corridor (-1: not yet), the grid's own then taken off.
  int extendedGridCount(const cv::Mat& points, const cv::Range& rows, const RoadSurfaceSettings& s,
                        int stride, int& corridor) const;
  bool plausible(const Eigen::Vector3d& n, double d, const RoadSurfaceSettings& s) const;
  /// Weighted count of the near samples within the band of (n, d); @p below (optional) gets
  /// the weight of those more than two bands below it (beyond the road, seen from the camera).
  double score(const Eigen::Vector3d& n, double d, const RoadSurfaceSettings& s,
               double* below = nullptr) const;
  bool ransac(const RoadSurfaceSettings& s, Eigen::Vector3d& n, double& d);
  /// IRLS refit of (n, d) on the near samples within @p first_band times the band.
  bool refine(const RoadSurfaceSettings& s, double first_band, Eigen::Vector3d& n, double& d);
  void measureValidRange(const RoadSurfaceSettings& s, const Eigen::Vector3d& n, double d);
  /// The band's growth with z^2 from the residuals of (n, d): three robust sigmas per z^2.
  void estimateNoise(const RoadSurfaceSettings& s, const Eigen::Vector3d& n, double d);

  struct Sample {
    Eigen::Vector3f p;
    float weight;  ///< corridor weight
  };
  std::vector<Sample> near_;  ///< samples within fit_range
  std::vector<Sample> far_;   ///< samples beyond fit_range (valid range check)
  std::vector<float> ratios_;
  std::vector<int> fill_from_;  ///< extendToCamera(): per column, the first row to fill
  /// Row @p y of the depth block map when it fits @p points, else null.
  const uint8_t* blockRow(const cv::Mat& points, int y) const;

  const cv::Mat* blocks_ = nullptr;  ///< setDepthBlocks()
  std::vector<int> fill_open_;  ///< extendToCamera(): per depth block, its columns without depth so far
  std::vector<double> fill_rx_; ///< extendToCamera(): per column, the x of its rays and nx x
  /// extendToCamera(): per row filled, the first column that fills and one past the last
  std::vector<int> fill_span_;
  double near_end_ = 0.0;     ///< farthest corridor depth within fit_range off the grid (m)
  double growth_ = 0.0;
  uint32_t rng_ = 1;
  double valid_range_ = 0.0;
  int inliers_ = 0;
};

}  // namespace rgbd_lane_detector
