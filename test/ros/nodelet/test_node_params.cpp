// The nodelet's parameter table (src/ros/node_params.def) is the documentation: docs/NODELET.md's
// table of node parameters is regenerated from it and compared line by line, and
// config/default.yaml and docs/INTERFACE.md give every parameter with its default.
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "../../../src/ros/node_params.h"

namespace rgbd_lane_detector {
namespace {

struct Entry {
  std::string type, name, literal, description;
  /// The default as the docs show it: strings without their quotes ("" stays "").
  std::string shown() const {
    if (literal.size() > 2 && literal.front() == '"') return literal.substr(1, literal.size() - 2);
    return literal;
  }
};

const std::vector<Entry>& entries() {
  static const std::vector<Entry> table = {
#define RLD_NODE_PARAM(type, name, default_value, description) \
  {#type, #name, #default_value, description},
#include "../../../src/ros/node_params.def"
#undef RLD_NODE_PARAM
  };
  return table;
}

std::string read(const std::string& relative) {
  std::ifstream in(std::string(RLD_SOURCE_DIR) + "/" + relative);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(NodeParams, DefaultsAreTheTablesAndRepairsAreSaid) {
  const NodeParams p;
  EXPECT_EQ(p.queue_size, 10);
  EXPECT_EQ(p.lane_model_frame, "base_link");
  NodeParams bad;
  bad.queue_size = 0;
  bad.tf_timeout = -1.0;
  bad.max_sync_interval = -0.1;
  bad.max_frame_gap = -2.0;
  bad.target_frame = "/base_link";
  bad.odom_frame = "//odom";
  bad.up_frame = "/";
  bad.diagnostic_period = 0.0;
  const NodeParams fixed = bad.sanitized();
  EXPECT_EQ(fixed.queue_size, 1);
  EXPECT_EQ(fixed.tf_timeout, 0.0);
  EXPECT_EQ(fixed.max_sync_interval, 0.0);
  EXPECT_EQ(fixed.max_frame_gap, 0.0);
  EXPECT_EQ(fixed.target_frame, "base_link") << "tf2 refuses tf1's leading '/'";
  EXPECT_EQ(fixed.odom_frame, "odom");
  EXPECT_EQ(fixed.up_frame, "");
  EXPECT_EQ(fixed.lane_model_frame, "base_link");
  EXPECT_EQ(fixed.diagnostic_period, 0.05);
}

TEST(NodeParams, NodeletDocTableIsTheTable) {
  std::istringstream doc(read("docs/NODELET.md"));
  std::string line;
  while (std::getline(doc, line) && line != "Node (read at start-up):") {
  }
  ASSERT_TRUE(static_cast<bool>(doc)) << "docs/NODELET.md: no \"Node (read at start-up):\" table";
  std::vector<std::string> rows;
  while (std::getline(doc, line) && (line.empty() || line[0] == '|'))
    if (!line.empty()) rows.push_back(line);
  std::vector<std::string> expected = {"| name | default | meaning |", "| --- | --- | --- |"};
  for (const Entry& e : entries())
    expected.push_back("| `" + e.name + "` | " + e.shown() + " | " + e.description + " |");
  EXPECT_EQ(rows, expected) << "regenerate the table from src/ros/node_params.def";
  if (rows != expected)
    for (const std::string& r : expected) std::cout << r << "\n";
}

TEST(NodeParams, DefaultYamlGivesEveryParameterWithItsDefault) {
  const std::string text = read("config/default.yaml");
  const YAML::Node yaml = YAML::Load(text);
  for (const Entry& e : entries()) {
    if (e.name == "mode") {  // given, it would override every preset value: shown commented
      EXPECT_NE(text.find("# mode: " + e.shown()), std::string::npos);
      continue;
    }
    ASSERT_TRUE(yaml[e.name]) << "config/default.yaml lacks " << e.name;
    if (e.type == "std::string")
      EXPECT_EQ(yaml[e.name].as<std::string>(), e.shown() == "\"\"" ? "" : e.shown()) << e.name;
    else if (e.type == "bool")
      EXPECT_EQ(yaml[e.name].as<bool>(), e.literal == "true") << e.name;
    else
      EXPECT_DOUBLE_EQ(yaml[e.name].as<double>(), std::stod(e.literal)) << e.name;
  }
}

TEST(NodeParams, InterfaceListsEveryParameterWithItsDefault) {
  const std::string text = read("docs/INTERFACE.md");
  for (const Entry& e : entries())
    EXPECT_NE(text.find("`" + e.name + "` (" + e.shown()), std::string::npos)
        << "docs/INTERFACE.md: `" << e.name << "` (" << e.shown() << ")";
}

}  // namespace
}  // namespace rgbd_lane_detector
