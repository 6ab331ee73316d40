/**
 * @file real_labels.h
 * @brief Hand labels of the real frames of ../shared/realdata (test/data/realdata_labels.yaml)
 * and the scoring of a detection against them.
 *
 * A label gives, per side of the ego lane, the boundary's kind (paint or road edge) and its
 * centre line as an image polyline; a frame without a lane (lane: 0) has none. The polyline is
 * placed on a reference road plane (fitted to the frame's LiDAR depth) by meeting each point's
 * ray with it. A reported side is right when it has at least 5 points, at least 80% of them
 * within 0.30 m laterally (in the reference plane) of the labelled line of its side, and its kind
 * is the labelled kind; anything else reported is wrong (a kerb or rail reported as paint, a
 * side reported where the label has none, a side off its line). A labelled side not reported is
 * missed.
 */
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {
namespace tools {

/// One labelled side.
struct LabelledSide {
  bool present = false;                ///< the side has a boundary
  BoundaryKind kind = BoundaryKind::kPaint;
  rgbd_lane_detector::LineKind style = rgbd_lane_detector::LineKind::kUnknown;        ///< paint: kSolid or kDashed (kUnknown: not labelled)
  rgbd_lane_detector::LineColour colour = rgbd_lane_detector::LineColour::kUnknown;   ///< paint: kWhite or kYellow (kUnknown: not labelled)
  std::vector<cv::Point2d> points;     ///< image polyline (left colour image pixels), near to far
};

/// One labelled frame.
struct LabelledFrame {
  std::string dataset;  ///< folder name under the real-data root (kitti2015, tum_office, ...)
  std::string frame;    ///< frame name as the dataset reader names it (000000_10, 1, ...)
  bool lane = false;    ///< the frame shows a lane (false: every reported side is wrong)
  bool key = false;     ///< a key frame of a sequence (frames between keys are interpolated)
  LabelledSide left, right;
};

/**
 * @brief Read a label file.
 * @return false with @p error when the file is missing or malformed (unknown kind, odd number of
 *         coordinates, a lane frame without sides).
 */
bool readRealLabels(const std::string& path, std::vector<LabelledFrame>& labels,
                    std::string& error);

/// The label of @p dataset / @p frame, or null.
const LabelledFrame* findRealLabel(const std::vector<LabelledFrame>& labels,
                                   const std::string& dataset, const std::string& frame);

/**
 * @brief The label of @p frame: its own, or for a numbered frame between two key frames of
 * @p dataset (key: 1) the two keys interpolated linearly per image row.
 *
 * A side is interpolated on the rows both keys cover (each key's polyline read at the rows of
 * both); a side labelled in one key and not in the other takes the nearer key's. Frames outside
 * the key range, or of a dataset without key frames, have no label.
 * @return false when there is none.
 */
bool realLabelOf(const std::vector<LabelledFrame>& labels, const std::string& dataset,
                 const std::string& frame, LabelledFrame& label);

/// x of an image polyline at row @p y (linear between its points); NaN outside its rows.
double polylineXAt(const std::vector<cv::Point2d>& line, double y);

/**
 * @brief Points given in the pixels of a raw (distorted) image moved to the undistorted pinhole
 * image of @p K (cv::undistortPoints); no-op for an empty @p distortion.
 */
void undistortLabel(const Intrinsics& K, const cv::Mat& distortion, LabelledFrame& label);

/**
 * @brief A labelled image polyline on a road plane: each point's ray met with the plane.
 * @param[in] side labelled side.
 * @param[in] K intrinsics of the labelled image.
 * @param[in] normal,distance the plane n . p + d = 0 (optical frame, n toward the camera).
 * @param[out] line 3D points (cleared first; points above the horizon are skipped).
 */
void labelOnPlane(const LabelledSide& side, const Intrinsics& K, const Eigen::Vector3d& normal,
                  double distance, std::vector<Eigen::Vector3d>& line);

/// How one reported or labelled side fared.
struct RealSideScore {
  rgbd_lane_detector::LineKind reported_style = rgbd_lane_detector::LineKind::kUnknown;      ///< paint: solid or dashed as reported
  rgbd_lane_detector::LineColour reported_colour = rgbd_lane_detector::LineColour::kUnknown; ///< paint: white or yellow as reported
  bool labelled = false;    ///< the label has this side
  bool reported = false;    ///< the detector reports it
  BoundaryKind reported_kind = BoundaryKind::kPaint;
  int points = 0;           ///< finite reported points
  int inliers = 0;          ///< of those within max_lateral of the labelled line
  double fraction = 0.0;    ///< inliers / points
  bool on_line = false;     ///< >= min_points and >= min_fraction within max_lateral
  bool correct = false;     ///< reported, on its line, of the labelled kind
  bool wrong = false;       ///< reported and not correct
  bool missed = false;      ///< labelled and not reported
  /// correct paint with a labelled style / colour: whether the reported one is the labelled one
  /// (-1: not scored)
  int style_right = -1, colour_right = -1;
};

/// Score of one real frame.
struct RealFrameScore {
  RealSideScore left, right;
  bool wrong = false;    ///< any side wrong
  bool complete = false; ///< every labelled side correct and nothing wrong (no lane: nothing reported)
};

/// Thresholds of the real-data rule (the values).
struct RealScoringRules {
  int min_points = 5;
  double min_fraction = 0.8;
  double max_lateral = 0.30;
  /// a trace's paint coverage below this is dashed, its yellowness at or above this yellow (the
  /// detector's Params::dashed_coverage and yellow_threshold)
  double dashed_coverage = 0.7;
  double yellowness = 0.25;
};

/**
 * @brief Score a detection against a label.
 * @param[in] result detector output (points in the optical frame of the labelled image).
 * @param[in] label the frame's label.
 * @param[in] K intrinsics of the image.
 * @param[in] normal,distance reference road plane (from LiDAR) for placing the labels; ignored
 *            for a frame without a lane.
 */
RealFrameScore scoreRealFrame(const Result& result, const LabelledFrame& label, const Intrinsics& K,
                              const Eigen::Vector3d& normal, double distance,
                              const RealScoringRules& rules = RealScoringRules());

}  // namespace tools
}  // namespace rgbd_lane_detector
