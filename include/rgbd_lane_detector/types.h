/**
 * @file types.h
 * @brief Plain input and output types of the ROS-free detector core.
 */
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

namespace rgbd_lane_detector {

/**
 * @brief Pinhole intrinsics of the (rectified) colour camera, in pixels: the one place where
 * pixels and optical-frame rays meet (x right, y down, z forward).
 */
struct Intrinsics {
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;
  /// Finite, positive focal lengths and finite principal point.
  bool valid() const;
  /// The ray through pixel (u, v), scaled to z = 1 (so a point at depth z is z * ray).
  Eigen::Vector3d ray(double u, double v) const {
    return Eigen::Vector3d((u - cx) / fx, (v - cy) / fy, 1.0);
  }
  /// Pixel of an optical-frame point in front of the camera (p.z() > 0), in double.
  template <typename Derived>
  cv::Point2d project(const Eigen::MatrixBase<Derived>& p) const {
    return cv::Point2d(fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy);
  }
  bool operator==(const Intrinsics& o) const {
    return fx == o.fx && fy == o.fy && cx == o.cx && cy == o.cy;
  }
  bool operator!=(const Intrinsics& o) const { return !(*this == o); }
};

/// Channel layout of the colour image (the ROS encodings the core reads in place).
enum class PixelFormat { kBgr8, kRgb8, kBgra8, kRgba8, kMono8 };

/// What a pixel format is, written once: channels, and the byte of red, green and blue in a pixel
/// (all 0 for mono).
struct PixelLayout {
  int channels;
  int r, g, b;
};

/// The layout of @p format.
constexpr PixelLayout pixelLayout(PixelFormat format) {
  switch (format) {
    case PixelFormat::kBgr8:
      return {3, 2, 1, 0};
    case PixelFormat::kRgb8:
      return {3, 0, 1, 2};
    case PixelFormat::kBgra8:
      return {4, 2, 1, 0};
    case PixelFormat::kRgba8:
      return {4, 0, 1, 2};
    case PixelFormat::kMono8:
      return {1, 0, 0, 0};
  }
  return {0, 0, 0, 0};
}

/**
 * @brief One RGB-D frame. The core only reads the images (no copy when the
 * processing scale is 1); they must stay alive during detect().
 */
struct Frame {
  cv::Mat colour;                       ///< CV_8UC3 (bgr8/rgb8), CV_8UC4 (bgra8/rgba8) or CV_8UC1
  PixelFormat format = PixelFormat::kBgr8;
  cv::Mat depth;                        ///< CV_16UC1 (depth_scale metres per unit) or CV_32FC1 metres
  double depth_scale = 0.001;           ///< metres per unit of a CV_16UC1 depth image
  Intrinsics intrinsics;                ///< of the colour camera; depth is registered to it
  /// Pose of the colour optical frame in the vehicle frame (base_link, REP-103) for the lane
  /// model; without it the road-aligned frame under the camera is used (RoadFrame).
  bool has_vehicle_frame = false;
  Eigen::Isometry3d vehicle_from_camera = Eigen::Isometry3d::Identity();
};

/// Outcome of LaneDetector::detect(). Anything but kOk means the frame was not processed.
enum class Status {
  kOk = 0,
  kEmptyImage,            ///< colour or depth has no pixels
  kSizeMismatch,          ///< colour and depth differ in size
  kUnsupportedColour,     ///< colour type does not match the pixel format or is not 8-bit
  kUnsupportedDepth,      ///< depth is neither CV_16UC1 nor CV_32FC1, or the 16-bit scale is not > 0
  kInvalidIntrinsics,     ///< zero, negative or non-finite focal length / principal point
  kImageTooSmall,         ///< the searched region is smaller than the template
};

/// A static, human-readable description of a status (never allocates).
const char* statusMessage(Status status);

/// Lane plane n . p + d = 0 in the camera optical frame, n pointing toward the camera.
struct PlaneEstimate {
  bool valid = false;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double distance = 0.0;                       ///< d; the camera height above the road when valid
  std::vector<Eigen::Vector3f> support;        ///< points the plane was fitted to
  double rms = 0.0;                            ///< RMS distance of the support points (m)
  double range = 0.0;                          ///< the road is this plane up to this far ahead (m); 0: unknown
  int fit_method = 0;                          ///< PlaneFit value used
};

/**
 * @brief What a lane boundary is. Paint lies flat on the road surface (within a few centimetres)
 * and is brighter than the asphalt beside it; a road edge is a height step (kerb, guard-rail
 * foot) or a change of surface (rails, grass, an unpainted asphalt edge).
 */
enum class BoundaryKind : int {
  kPaint = 0,     ///< a painted line on the road
  kRoadEdge = 1,  ///< the edge of the drivable surface without paint
};

/// "paint" or "road_edge" (static text).
const char* boundaryKindName(BoundaryKind kind);

/// One traced lane boundary (left or right side of the ego lane).
struct MarkerTrace {
  bool found = false;                 ///< reported this frame (enough traced points, checks passed)
  BoundaryKind kind = BoundaryKind::kPaint;  ///< meaningful when found
  float confidence = 0.0f;            ///< in [0, 1]: how sure the detector is of this side (0: not found)
  float paint_coverage = -1.0f;       ///< share of the boundary's seen length with paint (solid ~1, dashed ~0.25-0.5; < 0 unknown)
  float yellowness = -1.0f;           ///< yellow vs white evidence of its paint (white ~0, yellow >= 0.3; < 0 unknown)
  float peak_score = 0.0f;            ///< R at the seed (best match)
  cv::Point2f seed{-1.f, -1.f};       ///< best match, input-image pixel coordinates
  Eigen::Vector3f seed_point{0.f, 0.f, 0.f};  ///< 3D point of the best match (NaN: no depth)
  double angle = 0.0;                 ///< image angle (rad) from PCA, atan2(dv, du), dv > 0
  bool angle_valid = false;           ///< PCA found enough pixels above P_PCA
  std::vector<cv::Point2f> pixels;    ///< box centroids, input-image pixels, ordered near to far
  std::vector<float> scores;          ///< R at each centroid
  std::vector<Eigen::Vector3f> points;///< 3D centroids (optical frame, m); NaN where no depth
  int num_valid_points = 0;           ///< points with finite coordinates
  /// This frame's own measurement of a tracked side (the chosen line's road points, optical
  /// frame), before the lane tracker smooths it over frames into @ref points; empty when the
  /// tracker carries the side without evidence this frame, and without tracking. The lane model
  /// (LaneModelFilter) is updated from it: a smoothed input would lag a turning vehicle.
  std::vector<Eigen::Vector3f> measured;
};

// --- The lane model for planners (LaneModelFilter, lane_model.h) -----------------------------
// Vehicle frame (REP-103): x forward, y left, z up.

/// Position of a boundary relative to the vehicle's current lane.
enum class BoundaryPosition : int {
  kEgoLeft = 0,
  kEgoRight = 1,
  kNextLeft = 2,
  kNextRight = 3,
  kRoadEdgeLeft = 4,
  kRoadEdgeRight = 5,
};
constexpr int kNumBoundaryPositions = 6;

/// What a boundary looks like along its length.
enum class LineKind : int { kUnknown = 0, kSolid = 1, kDashed = 2, kRoadEdge = 3 };

/// Colour of a painted boundary.
enum class LineColour : int { kUnknown = 0, kWhite = 1, kYellow = 2 };

/// "ego_left", ... (static text).
const char* boundaryPositionName(BoundaryPosition p);
/// "unknown", "solid", "dashed", "road_edge" (static text).
const char* lineKindName(LineKind k);
/// "unknown", "white", "yellow" (static text).
const char* lineColourName(LineColour c);

/// One boundary of the lane model.
struct LaneBoundaryModel {
  bool valid = false;
  BoundaryPosition position = BoundaryPosition::kEgoLeft;
  LineKind kind = LineKind::kUnknown;
  LineColour colour = LineColour::kUnknown;
  std::array<double, 4> c{{0.0, 0.0, 0.0, 0.0}};  ///< y(x) = c0 + c1 x + c2 x^2 + c3 x^3
  double x_min = 0.0, x_max = 0.0;  ///< range of x over which it is known (m, LaneBoundary.msg)
  float confidence = 0.0f;          ///< estimate of P(this boundary is right), [0, 1]: evidence calibrated
  float evidence = 0.0f;            ///< uncalibrated evidence score in [0, 1] (calibratedConfidence())
  int age = 0;                      ///< frames since it was last measured (0: this frame)
  float lateral_std = 0.0f;         ///< standard deviation of y at x_max, the largest over the range (m)
  /// y at x.
  double lateral(double x) const { return c[0] + x * (c[1] + x * (c[2] + x * c[3])); }
};

/// The lane model of one frame.
struct LaneModelEstimate {
  bool valid = false;  ///< an ego lane is known (at least one ego boundary)
  std::array<LaneBoundaryModel, kNumBoundaryPositions> boundaries;  ///< indexed by position
  double width = 0.0;          ///< ego lane width at x = 0 (m)
  double offset = 0.0;         ///< the vehicle's lateral position relative to the lane centre (m, + left)
  double heading_error = 0.0;  ///< the vehicle's heading relative to the lane (rad, + pointing left of it)
  double curvature = 0.0;      ///< of the lane centre at x = 0 (1/m, + turning left)
  double curvature_rate = 0.0; ///< d curvature / dx (1/m^2)
  double x_min = 0.0, x_max = 0.0;  ///< range of the centre line (m)
  std::array<double, 4> centre{{0.0, 0.0, 0.0, 0.0}};  ///< the centre line's cubic y(x)
  int lane_changes = 0;        ///< lane changes since the last reset (+1 to the left, -1 to the right)
  /// The boundary at @p p.
  const LaneBoundaryModel& at(BoundaryPosition p) const { return boundaries[static_cast<int>(p)]; }
};

/// Index of Result::outer.
enum OuterBoundary : int { kNextLeft = 0, kNextRight = 1, kRoadEdgeLeft = 2, kRoadEdgeRight = 3 };

/// Wall-clock time of each stage of the last detect() call, milliseconds.
struct StageTimings {
  double preprocess = 0.0;   ///< resampling and half-binary image
  double points = 0.0;       ///< depth to organised 3D points
  double normals = 0.0;      ///< FALS normals and G (and where G enters R, fusionMask())
  double matching = 0.0;     ///< NCC with both templates (and the acquisition templates)
  double response = 0.0;     ///< plane gate and the fused R maps
  double road = 0.0;         ///< road surface from depth (improved mode)
  double pca = 0.0;          ///< seeds and template angle refinement
  double tracing = 0.0;      ///< sliding-box tracing of every candidate line
  double classify = 0.0;     ///< candidate classification (paint, road edge, no boundary)
  double plane = 0.0;        ///< lane plane and boundary fit
  double model = 0.0;        ///< paint measurements and the lane model
  double total = 0.0;

  /// Field by field sum (accumulating frames, e.g. for a mean per stage).
  StageTimings& operator+=(const StageTimings& o) {
    preprocess += o.preprocess;
    points += o.points;
    normals += o.normals;
    matching += o.matching;
    response += o.response;
    road += o.road;
    pca += o.pca;
    tracing += o.tracing;
    classify += o.classify;
    plane += o.plane;
    model += o.model;
    total += o.total;
    return *this;
  }
};

/**
 * @brief Everything one detect() call produces. Reuse one Result across frames:
 * its vectors keep their capacity, so steady-state detection does not allocate.
 * The cv::Mat members are headers onto the detector's internal buffers at the
 * processing resolution (0 outside the searched rows); they stay valid until
 * the next detect() or reset() call on the same detector.
 */
struct Result {
  Status status = Status::kOk;
  cv::Mat response_left;    ///< R of the left ("/") template, CV_32FC1
  cv::Mat response_right;   ///< R of the right ("\") template, CV_32FC1
  /// G, CV_32FC1: where it enters R (M >= tau_G) and 0 elsewhere, or everywhere with
  /// LaneDetector::setFullGeometricMap(true)
  cv::Mat geometric;
  cv::Mat half_binary;      ///< half-binary grey image, CV_8UC1
  cv::Rect roi;             ///< searched rows at the processing resolution
  double scale = 1.0;       ///< processing resolution / input resolution
  MarkerTrace left;
  MarkerTrace right;
  /// Boundaries beyond the ego lane's seen this frame (improved mode; found = seen), indexed by
  /// OuterBoundary: the next lanes' far lines and the road edges. Points on the road plane.
  std::array<MarkerTrace, 4> outer;
  PlaneEstimate plane;
  /// The tracked lane model in the vehicle frame (improved mode, lane_model option).
  LaneModelEstimate lane_model;
  double template_angle_left = 0.0;   ///< template angle (rad) used for this frame
  double template_angle_right = 0.0;
  StageTimings timings;
};

}  // namespace rgbd_lane_detector
