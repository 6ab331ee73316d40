/**
 * @file conversions.h
 * @brief Every conversion between ROS messages and the ROS-free core (the only place that
 * knows both): input images and camera_info to a core Frame (read in place), stereo disparity
 * images to the core's disparity model, core results to
 * the output messages, dynamic_reconfigure Config to core Params, tf transforms to Eigen.
 *
 * Functions that can fail return a static, human-readable description of the problem
 * (nullptr on success), in the spirit of the core's statusMessage(): nothing is allocated on
 * the error path.
 */
#pragma once

#include <string>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <rgbd_lane_detector/LaneDetectorConfig.h>
#include <rgbd_lane_detector/LaneMarkings.h>
#include <rgbd_lane_detector/LaneModel.h>
#include <rgbd_lane_detector/LanePlane.h>
#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>
#include <stereo_msgs/DisparityImage.h>
#include <visualization_msgs/MarkerArray.h>

#include "rgbd_lane_detector/disparity_depth.h"
#include "rgbd_lane_detector/lane_grid.h"
#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {
namespace conversions {

// ---------------------------------------------------------------------------
// Inputs

/**
 * @brief Channel layout of a colour encoding.
 * @param[in] encoding sensor_msgs/Image encoding.
 * @param[out] format matching core layout (unchanged when unsupported).
 * @return false unless the encoding is rgb8, bgr8, rgba8, bgra8 or mono8.
 */
bool pixelFormatFromEncoding(const std::string& encoding, PixelFormat& format);

/**
 * @brief Colour image as a cv::Mat header on the message's data (no copy; rows by msg.step).
 * An image with no pixels gives an empty Mat (the core reports Status::kEmptyImage).
 * @param[in] msg colour image; must outlive @p colour.
 * @param[out] colour header onto msg.data.
 * @param[out] format its channel layout.
 * @return nullptr on success, else a static description of the problem.
 */
const char* colourFromMsg(const sensor_msgs::Image& msg, cv::Mat& colour, PixelFormat& format);

/**
 * @brief Depth image (REP-118: 16UC1 millimetres or 32FC1 metres) as a cv::Mat header on the
 * message's data. Only a depth image whose byte order differs from the host's is copied
 * (byte-swapped into @p swap_buffer, reused across frames).
 * @param[in] msg depth image; must outlive @p depth.
 * @param[out] depth CV_16UC1 or CV_32FC1 header.
 * @param[out] depth_scale metres per unit (0.001 for 16UC1, 1 for 32FC1).
 * @param[in,out] swap_buffer storage for byte-swapped depth.
 * @return nullptr on success, else a static description of the problem.
 */
const char* depthFromMsg(const sensor_msgs::Image& msg, cv::Mat& depth, double& depth_scale,
                         cv::Mat& swap_buffer);

/**
 * @brief Pinhole intrinsics of a rectified image: from P (the projection of rectified
 * images, as image_geometry uses), or from K when P is unset (all zero focal length).
 * Not validated here: the core rejects zero or non-finite values (Status::kInvalidIntrinsics).
 */
Intrinsics intrinsicsFromCameraInfo(const sensor_msgs::CameraInfo& info);

/**
 * @brief Whether a camera_info describes a raw (distorted) image: any distortion coefficient
 * non-zero. The detector reads its images as rectified (the pinhole P, else K); raw images must
 * go through image_proc's rectification first.
 */
bool hasDistortion(const sensor_msgs::CameraInfo& info);

/**
 * @brief Whether @p b is the calibration @p a within the re-estimation noise of a driver that
 * refines it while it runs: fx, fy, cx and cy each within @p tolerance times a's fx of a's
 * (the default 1e-3 is half a pixel at a 500 px focal length). Invalid intrinsics match nothing.
 */
bool sameCamera(const Intrinsics& a, const Intrinsics& b, double tolerance = 1e-3);

/// @p frame_id as tf2 names frames: without tf1's leading '/' ("/camera_optical" ->
/// "camera_optical"; tf2 warns at every lookup of a name with it). Empty stays empty.
std::string tfFrameId(const std::string& frame_id);

/**
 * @brief camera_info of an undistorted pinhole camera (the inverse of
 * intrinsicsFromCameraInfo()): K and P from @p K, R identity, plumb_bob with zero distortion.
 */
sensor_msgs::CameraInfo cameraInfoFromIntrinsics(const Intrinsics& K, int width, int height,
                                                 const std_msgs::Header& header);

/**
 * @brief Build a core Frame from the three synchronised inputs, reading images in place.
 * Checks what only the messages can tell (encodings, step, data length, camera_info size);
 * the core's LaneDetector::validate() checks the rest (sizes, intrinsics, template fit).
 * @param[in] colour colour image; must outlive @p frame.
 * @param[in] depth registered depth image; must outlive @p frame.
 * @param[in] info camera_info of the colour camera.
 * @param[out] frame core frame (headers onto the messages' data).
 * @param[in,out] swap_buffer storage for byte-swapped depth (see depthFromMsg()).
 * @return nullptr on success, else a static description of the problem.
 */
const char* frameFromMsgs(const sensor_msgs::Image& colour, const sensor_msgs::Image& depth,
                          const sensor_msgs::CameraInfo& info, Frame& frame,
                          cv::Mat& swap_buffer);

/**
 * @brief A stereo disparity image (stereo_msgs/DisparityImage) as a cv::Mat header on its
 * 32FC1 data and the core's DisparityModel (f, T, min / max disparity, delta_d, valid window;
 * a window of zero size means the whole image, as in sensor_msgs/RegionOfInterest). Only an
 * image whose byte order differs from the host's is copied (into @p swap_buffer).
 * @param[in] msg disparity message; must outlive @p disparity.
 * @param[out] disparity CV_32FC1 header onto msg.image.data.
 * @param[out] model geometry and validity range for disparityToDepth().
 * @param[in,out] swap_buffer storage for byte-swapped disparities, reused across messages.
 * @return nullptr on success, else a static description of the problem (encoding, empty
 * image, layout, unusable f / T / range).
 */
const char* disparityFromMsg(const stereo_msgs::DisparityImage& msg, cv::Mat& disparity,
                             DisparityModel& model, cv::Mat& swap_buffer);

// ---------------------------------------------------------------------------
// Parameters

/**
 * @brief Copy every dynamic_reconfigure field into core Params, by name (the cfg names are the
 * Params field names, see params_io.h; enums become DepthTerm / PlaneFit). Fields that are not
 * reconfigurable (the up axis) are left unchanged. Not sanitised: pass the result through
 * rgbd_lane_detector::sanitize().
 * @return the number of cfg parameters without a Params field (0 unless the two disagree).
 */
int configToParams(const LaneDetectorConfig& config, Params& params);

/// The inverse of configToParams(): every reconfigurable field of @p params into @p config.
/// @return the number of cfg parameters without a Params field.
int paramsToConfig(const Params& params, LaneDetectorConfig& config);

// ---------------------------------------------------------------------------
// Geometry

/**
 * @brief Express a plane n . p + d = 0 in another frame: p' = T p gives n' = R n and
 * d' = d - n' . t.
 */
void transformPlane(const Eigen::Isometry3d& T, Eigen::Vector3d& normal, double& distance);

/**
 * @brief The +z axis of a frame expressed in the camera optical frame (the road's up
 * direction O_y when that frame is, e.g., base_link).
 * @param[in] T_optical_up transform taking points of the up frame into the optical frame.
 */
Eigen::Vector3d upAxisFromTransform(const Eigen::Isometry3d& T_optical_up);

// ---------------------------------------------------------------------------
// Outputs. Every function fills a message allocated by the caller; @p T takes points from
// the colour optical frame into header.frame_id (identity when no target_frame is set).

/// The lane plane (normal rotated, distance recomputed, support points transformed).
void fillLanePlane(const Result& result, const std_msgs::Header& header,
                   const Eigen::Isometry3d& T, LanePlane& msg);

/// Both boundaries' 3D polylines (valid points only; a side that is not found is empty, 0 score,
/// 0 confidence), their kinds (paint / road edge) and confidences.
void fillLaneMarkings(const Result& result, const std_msgs::Header& header,
                      const Eigen::Isometry3d& T, LaneMarkings& msg);

/// Point field value of `side` in lane_points.
enum class Side : uint8_t { kLeft = 0, kRight = 1 };

/**
 * @brief lane_points: one point per traced point with valid depth of each found side:
 * float32 x, y, z, float32 score, uint8 side (0 left, 1 right), uint8 kind (LaneMarkings
 * KIND_PAINT 0, KIND_ROAD_EDGE 1), padded to 20 bytes so every float is 4-byte aligned.
 * height 1, is_dense.
 */
void fillLanePoints(const Result& result, const std_msgs::Header& header,
                    const Eigen::Isometry3d& T, sensor_msgs::PointCloud2& msg);

/// Marker namespaces and ids of lane_visualization (stable across frames).
constexpr const char* kPlaneNs = "lane_plane";
constexpr const char* kMarkingsNs = "lane_markings";
constexpr int kLeftId = 0;
constexpr int kRightId = 1;

/**
 * @brief lane_visualization: the ego-lane patch of the plane (TRIANGLE_LIST, ns lane_plane,
 * id 0: both markers' near and far ends projected onto the plane) and each marker's polyline
 * (LINE_STRIP, ns lane_markings, ids 0 left / 1 right). An absent item is sent as a DELETE of
 * its ns/id, so rviz never shows a stale plane or marker.
 */
void fillLaneMarkers(const Result& result, const std_msgs::Header& header,
                     const Eigen::Isometry3d& T, visualization_msgs::MarkerArray& msg);

/**
 * @brief lane_model: the lane model (in the vehicle frame) as a message; the centre line is
 * sampled every @p step metres over its range, and at its far end. An invalid model has every
 * other field 0 (lane_changes too).
 * @param[in] model the detector's lane model.
 * @param[in] header stamp of the input image, frame_id of the vehicle frame.
 * @param[out] msg filled; boundaries only for the positions known this frame.
 */
void fillLaneModel(const LaneModelEstimate& model, const std_msgs::Header& header, LaneModel& msg,
                   double step = 1.0);

/// Marker namespace of the lane model's boundaries in lane_visualization (ids = positions).
constexpr const char* kModelNs = "lane_model";

/**
 * @brief Append the lane model's boundaries to lane_visualization: LINE_STRIPs in the vehicle
 * frame (ns lane_model, id = LaneBoundary position), coloured by kind (solid white / yellow,
 * dashed light grey / light yellow, road edge red, unknown grey), sampled every @p step metres
 * from x_min and at x_max; unknown positions as DELETE.
 */
void appendLaneModelMarkers(const LaneModelEstimate& model, const std_msgs::Header& header,
                            visualization_msgs::MarkerArray& msg, double step = 1.0);

/**
 * @brief lane_grid: the lane grid as an occupancy grid in the vehicle frame (info.origin the
 * grid's corner (0, -width / 2, 0), identity orientation; data row-major, rows along y).
 * @param[in] grid built from this frame's lane model.
 * @param[in] header stamp of the input image, frame_id of the lane model's vehicle frame.
 * @param[out] msg filled (map_load_time = the stamp).
 */
void fillOccupancyGrid(const LaneGrid& grid, const std_msgs::Header& header,
                       nav_msgs::OccupancyGrid& msg);

/**
 * @brief Copy a single-channel float map (the response maps) into an image message (32FC1).
 * @param[in] map CV_32FC1.
 */
void floatMapToImage(const cv::Mat& map, const std_msgs::Header& header, sensor_msgs::Image& msg);

/**
 * @brief Size an image message for @p rows x @p cols of @p type and return a cv::Mat header
 * onto its data, so an image can be drawn straight into the message (no extra copy).
 */
cv::Mat prepareImage(int rows, int cols, int type, const std::string& encoding,
                     const std_msgs::Header& header, sensor_msgs::Image& msg);

}  // namespace conversions
}  // namespace rgbd_lane_detector
