// Detector parameter files (ROS-style YAML without a directive).
#include <cstdio>

#include <gtest/gtest.h>

#include "rgbd_lane_detector_tools/params_io.h"
#include "temp_file.h"

namespace rgbd_lane_detector {
namespace tools {
namespace {

TEST(ParamsIo, YamlOverridesWithCommentsBoolsAndEnums) {
  const std::string path = writeTempFile("rgbd_params.yaml",
                                     "# lane detector\n"
                                     "tau_c: 120  # grey threshold\n"
                                     "use_depth: false\n"
                                     "alpha: 0.25\n"
                                     "depth_term: far_high\n"
                                     "plane_fit: 1\n"
                                     "no_such_param: 3\n"
                                     "lane_detector:\n"
                                     "  jump_step: 7\n");
  Params p = Params::paper();
  std::string error;
  std::vector<std::string> warnings;
  ASSERT_TRUE(loadParamsYaml(path, p, error, &warnings)) << error;
  EXPECT_EQ(p.tau_c, 120);
  EXPECT_FALSE(p.use_depth);
  EXPECT_DOUBLE_EQ(p.alpha, 0.25);
  EXPECT_EQ(p.depth_term, DepthTerm::kFarHigh);
  EXPECT_EQ(p.plane_fit, PlaneFit::kLeastSquares);
  EXPECT_EQ(p.jump_step, 7);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("no_such_param"), std::string::npos);
  std::remove(path.c_str());
}

TEST(ParamsIo, BadValuesAndFilesAreErrors) {
  Params p = Params::paper();
  const Params before = p;
  std::string error;
  const std::string bad = writeTempFile("rgbd_params_bad.yaml", "alpha: 0.3\ntau_c: abc\n");
  EXPECT_FALSE(loadParamsYaml(bad, p, error));
  EXPECT_NE(error.find("tau_c"), std::string::npos);
  EXPECT_EQ(p.alpha, before.alpha);  // nothing applied on error
  std::remove(bad.c_str());
  EXPECT_FALSE(loadParamsYaml("/nonexistent/params.yaml", p, error));
  EXPECT_NE(error.find("/nonexistent/params.yaml"), std::string::npos);
  EXPECT_FALSE(setParam(p, "use_depth", "maybe", error));
  EXPECT_FALSE(setParam(p, "depth_term", "sideways", error));
  EXPECT_FALSE(setParam(p, "unknown", "1", error));
  EXPECT_TRUE(setParam(p, "road_gate", "true", error));
  EXPECT_TRUE(p.road_gate);
}

TEST(ParamsIo, YamlRoundTrip) {
  Params p = Params::improved();
  p.tau_c = 111;
  p.beta = 0.123;
  p.use_depth = false;
  const std::string path = writeTempFile("rgbd_params_rt.yaml", paramsToYaml(p));
  Params back = Params::paper();
  std::string error;
  ASSERT_TRUE(loadParamsYaml(path, back, error)) << error;
  EXPECT_EQ(paramsToYaml(back), paramsToYaml(p));
  std::remove(path.c_str());
}

}  // namespace
}  // namespace tools
}  // namespace rgbd_lane_detector
