/**
 * @file road_edge_finder.h
 * @brief Road edges from depth (improved mode): where the road surface ends in a height step on
 * either side of the vehicle (a kerb and the sidewalk behind it), whatever it looks like.
 *
 * The line templates find a kerb only where its top looks like a painted line; at another
 * resolution, exposure or kerb stone it may not be matched at all. Depth sees the step itself.
 * On each image row of the near road, scanning outward from the camera's column, the edge is
 * the first place where the surface rises from the road by at least the kerb height and stays
 * raised at a sidewalk's height, with a level top (a car's side rises higher, a vehicle's rear
 * face is vertical: no edge on that row). A rise spread over up to 0.6 m (a rolled, mountable
 * kerb; a verge beyond a gutter), which a step between neighbouring points never shows, ends
 * the road at its foot: where the surface starts to rise. The edges of
 * the rows that line up along the road (a robust straight line in road coordinates over several
 * metres) are one side's road edge candidate, handed to the classifier and the lane fit like a
 * traced line.
 */
#pragma once

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/geometry.h"
#include "rgbd_lane_detector/lane_tracker.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/// Settings of the road edge search (from Params and the frame's geometry).
struct RoadEdgeSettings {
  double kerb_height = 0.05;  ///< a step at least this high ends the road (m)
  double max_step =
      0.35;  ///< a surface higher than this beyond it is an object, not a sidewalk (m)
  double offset_min = 0.15;            ///< a road edge lies at least this far beside the camera (m)
  double offset_max = 4.5;             ///< ... and at most this far
  double max_range = 25.0;             ///< rows whose road is farther ahead are not searched (m)
  double min_pixels_per_metre = 12.0;  ///< rows coarser than this are not searched (input px)
  int normal_window = 5;  ///< FALS window of the normal that tells a level sidewalk (px)
};

/// One side's road edge found in the depth: input-image pixels and their depth points.
struct RoadEdgeLine {
  bool found = false;
  std::vector<cv::Point2f> pixels;      ///< input image, near to far
  std::vector<Eigen::Vector3f> points;  ///< optical frame (the step's foot on the road plane)
  double offset = 0.0;                  ///< lateral offset at the camera (m, + left)
  double heading = 0.0;                 ///< direction in the road plane (rad, + toward the left)
};

/**
 * @brief Finds the road edges of both sides in an organised point matrix. No allocation in
 * steady state.
 */
class RoadEdgeFinder {
 public:
  /// A measured point of a searched row: its distance beside the camera (m), its height above
  /// the plane (m), its column.
  struct RowSample {
    float lateral;
    float height;
    int x;
  };

  /**
   * @brief Search both sides.
   * @param[in] points CV_32FC3 organised points at the processing scale (NaN: no depth).
   * @param[in] filled optional CV_8UC1 mask of points that are the road plane extended over
   *            missing depth (no measurement: skipped); may be null.
   * @param[in] rows rows of @p points to search.
   * @param[in] K intrinsics of the input image.
   * @param[in] col_map,row_map source column / row of each processing column / row (empty:
   *            the points are at the input resolution).
   * @param[in] plane road plane (valid).
   * @param[in] s settings.
   * @param[out] left,right each side's edge (found false: none).
   */
  void find(const cv::Mat& points, const cv::Mat* filled, const cv::Range& rows,
            const Intrinsics& K, const cv::Mat& col_map, const cv::Mat& row_map,
            const PlaneEstimate& plane, const RoadEdgeSettings& s, RoadEdgeLine& left,
            RoadEdgeLine& right);

 private:
  /// One row's edge of one side: its foot in road coordinates.
  struct RowEdge {
    Eigen::Vector2d road;  ///< (forward, lateral): RoadFrame x, y
  };
  /// The side's edge: the rows' edges on a robust straight line along the road.
  void fitSide(const std::vector<RowEdge>& edges, const Intrinsics& K, const RoadFrame& frame,
               const RoadEdgeSettings& s, bool left, RoadEdgeLine& out);

  std::vector<RowEdge> edges_[2];
  std::vector<RowSample> samples_;  ///< one side of the row being searched
  std::vector<Eigen::Vector2d> road_;
  std::vector<int> inliers_;
};

}  // namespace rgbd_lane_detector
