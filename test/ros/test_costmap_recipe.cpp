// config/costmap_lane_layer.yaml, the costmap_2d recipe of the README, against the detector: its
// topics are the nodelet's outputs in the launch files' default namespace, and costmap_2d's
// StaticLayer and ObstacleLayer, configured by it, turn what the detector publishes into the
// costs the README promises. costmap_2d is not packaged in Debian 12, so its two rules that
// matter here are restated from its source (navigation, costmap_2d): StaticLayer::interpretValue()
// (plugins/static_layer.cpp) and the height / range filters of ObservationBuffer::bufferCloud()
// and ObstacleLayer::updateBounds().
#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "rgbd_lane_detector/lane_grid.h"

#ifndef RLD_SOURCE_DIR
#error "RLD_SOURCE_DIR must point at the package source"
#endif

namespace rgbd_lane_detector {
namespace {

// costmap_2d/cost_values.h
constexpr int kNoInformation = 255, kLethal = 254, kFreeSpace = 0;

YAML::Node recipe() { return YAML::LoadFile(std::string(RLD_SOURCE_DIR) + "/config/costmap_lane_layer.yaml"); }

/// The default of <arg name="NAME"> in launch/lane_detector.launch.
std::string launchDefault(const std::string& name) {
  std::ifstream in(std::string(RLD_SOURCE_DIR) + "/launch/lane_detector.launch");
  std::stringstream text;
  text << in.rdbuf();
  std::smatch m;
  const std::string s = text.str();
  if (!std::regex_search(s, m, std::regex("<arg name=\"" + name + "\" default=\"([^\"]*)\"")))
    return "(none)";
  return m[1];
}

/// StaticLayer's settings (its defaults where the recipe gives none).
struct StaticLayerSettings {
  bool track_unknown, trinary;
  unsigned char unknown;
  int lethal;
  explicit StaticLayerSettings(const YAML::Node& layer)
      : track_unknown(layer["track_unknown_space"].as<bool>(true)),
        trinary(layer["trinary_costmap"].as<bool>(true)),
        unknown(static_cast<unsigned char>(layer["unknown_cost_value"].as<int>(-1))),
        lethal(std::max(std::min(layer["lethal_cost_threshold"].as<int>(100), 100), 0)) {}
};

/// StaticLayer::interpretValue(): the cost of an OccupancyGrid value under the layer's settings.
int staticLayerCost(int8_t value, const StaticLayerSettings& s) {
  const unsigned char v = static_cast<unsigned char>(value);
  if (s.track_unknown && v == s.unknown) return kNoInformation;
  if (!s.track_unknown && v == s.unknown) return kFreeSpace;
  if (v >= s.lethal) return kLethal;
  if (s.trinary) return kFreeSpace;
  return static_cast<unsigned char>(static_cast<double>(v) / s.lethal * kLethal);
}

TEST(CostmapRecipe, PluginsInOrderOnTheDetectorsTopics) {
  const YAML::Node r = recipe();
  ASSERT_TRUE(r["plugins"].IsSequence());
  ASSERT_EQ(r["plugins"].size(), 3u);
  EXPECT_EQ(r["plugins"][0]["name"].as<std::string>(), "lane_grid");
  EXPECT_EQ(r["plugins"][0]["type"].as<std::string>(), "costmap_2d::StaticLayer");
  EXPECT_EQ(r["plugins"][1]["name"].as<std::string>(), "lane_points");
  EXPECT_EQ(r["plugins"][1]["type"].as<std::string>(), "costmap_2d::ObstacleLayer");
  EXPECT_EQ(r["plugins"][2]["type"].as<std::string>(), "costmap_2d::InflationLayer")
      << "inflation goes last: it inflates what the layers before it marked";
  // the nodelet publishes lane_grid and lane_points relative to its namespace, the launch
  // files' `camera` argument
  const std::string ns = "/" + launchDefault("camera") + "/";
  EXPECT_EQ(r["lane_grid"]["map_topic"].as<std::string>(), ns + "lane_grid");
  const YAML::Node source = r["lane_points"]["lane_points"];
  EXPECT_EQ(r["lane_points"]["observation_sources"].as<std::string>(), "lane_points");
  EXPECT_EQ(source["topic"].as<std::string>(), ns + "lane_points");
  EXPECT_EQ(source["data_type"].as<std::string>(), "PointCloud2");
  // a rolling window in a fixed frame, around the frame of the grid and the points
  EXPECT_TRUE(r["rolling_window"].as<bool>());
  EXPECT_EQ(r["robot_base_frame"].as<std::string>(), "base_link");
  EXPECT_NE(r["global_frame"].as<std::string>(), "base_link");
  EXPECT_LE(r["resolution"].as<double>(), Params().lane_grid_resolution + 1e-9)
      << "a coarser costmap would merge a one-cell line with the lane beside it";
}

// Every value a lane grid holds, through the StaticLayer as configured: lines and road edges
// lethal, a crossable dashed line a medium cost, the free lane and unknown cells free; each new
// grid is taken (first_map_only false) as a whole (no updates topic).
TEST(CostmapRecipe, GridLayerCosts) {
  const YAML::Node layer = recipe()["lane_grid"];
  EXPECT_FALSE(layer["first_map_only"].as<bool>());
  EXPECT_FALSE(layer["subscribe_to_updates"].as<bool>());
  EXPECT_TRUE(layer["use_maximum"].as<bool>()) << "the grid must not lower other layers' costs";
  LaneModelEstimate m;
  m.valid = true;
  const double y[3] = {1.75, -1.75, 5.25};
  for (int p = 0; p < 3; ++p) {
    LaneBoundaryModel& b = m.boundaries[p];
    b.valid = true;
    b.position = static_cast<BoundaryPosition>(p);
    b.kind = p == 0 ? LineKind::kDashed : LineKind::kSolid;
    b.c = {y[p], 0.0, 0.0, 0.0};
    b.x_min = 4.0;
    b.x_max = 30.0;
    b.lateral_std = 0.05f;
  }
  LaneGridSettings s;
  s.allow_lane_change = true;
  LaneGrid grid;
  grid.build(m, s);
  const StaticLayerSettings settings(layer);
  int seen[4] = {0, 0, 0, 0};  // unknown, free, crossable, occupied
  for (int8_t v : grid.cells()) {
    const int cost = staticLayerCost(v, settings);
    switch (v) {
      case LaneGrid::kUnknown:
        ASSERT_EQ(cost, kFreeSpace) << "unknown cells would block the area the camera cannot see";
        ++seen[0];
        break;
      case LaneGrid::kFree:
        ASSERT_EQ(cost, kFreeSpace);
        ++seen[1];
        break;
      case LaneGrid::kCrossable:
        ASSERT_GT(cost, kFreeSpace);
        ASSERT_LT(cost, kLethal - 1) << "a dashed line the vehicle may cross is not an obstacle";
        ++seen[2];
        break;
      default:
        ASSERT_EQ(v, LaneGrid::kOccupied);
        ASSERT_EQ(cost, kLethal);
        ++seen[3];
    }
  }
  for (int n : seen) EXPECT_GT(n, 0) << "every value was checked";
}

// Points of lane_points on a road that is not at z = 0 in the global frame (a grade, a crest):
// the ObstacleLayer keeps every one the detector reports (to 40 m ahead) and clears along rays.
TEST(CostmapRecipe, PointLayerKeepsEveryRoadPoint) {
  const YAML::Node layer = recipe()["lane_points"];
  const YAML::Node source = layer["lane_points"];
  EXPECT_TRUE(source["marking"].as<bool>());
  EXPECT_TRUE(source["clearing"].as<bool>()) << "old marks inside the lane are cleared";
  const double min_h = source["min_obstacle_height"].as<double>(0.0);
  const double max_h = source["max_obstacle_height"].as<double>(2.0);
  const double layer_max = layer["max_obstacle_height"].as<double>(2.0);
  const double obstacle_range = source["obstacle_range"].as<double>(2.5);
  const double raytrace_range = source["raytrace_range"].as<double>(3.0);
  for (double z : {-20.0, -0.5, 0.0, 0.5, 20.0}) {  // m of the road in odom (a long grade)
    for (double x : {3.0, 20.0, Params().lane_grid_length}) {
      const double p[3] = {x, 1.75, z};
      // ObservationBuffer::bufferCloud(): the source's band; ObstacleLayer: its ceiling and the
      // range from the sensor origin (base_link, on the road under the vehicle: same z)
      const bool kept = p[2] >= min_h && p[2] <= max_h && p[2] <= layer_max &&
                        std::hypot(p[0], p[1]) < obstacle_range;
      EXPECT_TRUE(kept) << "x " << x << " z " << z;
    }
  }
  EXPECT_GE(raytrace_range, obstacle_range) << "rays reach every marked point";
}

}  // namespace
}  // namespace rgbd_lane_detector
