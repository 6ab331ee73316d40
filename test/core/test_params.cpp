// Parameters: names match cfg/LaneDetector.cfg, sanitising, YAML files.
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/params_io.h"

#ifndef RLD_SOURCE_DIR
#error "RLD_SOURCE_DIR must point at the package source"
#endif

namespace rgbd_lane_detector {
namespace {

// The entries of params.def (the table the .cfg reads): name -> group.
std::map<std::string, std::string> tableEntries() {
  std::ifstream in(std::string(RLD_SOURCE_DIR) + "/include/rgbd_lane_detector/params.def");
  std::map<std::string, std::string> entries;
  const std::regex re(R"(^RLD_PARAM\((\w+), \w+, (\w+), )");
  std::string line;
  std::smatch m;
  while (std::getline(in, line))
    if (std::regex_search(line, m, re)) entries[m[2]] = m[1];
  return entries;
}

TEST(Params, EveryFieldIsADynamicReconfigureParameter) {
  const std::map<std::string, std::string> table = tableEntries();
  ASSERT_GT(table.size(), 20u);
  std::set<std::string> reconfigurable;
  for (const auto& [name, group] : table)
    if (group != "none") reconfigurable.insert(name);
  std::set<std::string> fields(paramNames().begin(), paramNames().end());
  EXPECT_EQ(fields.size(), table.size());
  // the up axis comes from the camera or tf, not from the reconfigure GUI
  for (const char* n : {"up_x", "up_y", "up_z"}) {
    EXPECT_EQ(fields.erase(n), 1u);
    EXPECT_EQ(table.at(n), "none");
  }
  EXPECT_EQ(reconfigurable, fields);
  for (const char* n : {"tau_c", "template_size", "template_line_width", "normal_window",
                        "depth_threshold", "alpha", "beta", "tau_g", "pca_threshold",
                        "jump_step", "roi_top", "processing_scale", "depth_term", "use_depth"})
    EXPECT_TRUE(reconfigurable.count(n)) << n;  // the names INTERFACE.md promises
}

TEST(Params, SetAndGetRoundTripForEveryName) {
  for (const std::string& name : paramNames()) {
    Params p;
    double v0 = -1;
    ASSERT_TRUE(getParam(p, name, v0)) << name;
    const double v1 = (v0 == 0.0) ? 1.0 : (v0 == 1.0 ? 0.0 : v0 + 1.0);
    ASSERT_TRUE(setParam(p, name, v1)) << name;
    double back = -1;
    ASSERT_TRUE(getParam(p, name, back));
    EXPECT_DOUBLE_EQ(back, v1) << name;
  }
  Params p;
  double v;
  EXPECT_FALSE(setParam(p, "no_such_parameter", 1.0));
  EXPECT_FALSE(getParam(p, "no_such_parameter", v));
}

// Params{} is the improved preset; Params::paper() keeps the paper's values (METHOD.md).
TEST(Params, DefaultsAreTheImprovedPresetAndPaperIsThePapers) {
  const Params d;
  EXPECT_EQ(d.plane_fit, PlaneFit::kRoadSurface);
  EXPECT_EQ(d.gap_steps, 12);
  EXPECT_TRUE(d.lane_model);
  EXPECT_TRUE(d.classify_boundaries);
  EXPECT_EQ(d.boundary_candidates, 3);
  EXPECT_FALSE(d.report_only_complete);
  Params by_name;
  ASSERT_TRUE(paramsForMode("improved", by_name));
  EXPECT_EQ(by_name.plane_fit, d.plane_fit);
  EXPECT_EQ(by_name.acquisition_angle_deg, d.acquisition_angle_deg);

  const Params p = Params::paper();
  EXPECT_EQ(p.template_size, 32);
  EXPECT_EQ(p.normal_window, 5);
  EXPECT_DOUBLE_EQ(p.depth_threshold, 20.0);
  EXPECT_DOUBLE_EQ(p.alpha, 0.4);
  EXPECT_DOUBLE_EQ(p.beta, 0.1);
  EXPECT_DOUBLE_EQ(p.tau_g, 0.5);
  EXPECT_EQ(p.jump_step, 5);
  EXPECT_DOUBLE_EQ(p.pca_threshold, 0.75);
  EXPECT_EQ(p.tau_c, 100);
  EXPECT_FALSE(p.adaptive_tau_c);
  EXPECT_EQ(p.template_line_width, 10);
  EXPECT_EQ(p.plane_fit, PlaneFit::kThreePoint);
  EXPECT_EQ(p.gap_steps, 0);
  EXPECT_EQ(p.boundary_candidates, 1);
  EXPECT_FALSE(p.track_lanes);
  EXPECT_FALSE(p.lane_model);
  ASSERT_TRUE(paramsForMode("paper", by_name));
  EXPECT_EQ(by_name.plane_fit, PlaneFit::kThreePoint);
  EXPECT_FALSE(paramsForMode("fast", by_name));
  EXPECT_EQ(by_name.plane_fit, PlaneFit::kThreePoint) << "an unknown mode changes nothing";
}

TEST(Params, SanitiseRepairsOutOfRangeValues) {
  Params p;
  p.normal_window = 4;
  p.tau_c = 400;
  p.roi_top = 0.8;
  p.roi_bottom = 0.5;
  p.alpha = std::numeric_limits<double>::quiet_NaN();
  p.up_x = 0;
  p.up_y = 0;
  p.up_z = 0;
  p.template_line_width = 100;
  const Params s = sanitize(p);
  EXPECT_EQ(s.normal_window, 5);
  EXPECT_EQ(s.tau_c, 255);
  EXPECT_GT(s.roi_bottom, s.roi_top);
  EXPECT_DOUBLE_EQ(s.alpha, Params().alpha);
  EXPECT_DOUBLE_EQ(s.up_y, -1.0);
  EXPECT_LE(s.template_line_width, s.template_size);
  p = Params();
  p.normal_window = 9;
  EXPECT_EQ(sanitize(p).normal_window, 7);
  p = Params();  // a lane narrower than its minimum: the maximum is the minimum
  p.lane_width_min = 6.0;
  p.lane_width_max = 5.0;
  EXPECT_DOUBLE_EQ(sanitize(p).lane_width_max, 6.0);
  p.lane_width_max = 0.0;  // no lane width check
  EXPECT_DOUBLE_EQ(sanitize(p).lane_width_max, 0.0);
  // valid input comes back unchanged
  const Params d = sanitize(Params());
  EXPECT_EQ(d.normal_window, 5);
  EXPECT_DOUBLE_EQ(d.roi_top, Params().roi_top);
}

TEST(Params, LoadsFlatYamlFiles) {
  const std::string path = ::testing::TempDir() + "rld_params.yaml";
  {
    std::ofstream out(path);
    out << "# a parameter file\n"
           "tau_c: 120        # threshold\n"
           "use_depth: false\n"
           "depth_term: far_high\n"
           "plane_fit: least_squares\n"
           "alpha: 0.35\n"
           "mode: improved    # anywhere in the file\n"
           "queue_size: 5     # a node setting, ignored\n";
  }
  Params p;
  std::string err;
  ASSERT_TRUE(loadParamsYaml(path, p, &err)) << err;
  EXPECT_EQ(p.tau_c, 120);
  EXPECT_FALSE(p.use_depth);
  EXPECT_EQ(p.depth_term, DepthTerm::kFarHigh);
  EXPECT_EQ(p.plane_fit, PlaneFit::kLeastSquares);
  EXPECT_DOUBLE_EQ(p.alpha, 0.35);
  EXPECT_EQ(p.gap_steps, Params::improved().gap_steps);  // from the preset
  {
    std::ofstream out(path);
    out << "tau_c: lots\n";
  }
  Params q;
  EXPECT_FALSE(loadParamsYaml(path, q, &err));
  EXPECT_NE(err.find("tau_c"), std::string::npos);
  EXPECT_EQ(q.tau_c, Params().tau_c);
  EXPECT_FALSE(loadParamsYaml("/nonexistent/file.yaml", q, &err));
}

// Every enum value's name in param_enums.def is what a parameter file takes, and gives the value
// the table states (the table is also what dynamic_reconfigure offers).
TEST(Params, EnumNamesComeFromTheirTable) {
  std::ifstream in(std::string(RLD_SOURCE_DIR) + "/include/rgbd_lane_detector/param_enums.def");
  const std::regex re(R"(^RLD_ENUM\((\w+), (\w+), (\w+), (\d+), ")");
  const std::map<std::string, std::string> field = {{"DepthTerm", "depth_term"},
                                                    {"PlaneFit", "plane_fit"}};
  std::string line;
  std::smatch m;
  int entries = 0;
  while (std::getline(in, line)) {
    if (!std::regex_search(line, m, re)) continue;
    ++entries;
    ASSERT_TRUE(field.count(m[1])) << line;
    Params p;
    std::string err;
    ASSERT_TRUE(setParamText(p, field.at(m[1]), m[3], &err)) << err;
    double v = -1;
    ASSERT_TRUE(getParam(p, field.at(m[1]), v));
    EXPECT_EQ(v, std::stod(m[4])) << m[3];
  }
  EXPECT_EQ(entries, 5);
  Params p;
  std::string err;
  EXPECT_FALSE(setParamText(p, "plane_fit", "sideways", &err));
}

// A ROS parameter file read with yaml-cpp: a node's namespace, non-parameters listed, YAML
// errors and non-scalar values reported with their line, nothing applied on error.
TEST(Params, YamlFilesWithNamespacesAndErrors) {
  std::istringstream nested(
      "lane_detector:\n"
      "  queue_size: 5\n"
      "  tau_c: 90\n"
      "  plane_fit: three_point\n"
      "other: {jump_step: 9}\n");
  Params p;
  std::string err;
  std::vector<std::string> ignored;
  ASSERT_TRUE(parseParamsYaml(nested, "nested", p, &err, &ignored)) << err;
  EXPECT_EQ(p.tau_c, 90);
  EXPECT_EQ(p.plane_fit, PlaneFit::kThreePoint);
  EXPECT_EQ(p.jump_step, 9);
  EXPECT_EQ(ignored, std::vector<std::string>{"queue_size"});

  std::istringstream list("tau_c: 70\nalpha: [1, 2]\n");
  Params q;
  EXPECT_FALSE(parseParamsYaml(list, "list.yaml", q, &err));
  EXPECT_NE(err.find("list.yaml:2"), std::string::npos) << err;
  EXPECT_EQ(q.tau_c, Params().tau_c);

  std::istringstream broken("tau_c: [70\n");
  EXPECT_FALSE(parseParamsYaml(broken, "broken.yaml", q, &err));
  EXPECT_NE(err.find("broken.yaml"), std::string::npos);

  std::istringstream scalar("just text\n");
  EXPECT_FALSE(parseParamsYaml(scalar, "scalar.yaml", q, &err));

  std::istringstream mode("tau_c: 80\nmode: sideways\n");
  EXPECT_FALSE(parseParamsYaml(mode, "mode.yaml", q, &err));
  EXPECT_NE(err.find("sideways"), std::string::npos);

  std::istringstream empty("");
  EXPECT_TRUE(parseParamsYaml(empty, "empty.yaml", q, &err));
  EXPECT_EQ(q.tau_c, Params().tau_c);
}

// fuzz_readers: "template_size: 2444...4" (2.4e46) in a parameter file cast a double outside
// the int range to int (undefined behaviour; INT_MIN on x86, so the template became the
// smallest instead of the largest). Integer fields now saturate, NaN leaves them unchanged.
TEST(Params, OutOfRangeNumbersSaturateIntegerFields) {
  Params p;
  std::string err;
  ASSERT_TRUE(setParamText(p, "template_size", std::string(48, '4'), &err)) << err;
  EXPECT_EQ(p.template_size, std::numeric_limits<int>::max());
  EXPECT_EQ(sanitize(p).template_size, 256);
  ASSERT_TRUE(setParamText(p, "jump_step", "-1e300", &err)) << err;
  EXPECT_EQ(p.jump_step, std::numeric_limits<int>::min());
  EXPECT_EQ(sanitize(p).jump_step, 1);
  ASSERT_TRUE(setParam(p, "plane_fit", 1e20));
  EXPECT_EQ(static_cast<int>(p.plane_fit), std::numeric_limits<int>::max());
  EXPECT_EQ(sanitize(p).plane_fit, Params().plane_fit);
  Params q;
  ASSERT_TRUE(setParam(q, "tau_c", std::numeric_limits<double>::quiet_NaN()));
  EXPECT_EQ(q.tau_c, Params().tau_c);
  ASSERT_TRUE(setParam(q, "tau_c", 120.9));  // in range: truncated as before
  EXPECT_EQ(q.tau_c, 120);

  std::istringstream yaml("template_size: " + std::string(48, '4') + "\n");
  Params r;
  ASSERT_TRUE(parseParamsYaml(yaml, "test", r, &err)) << err;
  EXPECT_EQ(sanitize(r).template_size, 256);
}

}  // namespace
}  // namespace rgbd_lane_detector
