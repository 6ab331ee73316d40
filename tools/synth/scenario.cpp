#include "rgbd_lane_detector_tools/synth/scenario.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace rgbd_lane_detector {
namespace synth {
namespace {

using T = SettingField::Type;

bool parseDouble(const std::string& text, double& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return end && *end == '\0' && std::isfinite(out);
}

bool parseInt(const std::string& text, int& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (!end || *end != '\0' || v < -2147483647L || v > 2147483647L) return false;
  out = static_cast<int>(v);
  return true;
}

bool parseBool(const std::string& text, bool& out) {
  if (text == "true" || text == "1" || text == "on" || text == "yes") {
    out = true;
    return true;
  }
  if (text == "false" || text == "0" || text == "off" || text == "no") {
    out = false;
    return true;
  }
  return false;
}

bool parseColour(const std::string& text, cv::Vec3d& out) {
  std::stringstream ss(text);
  std::string item;
  cv::Vec3d c;
  for (int i = 0; i < 3; ++i) {
    if (!std::getline(ss, item, ',') || !parseDouble(item, c[i])) return false;
  }
  if (std::getline(ss, item, ',')) return false;
  out = c;
  return true;
}

// Name tables of the enum settings, indexed by the enum value.
const char* const kMarkerNames[] = {"none", "solid", "dashed", "double"};
const char* const kPaintNames[] = {"white", "yellow"};
const char* const kBoundaryNames[] = {"paint", "kerb", "tram_rails", "asphalt_edge"};

template <typename E, size_t N>
bool parseEnum(const std::string& text, const char* const (&names)[N], E& out) {
  for (size_t i = 0; i < N; ++i) {
    if (text == names[i]) {
      out = static_cast<E>(i);
      return true;
    }
  }
  return false;
}

template <typename E, size_t N>
const char* enumName(E value, const char* const (&names)[N]) {
  const size_t i = static_cast<size_t>(value);
  return i < N ? names[i] : names[0];
}

// An urban two-lane street: narrower lanes, lamp posts, trees.
void applyStreet(SceneSettings& s) {
  s.lane_width = 3.5;
  s.pole_period = 30.0;
  s.canopy_shadows = 0.3;
}

void applyCloudyLight(SceneSettings& s) {
  s.ambient = 0.85;
  s.direct = 0.10;
  s.shadows = false;
  s.sky_horizon = cv::Vec3d(0.78, 0.79, 0.80);
  s.sky_zenith = cv::Vec3d(0.58, 0.60, 0.64);
  s.cloud_cover = 0.9;
}

}  // namespace

std::vector<SettingField> settingFields(SceneSettings& s) {
  return {
      {"scenario", T::kString, &s.scenario, "preset the settings started from"},
      {"sensor", T::kString, &s.sensor, "depth sensor model (clean, kinect, sparse, lidar)"},
      {"seed", T::kInt, &s.seed, "random seed"},
      {"frames", T::kInt, &s.frames, "number of frames"},
      {"width", T::kInt, &s.width, "image width (px)"},
      {"height", T::kInt, &s.height, "image height (px)"},
      {"focal_1280", T::kDouble, &s.focal_1280, "focal length at 1280 px width (px)"},
      {"baseline", T::kDouble, &s.baseline, "stereo baseline in intrinsics.txt (m)"},
      {"fps", T::kDouble, &s.fps, "frame rate (Hz)"},
      {"supersample", T::kInt, &s.supersample, "colour samples per pixel side"},
      {"camera_height", T::kDouble, &s.camera_height, "camera above the road (m)"},
      {"pitch_deg", T::kDouble, &s.pitch_deg, "camera pitch, positive down (deg)"},
      {"roll_deg", T::kDouble, &s.roll_deg, "camera roll, right side up (deg)"},
      {"pitch_wobble_deg", T::kDouble, &s.pitch_wobble_deg, "pitch oscillation amplitude (deg)"},
      {"roll_wobble_deg", T::kDouble, &s.roll_wobble_deg, "roll oscillation amplitude (deg)"},
      {"wobble_period", T::kDouble, &s.wobble_period, "distance per wobble cycle (m)"},
      {"speed", T::kDouble, &s.speed, "camera speed (m/s)"},
      {"start_s", T::kDouble, &s.start_s, "road position of frame 0 (m)"},
      {"drift_amplitude", T::kDouble, &s.drift_amplitude, "lateral drift amplitude (m)"},
      {"drift_period", T::kDouble, &s.drift_period, "distance per drift cycle (m)"},
      {"curvature", T::kDouble, &s.curvature, "road curvature, positive right (1/m)"},
      {"lane_width", T::kDouble, &s.lane_width, "lane width (m)"},
      {"lanes_left", T::kInt, &s.lanes_left, "lanes left of the ego lane"},
      {"lanes_right", T::kInt, &s.lanes_right, "lanes right of the ego lane"},
      {"shoulder_width", T::kDouble, &s.shoulder_width, "paved shoulder width (m)"},
      {"marker_width", T::kDouble, &s.marker_width, "lane marker width (m)"},
      {"edge_marker_width", T::kDouble, &s.edge_marker_width, "road edge line width (m)"},
      {"dash_length", T::kDouble, &s.dash_length, "dash length (m)"},
      {"dash_gap", T::kDouble, &s.dash_gap, "gap between dashes (m)"},
      {"ego_left", T::kMarker, &s.ego_left, "ego lane left line (none, solid, dashed)"},
      {"ego_right", T::kMarker, &s.ego_right, "ego lane right line"},
      {"separators", T::kMarker, &s.separators, "lines between the other lanes"},
      {"edges", T::kMarker, &s.edges, "outer road edge lines"},
      {"double_line_gap", T::kDouble, &s.double_line_gap, "gap between double lines (m)"},
      {"ego_left_colour", T::kPaint, &s.ego_left_colour, "ego left line colour (white, yellow)"},
      {"ego_right_colour", T::kPaint, &s.ego_right_colour, "ego right line colour"},
      {"yellow_paint", T::kColour, &s.yellow_paint, "yellow paint albedo (r,g,b)"},
      {"oncoming_left", T::kBool, &s.oncoming_left, "oncoming traffic left of the ego lane"},
      {"left_boundary", T::kBoundary, &s.left_boundary, "ego lane's left side (paint, tram_rails)"},
      {"right_boundary", T::kBoundary, &s.right_boundary,
       "ego lane's right side (paint, kerb, asphalt_edge)"},
      {"kerb_height", T::kDouble, &s.kerb_height, "kerb face height (m)"},
      {"kerb_width", T::kDouble, &s.kerb_width, "kerb stone top width (m)"},
      {"sidewalk_width", T::kDouble, &s.sidewalk_width, "sidewalk width beyond the kerb (m)"},
      {"kerb_albedo", T::kDouble, &s.kerb_albedo, "kerb stone albedo"},
      {"sidewalk_albedo", T::kDouble, &s.sidewalk_albedo, "sidewalk albedo"},
      {"tram_gauge", T::kDouble, &s.tram_gauge, "tram track gauge (m)"},
      {"tram_head_width", T::kDouble, &s.tram_head_width, "rail head width (m)"},
      {"tram_groove_width", T::kDouble, &s.tram_groove_width, "rail groove width (m)"},
      {"tram_track_spacing", T::kDouble, &s.tram_track_spacing, "distance of the track centres (m)"},
      {"edge_drop", T::kDouble, &s.edge_drop, "gravel below the asphalt edge (m)"},
      {"gravel_width", T::kDouble, &s.gravel_width, "gravel strip width (m)"},
      {"gravel_albedo", T::kDouble, &s.gravel_albedo, "gravel albedo"},
      {"intersection_period", T::kDouble, &s.intersection_period,
       "distance between intersections (m, 0 = none)"},
      {"intersection_start", T::kDouble, &s.intersection_start, "first crossing road (m)"},
      {"crossing_width", T::kDouble, &s.crossing_width, "crossing road width (m)"},
      {"turn_arrows", T::kBool, &s.turn_arrows, "arrows before the stop line"},
      {"vertical_radius", T::kDouble, &s.vertical_radius, "vertical curve radius (m, 0 = flat)"},
      {"vertical_grade", T::kDouble, &s.vertical_grade, "grade between vertical curves"},
      {"vertical_tangent", T::kDouble, &s.vertical_tangent, "constant-grade length (m)"},
      {"vertical_flat", T::kDouble, &s.vertical_flat, "level road between cycles (m)"},
      {"vertical_start", T::kDouble, &s.vertical_start, "start of the first crest (m)"},
      {"lane_change_length", T::kDouble, &s.lane_change_length,
       "road length of a lane change (m, 0 = none)"},
      {"lane_change_start", T::kDouble, &s.lane_change_start, "start of the lane change (m)"},
      {"lane_change_return", T::kDouble, &s.lane_change_return,
       "start of the change back (m, 0 = none)"},
      {"lane_change_lanes", T::kInt, &s.lane_change_lanes, "lanes moved (negative: left)"},
      {"asphalt_albedo", T::kDouble, &s.asphalt_albedo, "mean asphalt albedo"},
      {"asphalt_contrast", T::kDouble, &s.asphalt_contrast, "asphalt texture contrast"},
      {"crack_density", T::kDouble, &s.crack_density, "crack density (0..1)"},
      {"patch_density", T::kDouble, &s.patch_density, "repaired patches per lane cell"},
      {"paint_albedo", T::kDouble, &s.paint_albedo, "marker paint albedo"},
      {"paint_wear", T::kDouble, &s.paint_wear, "worn paint fraction (0..1)"},
      {"sun_elevation_deg", T::kDouble, &s.sun_elevation_deg, "sun elevation (deg)"},
      {"sun_azimuth_deg", T::kDouble, &s.sun_azimuth_deg, "sun azimuth from the road (deg)"},
      {"ambient", T::kDouble, &s.ambient, "ambient light"},
      {"direct", T::kDouble, &s.direct, "direct sun light"},
      {"shadows", T::kBool, &s.shadows, "cast shadows"},
      {"sky_horizon", T::kColour, &s.sky_horizon, "sky colour at the horizon (r,g,b)"},
      {"sky_zenith", T::kColour, &s.sky_zenith, "sky colour at the zenith (r,g,b)"},
      {"cloud_cover", T::kDouble, &s.cloud_cover, "cloud cover (0..1)"},
      {"fog_visibility", T::kDouble, &s.fog_visibility, "fog visibility (m, 0 = none)"},
      {"fog_colour", T::kColour, &s.fog_colour, "fog colour (r,g,b)"},
      {"exposure", T::kDouble, &s.exposure, "exposure gain"},
      {"exposure_flicker", T::kDouble, &s.exposure_flicker, "exposure oscillation amplitude"},
      {"flicker_period", T::kDouble, &s.flicker_period, "exposure oscillation period (frames)"},
      {"overpass_period", T::kDouble, &s.overpass_period, "distance between overpasses (m)"},
      {"overpass_length", T::kDouble, &s.overpass_length, "overpass deck length (m)"},
      {"overpass_clearance", T::kDouble, &s.overpass_clearance, "overpass clearance (m)"},
      {"exposure_adapt", T::kDouble, &s.exposure_adapt, "auto-exposure gain under overpasses"},
      {"pole_period", T::kDouble, &s.pole_period, "distance between lamp poles (m)"},
      {"canopy_shadows", T::kDouble, &s.canopy_shadows, "tree shadow coverage (0..1)"},
      {"headlights", T::kDouble, &s.headlights, "low-beam road irradiance (0 = off)"},
      {"headlight_range", T::kDouble, &s.headlight_range, "evenly lit road ahead (m)"},
      {"bonnet", T::kDouble, &s.bonnet, "image height hidden by the bonnet (0..1)"},
      {"vehicles", T::kInt, &s.vehicles, "cars in the other lanes"},
      {"lead_vehicle", T::kBool, &s.lead_vehicle, "car ahead in the ego lane"},
      {"trucks", T::kInt, &s.trucks, "trucks in the other lanes"},
      {"truck_stripes", T::kBool, &s.truck_stripes, "white stripes on trucks"},
      {"guard_rails", T::kBool, &s.guard_rails, "white guard rails on both sides"},
      {"rail_height", T::kDouble, &s.rail_height, "guard rail top (m)"},
      {"colour_noise", T::kDouble, &s.colour_noise, "colour noise sigma (0-255)"},
      {"depth_noise_k", T::kDouble, &s.depth_noise_k, "depth noise sigma = k z^2 (1/m)"},
      {"depth_range", T::kDouble, &s.depth_range, "depth range limit (m)"},
      {"depth_dropout", T::kDouble, &s.depth_dropout, "speckle dropout probability"},
      {"depth_holes", T::kDouble, &s.depth_holes, "invalid blob coverage (0..1)"},
      {"max_range", T::kDouble, &s.max_range, "render distance (m)"},
      {"lidar_beams", T::kInt, &s.lidar_beams, "LiDAR rings (0 = dense depth sensor)"},
      {"lidar_low_deg", T::kDouble, &s.lidar_low_deg, "lowest LiDAR ring elevation (deg)"},
      {"lidar_high_deg", T::kDouble, &s.lidar_high_deg, "highest LiDAR ring elevation (deg)"},
      {"lidar_azimuth_deg", T::kDouble, &s.lidar_azimuth_deg, "LiDAR azimuth step (deg)"},
      {"lidar_range_noise", T::kDouble, &s.lidar_range_noise, "LiDAR range noise sigma (m)"},
      {"gt_min_distance", T::kDouble, &s.gt_min_distance, "first ground-truth sample ahead (m)"},
      {"gt_max_distance", T::kDouble, &s.gt_max_distance, "last ground-truth sample ahead (m)"},
      {"gt_step", T::kDouble, &s.gt_step, "ground-truth sample spacing (m)"},
      {"gt_plane_min", T::kDouble, &s.gt_plane_min, "true plane fitted from here ahead (m)"},
      {"gt_plane_max", T::kDouble, &s.gt_plane_max, "true plane fitted to here ahead (m)"},
      {"gt_required_range", T::kDouble, &s.gt_required_range,
       "lane optional when the ego lines end within this range (m)"},
  };
}

const std::vector<std::string>& scenarioNames() {
  static const std::vector<std::string> names = {
      "summer",      "cloudy",       "fog",       "overpass",      "solid",
      "dashed",      "shadows",      "lane_like_objects", "no_markings",   "curve",
      "kerb",        "tram_rails",   "road_edge", "intersection",  "crest_sag",
      "yellow_centre", "lane_change", "sharp_bend", "night_motorway"};
  return names;
}

const std::vector<std::string>& sensorNames() {
  static const std::vector<std::string> names = {"clean", "kinect", "sparse", "lidar"};
  return names;
}

bool applyScenario(const std::string& name, SceneSettings& s) {
  bool known = false;
  for (const auto& n : scenarioNames()) known = known || n == name;
  if (!known) return false;
  SceneSettings p;  // defaults: the summer preset
  p.seed = s.seed;
  p.frames = s.frames;
  p.width = s.width;
  p.height = s.height;
  p.sensor = s.sensor;
  p.scenario = name;
  if (name == "cloudy") {
    applyCloudyLight(p);
  } else if (name == "fog") {
    applyCloudyLight(p);
    p.fog_visibility = 40.0;
  } else if (name == "overpass") {
    p.overpass_period = 110.0;
    p.exposure_adapt = 0.7;
    p.exposure_flicker = 0.1;
    p.sun_elevation_deg = 60.0;
  } else if (name == "solid") {
    p.lanes_right = 1;
    p.ego_left = p.ego_right = p.separators = MarkerKind::kSolid;
  } else if (name == "dashed") {
    p.lanes_right = 1;
    p.ego_left = p.ego_right = MarkerKind::kDashed;
  } else if (name == "shadows") {
    p.lanes_right = 1;
    p.sun_elevation_deg = 28.0;
    p.sun_azimuth_deg = 70.0;
    p.ambient = 0.42;
    p.direct = 0.95;
    p.vehicles = 5;
    p.trucks = 2;
    p.pole_period = 35.0;
    p.canopy_shadows = 0.5;
  } else if (name == "lane_like_objects") {
    p.lanes_right = 1;
    p.vehicles = 1;
    p.trucks = 4;
    p.truck_stripes = true;
    p.guard_rails = true;
  } else if (name == "no_markings") {
    p.ego_left = p.ego_right = p.separators = p.edges = MarkerKind::kNone;
  } else if (name == "curve") {
    p.curvature = 1.0 / 300.0;
  } else if (name == "kerb") {
    applyStreet(p);
    p.right_boundary = BoundaryType::kKerb;
  } else if (name == "tram_rails") {
    applyStreet(p);
    p.left_boundary = BoundaryType::kTramRails;
    p.oncoming_left = true;
  } else if (name == "road_edge") {
    p.lane_width = 3.5;
    p.right_boundary = BoundaryType::kAsphaltEdge;
  } else if (name == "intersection") {
    applyStreet(p);
    p.oncoming_left = true;
    p.intersection_period = 130.0;
  } else if (name == "crest_sag") {
    p.vertical_radius = 1000.0;
  } else if (name == "yellow_centre") {
    p.oncoming_left = true;
    p.ego_left = MarkerKind::kDouble;
    p.ego_left_colour = PaintColour::kYellow;
  } else if (name == "lane_change") {
    p.lanes_right = 1;
    p.ego_left = p.ego_right = MarkerKind::kDashed;
    p.drift_amplitude = 0.2;
    p.lane_change_length = 70.0;
  } else if (name == "sharp_bend") {
    // a bend of radius 90 m (a rural road, a motorway ramp): 20-25 m ahead the road runs 13-16
    // deg off the camera's axis, the inner line leaves the image's side
    p.curvature = -1.0 / 90.0;
    p.speed = 15.0;
  } else if (name == "night_motorway") {
    // a motorway at night in the leftmost lane: the solid edge line on the left, a dashed lane
    // line on the right with long gaps (4.5 m of paint, 10.5 m gap) at 30 m/s and 15 Hz, lit
    // by the vehicle's own low beams only; the bonnet hides the bottom 15% of the image
    p.lanes_left = 0;
    p.lanes_right = 2;
    p.ego_left = MarkerKind::kSolid;
    p.ego_right = p.separators = MarkerKind::kDashed;
    p.dash_length = 4.5;
    p.dash_gap = 10.5;
    p.speed = 30.0;
    p.fps = 15.0;
    p.shoulder_width = 2.5;
    p.ambient = 0.02;
    p.direct = 0.0;
    p.shadows = false;
    p.cloud_cover = 0.0;
    p.sky_horizon = cv::Vec3d(0.025, 0.028, 0.045);
    p.sky_zenith = cv::Vec3d(0.004, 0.005, 0.012);
    p.headlights = 0.5;
    p.colour_noise = 5.0;  // the gain of a camera at night
    p.bonnet = 0.15;
    p.pitch_deg = 2.0;
  }
  s = p;
  applySensor(s.sensor, s);
  return true;
}

bool applySensor(const std::string& name, SceneSettings& s) {
  if (name == "clean") {
    s.depth_noise_k = 0.0;
    s.depth_range = 200.0;
    s.depth_dropout = 0.0;
    s.depth_holes = 0.0;
  } else if (name == "kinect") {
    // Kinect-like noise model with a road-usable range limit (a real Kinect stops at 8-10 m).
    s.depth_noise_k = 0.0015;
    s.depth_range = 20.0;
    s.depth_dropout = 0.01;
    s.depth_holes = 0.0;
  } else if (name == "lidar") {
    // a 32-ring LiDAR on the roof, projected into the image: a ring every 1.3 deg (6 rows of a
    // 640-wide image, 15-20 of an HD one), 2 cm range noise, 100 m range, 5% of returns lost
    s.depth_noise_k = 0.0;
    s.depth_range = 100.0;
    s.depth_dropout = 0.05;
    s.depth_holes = 0.0;
    s.lidar_beams = 32;
    s.lidar_low_deg = -25.0;
    s.lidar_high_deg = 15.0;
    s.lidar_azimuth_deg = 0.2;
    s.lidar_range_noise = 0.02;
    s.sensor = name;
    return true;
  } else if (name == "sparse") {
    // RealSense R200-like active stereo: blob holes, speckle dropout, noisy, short range.
    s.depth_noise_k = 0.003;
    s.depth_range = 18.0;
    s.depth_dropout = 0.3;
    s.depth_holes = 0.35;
  } else {
    return false;
  }
  s.lidar_beams = 0;
  s.sensor = name;
  return true;
}

bool parseMarkerKind(const std::string& text, MarkerKind& kind) {
  return parseEnum(text, kMarkerNames, kind);
}

const char* markerKindName(MarkerKind kind) {
  return enumName(kind, kMarkerNames);
}

bool parsePaintColour(const std::string& text, PaintColour& colour) {
  return parseEnum(text, kPaintNames, colour);
}

const char* paintColourName(PaintColour colour) {
  return enumName(colour, kPaintNames);
}

bool parseBoundaryType(const std::string& text, BoundaryType& type) {
  return parseEnum(text, kBoundaryNames, type);
}

const char* boundaryTypeName(BoundaryType type) {
  return enumName(type, kBoundaryNames);
}

bool setSetting(SceneSettings& s, const std::string& key, const std::string& value,
                std::string& error) {
  for (const SettingField& f : settingFields(s)) {
    if (key != f.name) continue;
    bool ok = false;
    switch (f.type) {
      case T::kInt:
        ok = parseInt(value, *static_cast<int*>(f.value));
        break;
      case T::kDouble:
        ok = parseDouble(value, *static_cast<double*>(f.value));
        break;
      case T::kBool:
        ok = parseBool(value, *static_cast<bool*>(f.value));
        break;
      case T::kString:
        *static_cast<std::string*>(f.value) = value;
        ok = true;
        break;
      case T::kColour:
        ok = parseColour(value, *static_cast<cv::Vec3d*>(f.value));
        break;
      case T::kMarker:
        ok = parseMarkerKind(value, *static_cast<MarkerKind*>(f.value));
        break;
      case T::kPaint:
        ok = parsePaintColour(value, *static_cast<PaintColour*>(f.value));
        break;
      case T::kBoundary:
        ok = parseBoundaryType(value, *static_cast<BoundaryType*>(f.value));
        break;
    }
    if (!ok) error = "invalid value '" + value + "' for setting '" + key + "'";
    return ok;
  }
  error = "unknown setting '" + key + "'";
  return false;
}

bool validateSettings(const SceneSettings& s, std::string& error) {
  auto fail = [&error](const std::string& m) {
    error = m;
    return false;
  };
  if (s.width < 32 || s.height < 32 || s.width > 8192 || s.height > 8192)
    return fail("image size must be between 32 and 8192 px");
  if (s.frames < 1) return fail("frames must be >= 1");
  if (s.supersample < 1 || s.supersample > 4) return fail("supersample must be 1..4");
  if (!(s.focal_1280 > 0) || !(s.fps > 0)) return fail("focal_1280 and fps must be > 0");
  if (!(s.camera_height > 0.1)) return fail("camera_height must be > 0.1 m");
  if (std::fabs(s.pitch_deg) > 45 || std::fabs(s.roll_deg) > 45)
    return fail("pitch and roll must be within 45 deg");
  if (!(s.lane_width > 1.0) || s.lanes_left < 0 || s.lanes_right < 0 || s.lanes_left > 5 ||
      s.lanes_right > 5)
    return fail("lane_width must be > 1 m and lanes_left/right 0..5");
  if (!(s.marker_width > 0.01) || !(s.edge_marker_width > 0.01))
    return fail("marker widths must be > 0.01 m");
  if (!(s.dash_length > 0.1) || !(s.dash_gap >= 0)) return fail("dash_length/gap invalid");
  if (std::fabs(s.curvature) > 0.02) return fail("|curvature| must be <= 0.02 1/m (R >= 50 m)");
  if (!(s.wobble_period > 0) || !(s.drift_period > 0)) return fail("periods must be > 0");
  if (!(s.max_range > 10) || !(s.depth_range > 0)) return fail("ranges must be positive");
  if (s.fog_visibility < 0 || s.overpass_period < 0 || s.pole_period < 0)
    return fail("fog_visibility, overpass_period, pole_period must be >= 0");
  if (s.overpass_period > 0 && s.overpass_period < s.overpass_length + 10)
    return fail("overpass_period must exceed overpass_length + 10 m");
  if (s.vehicles < 0 || s.trucks < 0 || s.vehicles + s.trucks > 40)
    return fail("vehicles + trucks must be 0..40");
  if (!(s.gt_step > 0) || !(s.gt_max_distance > s.gt_min_distance) ||
      !(s.gt_plane_min > 0) || !(s.gt_plane_max > s.gt_plane_min + 1.0) ||
      !(s.gt_required_range >= 0))
    return fail("ground-truth sampling invalid");
  if (!(s.double_line_gap > 0)) return fail("double_line_gap must be > 0");
  if (s.left_boundary == BoundaryType::kKerb || s.left_boundary == BoundaryType::kAsphaltEdge)
    return fail("left_boundary must be paint or tram_rails");
  if (s.right_boundary == BoundaryType::kTramRails)
    return fail("right_boundary must be paint, kerb or asphalt_edge");
  if (s.right_boundary != BoundaryType::kPaint && s.lanes_right != 0)
    return fail("a kerb or asphalt edge bounds the rightmost lane: lanes_right must be 0");
  if (s.right_boundary == BoundaryType::kKerb &&
      (!(s.kerb_height > 0.0 && s.kerb_height < 0.5) || !(s.kerb_width > 0) ||
       !(s.sidewalk_width >= 0)))
    return fail("kerb_height must be in (0, 0.5) m, kerb_width > 0, sidewalk_width >= 0");
  if (s.right_boundary == BoundaryType::kAsphaltEdge &&
      (!(s.edge_drop >= 0.0 && s.edge_drop < 0.5) || !(s.gravel_width >= 0)))
    return fail("edge_drop must be in [0, 0.5) m and gravel_width >= 0");
  if (s.left_boundary == BoundaryType::kTramRails &&
      (!(s.tram_gauge > 0.5) || !(s.tram_head_width > 0.01) || !(s.tram_groove_width >= 0) ||
       !(s.tram_track_spacing > s.tram_gauge + s.tram_head_width + 2 * s.tram_groove_width)))
    return fail("tram track dimensions invalid (spacing must exceed one track's width)");
  if (s.left_boundary == BoundaryType::kTramRails && s.lanes_left < 1)
    return fail("tram_rails needs lanes_left >= 1 (the lanes beyond the tracks)");
  if (s.intersection_period < 0 ||
      (s.intersection_period > 0 && s.intersection_period < s.crossing_width + 60.0))
    return fail("intersection_period must be 0 or exceed crossing_width + 60 m");
  if (s.intersection_period > 0 &&
      (!(s.crossing_width > 3.0) || s.right_boundary != BoundaryType::kPaint ||
       s.left_boundary != BoundaryType::kPaint || s.vertical_radius > 0 || s.guard_rails))
    return fail("intersections need crossing_width > 3 m on a flat road with paint on both "
                "sides and no guard rails");
  if (s.vertical_radius < 0 ||
      (s.vertical_radius > 0 &&
       (!(s.vertical_radius >= 100.0) || !(s.vertical_grade > 0 && s.vertical_grade <= 0.12) ||
        !(s.vertical_tangent >= 0) || !(s.vertical_flat >= 0))))
    return fail("vertical profile invalid (radius 0 or >= 100 m, grade in (0, 0.12])");
  if (s.lane_change_length < 0 ||
      (s.lane_change_length > 0 &&
       (!(s.lane_change_length >= 20.0) || s.lane_change_lanes == 0 ||
        s.lane_change_lanes < -s.lanes_left || s.lane_change_lanes > s.lanes_right ||
        (s.lane_change_return > 0 &&
         s.lane_change_return < s.lane_change_start + s.lane_change_length))))
    return fail("lane change invalid (length >= 20 m, a target lane that exists, the return "
                "after the change)");
  if (s.lane_change_length > 0 && s.left_boundary != BoundaryType::kPaint)
    return fail("a lane change needs paint on the left (no tram zone)");
  return true;
}

std::string settingsToJson(const SceneSettings& settings) {
  SceneSettings s = settings;  // the field table needs mutable pointers
  cv::FileStorage fs(
      ".json", cv::FileStorage::WRITE | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_JSON);
  fs << "generator_version" << kGeneratorVersion;
  for (const SettingField& f : settingFields(s)) {
    switch (f.type) {
      case T::kInt:
        fs << f.name << *static_cast<int*>(f.value);
        break;
      case T::kDouble:
        fs << f.name << *static_cast<double*>(f.value);
        break;
      case T::kBool:
        fs << f.name << static_cast<int>(*static_cast<bool*>(f.value));
        break;
      case T::kString:
        fs << f.name << *static_cast<std::string*>(f.value);
        break;
      case T::kColour: {
        const cv::Vec3d& c = *static_cast<cv::Vec3d*>(f.value);
        fs << f.name << "[" << c[0] << c[1] << c[2] << "]";
        break;
      }
      case T::kMarker:
        fs << f.name << std::string(markerKindName(*static_cast<MarkerKind*>(f.value)));
        break;
      case T::kPaint:
        fs << f.name << std::string(paintColourName(*static_cast<PaintColour*>(f.value)));
        break;
      case T::kBoundary:
        fs << f.name << std::string(boundaryTypeName(*static_cast<BoundaryType*>(f.value)));
        break;
    }
  }
  return fs.releaseAndGetString();
}

bool readSettingsJson(const std::string& path, SceneSettings& s, std::string& error) {
  cv::FileStorage fs;
  try {
    if (!fs.open(path, cv::FileStorage::READ)) {
      error = "cannot open " + path;
      return false;
    }
  } catch (const cv::Exception& e) {
    error = "cannot parse " + path + ": " + e.what();
    return false;
  }
  for (const SettingField& f : settingFields(s)) {
    const cv::FileNode n = fs[f.name];
    if (n.empty()) continue;
    switch (f.type) {
      case T::kInt:
        *static_cast<int*>(f.value) = static_cast<int>(n);
        break;
      case T::kDouble:
        *static_cast<double*>(f.value) = static_cast<double>(n);
        break;
      case T::kBool:
        *static_cast<bool*>(f.value) = static_cast<int>(n) != 0;
        break;
      case T::kString:
        *static_cast<std::string*>(f.value) = static_cast<std::string>(n);
        break;
      case T::kColour:
        if (n.isSeq() && n.size() == 3) {
          cv::Vec3d& c = *static_cast<cv::Vec3d*>(f.value);
          for (int i = 0; i < 3; ++i) c[i] = static_cast<double>(n[i]);
        }
        break;
      case T::kMarker:
        parseMarkerKind(static_cast<std::string>(n), *static_cast<MarkerKind*>(f.value));
        break;
      case T::kPaint:
        parsePaintColour(static_cast<std::string>(n), *static_cast<PaintColour*>(f.value));
        break;
      case T::kBoundary:
        parseBoundaryType(static_cast<std::string>(n), *static_cast<BoundaryType*>(f.value));
        break;
    }
  }
  return true;
}

}  // namespace synth
}  // namespace rgbd_lane_detector
