// config/default.yaml is generated from the parameter tables: regenerated here and compared byte
// for byte; and what it sets is what a node without it would use.
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "../../../src/ros/default_parameter_file.h"
#include "rgbd_lane_detector/params_io.h"

namespace rgbd_lane_detector {
namespace {

std::string readDefaultYaml() {
  std::ifstream in(std::string(RLD_SOURCE_DIR) + "/config/default.yaml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(DefaultParameterFile, IsTheTablesByteForByte) {
  const std::string expected = defaultParameterFile();
  const std::string file = readDefaultYaml();
  EXPECT_EQ(file, expected) << "config/default.yaml differs from the parameter tables: "
                               "regenerate it with `rosrun rgbd_lane_detector "
                               "write_default_parameters > config/default.yaml`";
}

TEST(DefaultParameterFile, LoadingItChangesNoDetectorParameter) {
  const std::string text = defaultParameterFile();
  std::istringstream in(text);
  Params p = Params::paper();  // every improved value must come from the file
  std::string error;
  std::vector<std::string> ignored;
  ASSERT_TRUE(parseParamsYaml(in, "default.yaml", p, &error, &ignored)) << error;
  const Params improved;
  for (const std::string& name : paramNames()) {
    double a = 0, b = 0;
    ASSERT_TRUE(getParam(p, name, a));
    ASSERT_TRUE(getParam(improved, name, b));
    if (name == "up_x" || name == "up_y" || name == "up_z") continue;  // from up_frame, not a file
    EXPECT_EQ(a, b) << name;
  }
  // the node's own keys are there, not parameters of the detector
  const YAML::Node yaml = YAML::Load(text);
  EXPECT_TRUE(yaml["queue_size"]);
  EXPECT_TRUE(yaml["lane_model_frame"]);
  EXPECT_FALSE(yaml["mode"]);  // commented: given, it would override the preset of every key
  EXPECT_NE(text.find("# mode: improved"), std::string::npos);
}

}  // namespace
}  // namespace rgbd_lane_detector
