/**
 * @file scenario.h
 * @brief Settings of the synthetic road generator, the named scenarios and depth-sensor models.
 *
 * Every setting is listed once in a field table (settingFields()), which drives the JSON
 * record (scenario.json), the command-line overrides (--set key=value) and the comparison
 * that lets scripts skip regenerating an unchanged sequence.
 */
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace rgbd_lane_detector {
namespace synth {

/// Bumped whenever rendering or the ground truth changes, so cached sequences are regenerated.
/// Version 2: urban scenarios (kerb, tram rails, road edge, intersections, crest and sag, yellow
/// centre line, lane change) and the extended ground truth (ground_truth.h).
constexpr int kGeneratorVersion = 2;

/// Painted line style (kDouble: two solid lines, double_line_gap apart).
enum class MarkerKind : int { kNone = 0, kSolid = 1, kDashed = 2, kDouble = 3 };

/// Paint colour of a line.
enum class PaintColour : int { kWhite = 0, kYellow = 1 };

/**
 * @brief What bounds the ego lane on one side.
 * kPaint: the painted line of ego_left / ego_right; kKerb (right side only): a raised kerb and a
 * sidewalk; kTramRails (left side only): a double tram track flush with the road, its nearest
 * rail on the lane boundary; kAsphaltEdge (right side only): the asphalt ends (gravel, grass).
 */
enum class BoundaryType : int { kPaint = 0, kKerb = 1, kTramRails = 2, kAsphaltEdge = 3 };

/// Class ids written to GT/LABELS (R channel), following SYNTHIA's numbering.
enum LabelClass : uint8_t {
  kLabelVoid = 0,
  kLabelSky = 1,
  kLabelBuilding = 2,  ///< overpasses and their pillars
  kLabelRoad = 3,
  kLabelSidewalk = 4,  ///< paved shoulder
  kLabelFence = 5,     ///< guard rails
  kLabelVegetation = 6,
  kLabelPole = 7,
  kLabelCar = 8,  ///< cars and trucks
  kLabelLaneMarking = 12,  ///< lines, stop lines, zebra crossings, arrows
  // beyond SYNTHIA's classes (generator version 2)
  kLabelKerb = 16,     ///< kerb stones: the vertical face and the top
  kLabelRail = 17,     ///< tram rail heads and their grooves
  kLabelTerrain = 18,  ///< gravel beside an unpainted asphalt edge
};

/**
 * @brief Everything that defines a generated sequence. Lengths in metres, angles in degrees,
 * colours as (R, G, B) in [0, 1] (albedo or light), distances along the road in metres.
 */
struct SceneSettings {
  // --- identity and output ---
  std::string scenario = "summer";  ///< preset the settings started from
  std::string sensor = "clean";     ///< depth sensor model: clean, kinect, sparse, lidar
  int seed = 1;                     ///< all randomness derives from it
  int frames = 300;
  int width = 640;
  int height = 380;
  double focal_1280 = 532.740352;  ///< focal length at 1280 px width (SYNTHIA); scaled with width
  double baseline = 0.8;           ///< stereo baseline written to intrinsics.txt (SYNTHIA)
  double fps = 10.0;
  int supersample = 2;  ///< colour samples per pixel side (2: 2x2); depth/labels: pixel centre

  // --- camera motion ---
  double camera_height = 1.5;
  double pitch_deg = 3.0;  ///< positive looks down
  double roll_deg = 0.0;   ///< positive raises the image's right side (REP-103 roll = -roll_deg)
  double pitch_wobble_deg = 0.3;  ///< amplitude of a sinusoidal pitch change (road bumps)
  double roll_wobble_deg = 0.4;
  double wobble_period = 37.0;    ///< m travelled per wobble cycle
  double speed = 20.0;            ///< m/s
  double start_s = 0.0;           ///< road position of frame 0
  double drift_amplitude = 0.35;  ///< lateral sinusoid inside the lane
  double drift_period = 160.0;    ///< m travelled per drift cycle

  // --- road layout ---
  double curvature = 0.0;  ///< 1/m, positive turns right (constant-curvature arc)
  double lane_width = 3.6;
  int lanes_left = 1;  ///< lanes left of the ego lane
  int lanes_right = 0;
  double shoulder_width = 2.0;
  double marker_width = 0.15;
  double edge_marker_width = 0.20;
  double dash_length = 3.0;
  double dash_gap = 9.0;
  MarkerKind ego_left = MarkerKind::kDashed;
  MarkerKind ego_right = MarkerKind::kSolid;
  MarkerKind separators = MarkerKind::kDashed;  ///< lines between other lanes
  MarkerKind edges = MarkerKind::kSolid;        ///< outer road edges (when not an ego line)
  double double_line_gap = 0.12;                ///< gap between the two lines of a double line
  PaintColour ego_left_colour = PaintColour::kWhite;
  PaintColour ego_right_colour = PaintColour::kWhite;
  cv::Vec3d yellow_paint{0.80, 0.62, 0.14};  ///< albedo of yellow road paint (RGB)
  bool oncoming_left = false;  ///< the lanes left of the ego lane carry oncoming traffic

  // --- what bounds the ego lane (urban scenarios) ---
  BoundaryType left_boundary = BoundaryType::kPaint;   ///< kPaint or kTramRails
  BoundaryType right_boundary = BoundaryType::kPaint;  ///< kPaint, kKerb or kAsphaltEdge
  double kerb_height = 0.13;        ///< height of the kerb face above the road
  double kerb_width = 0.15;         ///< width of the kerb stones' top
  double sidewalk_width = 3.0;      ///< raised sidewalk beyond the kerb (then grass)
  double kerb_albedo = 0.56;        ///< light granite / concrete kerb stones
  double sidewalk_albedo = 0.44;    ///< concrete sidewalk tiles
  double tram_gauge = 1.435;        ///< between the rails' inner faces
  double tram_head_width = 0.07;    ///< rail head (the bright steel top)
  double tram_groove_width = 0.04;  ///< dark flangeway beside each head (gauge side)
  double tram_track_spacing = 3.0;  ///< between the centres of the two tracks
  double edge_drop = 0.04;          ///< gravel below the asphalt edge
  double gravel_width = 0.8;        ///< gravel strip beyond the asphalt edge (then grass)
  double gravel_albedo = 0.40;

  // --- intersections ---
  double intersection_period = 0.0;  ///< m between intersections (0 = none)
  double intersection_start = 100.0;  ///< road position of the first crossing road's near edge
  double crossing_width = 9.0;        ///< width of the crossing road (m along the road)
  bool turn_arrows = true;            ///< arrows in the lanes before the stop line

  // --- vertical profile (crest and sag) ---
  double vertical_radius = 0.0;    ///< radius of the vertical curves (0 = flat road)
  double vertical_grade = 0.04;    ///< grade of the tangents between the curves
  double vertical_tangent = 40.0;  ///< length of each constant-grade tangent
  double vertical_flat = 60.0;     ///< level road between two crest-sag cycles
  double vertical_start = 30.0;    ///< road position where the first crest begins

  // --- lane change ---
  double lane_change_length = 0.0;    ///< m of road per lane change (0 = none)
  double lane_change_start = 150.0;   ///< road position where the change begins
  double lane_change_return = 400.0;  ///< where the change back begins (0 = no return)
  int lane_change_lanes = -1;         ///< lanes moved (negative: to the left)

  // --- materials ---
  double asphalt_albedo = 0.30;
  double asphalt_contrast = 0.30;  ///< relative variation of the value-noise texture
  double crack_density = 0.5;      ///< 0..1
  double patch_density = 0.25;     ///< probability of a repaired patch per 8 m lane cell
  double paint_albedo = 0.85;
  double paint_wear = 0.15;  ///< 0..1, fraction of worn paint

  // --- lighting and weather ---
  double sun_elevation_deg = 50.0;
  double sun_azimuth_deg = 40.0;  ///< from the road's initial direction, positive right
  double ambient = 0.55;
  double direct = 0.60;
  bool shadows = true;  ///< cast shadows of boxes (vehicles, overpasses, poles)
  cv::Vec3d sky_horizon{0.75, 0.82, 0.92};
  cv::Vec3d sky_zenith{0.30, 0.50, 0.85};
  double cloud_cover = 0.2;
  double fog_visibility = 0.0;  ///< m; 0 = no fog; colour = mix(c, fog, 1 - exp(-z / visibility))
  cv::Vec3d fog_colour{0.80, 0.80, 0.81};
  double exposure = 1.0;
  double exposure_flicker = 0.0;  ///< relative amplitude of a slow exposure oscillation
  double flicker_period = 60.0;   ///< frames
  double overpass_period = 0.0;   ///< m between overpasses (0 = none)
  double overpass_length = 14.0;  ///< deck extent along the road
  double overpass_clearance = 5.0;
  double exposure_adapt = 0.0;  ///< extra gain when the camera is under an overpass (auto-exposure)
  double pole_period = 0.0;     ///< m between lamp poles on both sides (0 = none)
  double canopy_shadows = 0.0;  ///< 0..1 coverage of tree shadows near the road edges
  /// Low-beam headlights (night): road irradiance in the beam, in the units of `direct` (0 =
  /// none). The lamps sit 0.7 m above the road, 1.8 m ahead of the camera; the beam is cut off
  /// at the lamps' horizon, about 34 deg wide (1/e), and lights the road evenly out to
  /// headlight_range, then falls off with the square of the distance.
  double headlights = 0.0;
  double headlight_range = 45.0;  ///< m
  /// Fraction of the image height the vehicle's bonnet (hood) hides at the image's centre
  /// column (its edge curves down toward the sides); 0 = none. Dark paint; its depth is the
  /// hood's, except for a LiDAR (roof-mounted: no returns from the bonnet).
  double bonnet = 0.0;

  // --- objects ---
  int vehicles = 3;            ///< cars in the other lanes
  bool lead_vehicle = true;    ///< a car ahead in the ego lane (25-60 m)
  int trucks = 0;              ///< trucks in the other lanes
  bool truck_stripes = false;  ///< white conspicuity stripes on trucks' sides and rears
  bool guard_rails = false;    ///< white guard rails on both road sides
  double rail_height = 0.75;   ///< top of the rail beam

  // --- sensors ---
  double colour_noise = 2.0;   ///< Gaussian sigma of the colour sensor (0-255)
  double depth_noise_k = 0.0;  ///< depth sigma = k * z^2 (1/m)
  double depth_range = 200.0;  ///< depth beyond this is invalid (m)
  double depth_dropout = 0.0;  ///< probability of an invalid pixel (speckle)
  double depth_holes = 0.0;    ///< 0..1 coverage of invalid blobs (moving per frame)
  double max_range = 200.0;    ///< scene beyond this distance is not rendered (horizon haze)
  /// A spinning LiDAR projected into the image (0 = a dense depth sensor): depth only on the
  /// pixels its beams hit, lidar_beams rings evenly spaced in elevation from lidar_low_deg to
  /// lidar_high_deg (world elevation at the camera), one return every lidar_azimuth_deg.
  int lidar_beams = 0;
  double lidar_low_deg = -25.0;
  double lidar_high_deg = 15.0;
  double lidar_azimuth_deg = 0.2;
  double lidar_range_noise = 0.02;  ///< m, Gaussian sigma of a return's range

  // --- ground truth sampling ---
  double gt_min_distance = 3.0;
  double gt_max_distance = 60.0;
  double gt_step = 0.5;
  double gt_plane_min = 3.0;       ///< the true plane fits the ego lane's surface from here...
  double gt_plane_max = 20.0;      ///< ...to here ahead (matters on a non-planar road)
  double gt_required_range = 20.0;  ///< lane_optional: the ego lines end within this range
};

/// One entry of the settings table.
struct SettingField {
  enum class Type { kInt, kDouble, kBool, kString, kColour, kMarker, kPaint, kBoundary };
  const char* name;
  Type type;
  void* value;
  const char* help;
};

/// The table of every setting of @p s (pointers into @p s).
std::vector<SettingField> settingFields(SceneSettings& s);

/// Names of the scenario presets.
const std::vector<std::string>& scenarioNames();
/// Names of the depth sensor models.
const std::vector<std::string>& sensorNames();

/**
 * @brief Reset @p s to defaults and apply a named scenario (keeps seed, size, frames, sensor).
 * @return false for an unknown name (@p s unchanged).
 */
bool applyScenario(const std::string& name, SceneSettings& s);

/**
 * @brief Apply a depth-sensor model: clean (exact depth), kinect (sigma = 0.0015 z^2, 20 m
 * range), sparse (R200-like: holes, speckle dropout, sigma = 0.003 z^2, 18 m range).
 * @return false for an unknown name.
 */
bool applySensor(const std::string& name, SceneSettings& s);

/**
 * @brief Set one field from text ("key=value" overrides).
 * @return false with @p error filled for an unknown key or an unparsable value.
 */
bool setSetting(SceneSettings& s, const std::string& key, const std::string& value,
                std::string& error);

/// Check ranges (sizes, positive lengths...). @return false with a message.
bool validateSettings(const SceneSettings& s, std::string& error);

/// Settings and generator version as JSON text (cv::FileStorage), deterministic.
std::string settingsToJson(const SceneSettings& s);

/**
 * @brief Read settings written by settingsToJson() (unknown keys are ignored).
 * @return false when the file cannot be parsed.
 */
bool readSettingsJson(const std::string& path, SceneSettings& s, std::string& error);

/// Marker kind from "none", "solid", "dashed" or "double".
bool parseMarkerKind(const std::string& text, MarkerKind& kind);
const char* markerKindName(MarkerKind kind);
/// Paint colour from "white" or "yellow".
bool parsePaintColour(const std::string& text, PaintColour& colour);
const char* paintColourName(PaintColour colour);
/// Boundary type from "paint", "kerb", "tram_rails" or "asphalt_edge".
bool parseBoundaryType(const std::string& text, BoundaryType& type);
const char* boundaryTypeName(BoundaryType type);

}  // namespace synth
}  // namespace rgbd_lane_detector
