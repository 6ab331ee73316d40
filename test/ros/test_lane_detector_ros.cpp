// rostest of the lane detector nodelet, run against the standalone node
// (lane_detector_node.test) and the nodelet in a manager (lane_detector_nodelet.test), with the
// harness of ros_harness.h.
//
// Private parameters: those of the harness, ~default_yaml/ (config/default.yaml loaded for a
// coverage check).
#include "ros_harness.h"

namespace rgbd_lane_detector {
namespace {

using namespace ros_test;  // NOLINT: the harness of this test

// ---------------------------------------------------------------------------------------------
// Declared first: it needs the time before the static transform is broadcast.
TEST(LaneDetectorRos, MissingTransformSkipsFramesWithWarning) {
  if (g->target_frame.empty() || g->tf_sent)
    GTEST_SKIP() << "needs ~target_frame and no transform yet";
  Outputs out;
  out.plane.subscribe(g->nh, "lane_plane");
  ASSERT_TRUE(waitFor(
      [] { return g->logContains(rosgraph_msgs::Log::WARN, "Skipping frame", "transform"); },
      [&] { g->publishPaced(out.plane); }))
      << "no throttled warning about the missing transform";
  EXPECT_EQ(out.plane.size(), 0u) << "a frame was published without its transform";
  g->broadcastTransform();
  const ros::Time after = g->last_stamp;
  EXPECT_TRUE(waitFor(
      [&] { return out.plane.find([&](const LanePlane& m) { return m.header.stamp > after; }); },
      [&] { g->publishPaced(out.plane); }))
      << "frames still skipped once the transform exists";
}

TEST(LaneDetectorRos, DefaultYamlCoversEveryParameter) {
  ros::NodeHandle yaml("~default_yaml");
  const LaneDetectorConfig& def = LaneDetectorConfig::__getDefault__();
  dynamic_reconfigure::Config def_msg;
  def.__toMessage__(def_msg);
  for (const auto& b : def_msg.bools) {
    bool v;
    ASSERT_TRUE(yaml.getParam(b.name, v)) << "config/default.yaml lacks " << b.name;
    EXPECT_EQ(v, static_cast<bool>(b.value)) << b.name;
  }
  for (const auto& i : def_msg.ints) {
    int v;
    ASSERT_TRUE(yaml.getParam(i.name, v)) << "config/default.yaml lacks " << i.name;
    EXPECT_EQ(v, i.value) << i.name;
  }
  for (const auto& d : def_msg.doubles) {
    double v;
    ASSERT_TRUE(yaml.getParam(d.name, v)) << "config/default.yaml lacks " << d.name;
    EXPECT_DOUBLE_EQ(v, d.value) << d.name;
  }
}

// Without a mode (a bare `rosrun rgbd_lane_detector lane_detector_node`) the detector runs the
// improved preset, like with `mode: improved`: its parameters on the server are Params{}'s.
TEST(LaneDetectorRos, RunsTheImprovedPresetByDefault) {
  g->prepare();
  std::string mode = "(unset)";
  ros::param::get(g->detector + "/mode", mode);
  if (mode == "paper") GTEST_SKIP() << "this detector was started with mode: paper";
  const Params improved;
  int plane_fit = -1, gap_steps = -1, candidates = -1;
  bool lane_model = false, classify = false;
  // The node writes its parameters one setParam at a time while it starts (and the test may
  // run meanwhile, e.g. on a loaded machine): wait until every one read here is on the server.
  const std::string& d = g->detector;
  ASSERT_TRUE(waitFor([&] {
    return ros::param::get(d + "/plane_fit", plane_fit) &&
           ros::param::get(d + "/gap_steps", gap_steps) &&
           ros::param::get(d + "/boundary_candidates", candidates) &&
           ros::param::get(d + "/lane_model", lane_model) &&
           ros::param::get(d + "/classify_boundaries", classify);
  })) << "the detector's parameters never all reached the parameter server";
  EXPECT_EQ(plane_fit, static_cast<int>(improved.plane_fit)) << "mode " << mode;
  EXPECT_EQ(gap_steps, improved.gap_steps) << "mode " << mode;
  EXPECT_EQ(candidates, improved.boundary_candidates) << "mode " << mode;
  EXPECT_TRUE(lane_model) << "mode " << mode;
  EXPECT_TRUE(classify) << "mode " << mode;
}

// Detector parameters given as text (enum_parameters.test: `depth_term: far_high`, as the README
// and parameter files name the enums; `plane_fit: three_points`, no value of it) are on the server
// as the integers dynamic_reconfigure reads: it would ignore the strings without a word and keep
// its own defaults, here depth_term 0. The expected values are the test's ~expected_* parameters
// (elsewhere the mode's preset, which the node writes as integers itself).
TEST(LaneDetectorRos, EnumParametersGivenByNameBecomeTheirValues) {
  g->prepare();
  std::string mode = "(unset)";
  ros::param::get(g->detector + "/mode", mode);
  const Params preset = mode == "paper" ? Params::paper() : Params::improved();
  ros::NodeHandle pnh("~");
  int expected_depth_term = 0, expected_plane_fit = 0;
  pnh.param("expected_depth_term", expected_depth_term, static_cast<int>(preset.depth_term));
  pnh.param("expected_plane_fit", expected_plane_fit, static_cast<int>(preset.plane_fit));
  int plane_fit = -1, depth_term = -1;
  const std::string& d = g->detector;
  ASSERT_TRUE(waitFor([&] {
    return ros::param::get(d + "/plane_fit", plane_fit) &&
           ros::param::get(d + "/depth_term", depth_term);
  })) << "plane_fit and depth_term never both reached the parameter server as integers";
  EXPECT_EQ(depth_term, expected_depth_term) << "mode " << mode;
  EXPECT_EQ(plane_fit, expected_plane_fit) << "mode " << mode;
}

TEST(LaneDetectorRos, LazySubscription) {
  g->prepare();
  // the detector is up (outputs advertised) but nobody listens: no input subscriptions
  ASSERT_TRUE(waitFor([] {
    ros::master::V_TopicInfo topics;
    ros::master::getTopics(topics);
    return std::any_of(topics.begin(), topics.end(), [](const ros::master::TopicInfo& t) {
      return t.name == g->nh.resolveName("lane_plane");
    });
  })) << "detector never advertised lane_plane";
  ASSERT_TRUE(waitFor([] { return inputsSubscribed(false); }))
      << "inputs subscribed with no output subscriber";

  Outputs out;
  const std::vector<std::pair<std::string, std::function<void(bool)>>> outputs = {
      {"lane_plane",
       [&](bool on) { on ? out.plane.subscribe(g->nh, "lane_plane") : out.plane.shutdown(); }},
      {"lane_points",
       [&](bool on) { on ? out.points.subscribe(g->nh, "lane_points") : out.points.shutdown(); }},
      {"debug_image",
       [&](bool on) { on ? out.debug.subscribe(g->nh, "debug_image") : out.debug.shutdown(); }},
      {"lane_model",
       [&](bool on) { on ? out.model.subscribe(g->nh, "lane_model") : out.model.shutdown(); }},
      {"lane_centre_line", [&](bool on) {
         on ? out.centre.subscribe(g->nh, "lane_centre_line") : out.centre.shutdown();
       }},
      {"lane_grid",
       [&](bool on) { on ? out.grid.subscribe(g->nh, "lane_grid") : out.grid.shutdown(); }},
      {"response/geometric", [&](bool on) {
         on ? out.geometric.subscribe(g->nh, "response/geometric") : out.geometric.shutdown();
       }}};
  for (const auto& output : outputs) {
    output.second(true);
    EXPECT_TRUE(waitFor([] { return inputsSubscribed(true); }))
        << "subscribing to " << output.first << " did not subscribe the inputs";
    output.second(false);
    EXPECT_TRUE(waitFor([] { return inputsSubscribed(false); }))
        << "inputs still subscribed after " << output.first << " lost its subscriber";
  }
}

TEST(LaneDetectorRos, SyntheticRoadGivesEveryOutput) {
  g->prepare();
  Outputs out;
  out.subscribeAll(g->nh);
  // a stamp for which every output arrived and the plane is valid
  ros::Time stamp;
  auto complete = [&] {
    auto plane = out.plane.find([&](const LanePlane& m) {
      return m.valid && out.markings.withStamp(m.header.stamp) &&
             out.points.withStamp(m.header.stamp) && out.markers.withStamp(m.header.stamp) &&
             out.left.withStamp(m.header.stamp) && out.right.withStamp(m.header.stamp) &&
             out.geometric.withStamp(m.header.stamp) && out.debug.withStamp(m.header.stamp) &&
             out.model.withStamp(m.header.stamp) && out.centre.withStamp(m.header.stamp);
    });
    if (plane) stamp = plane->header.stamp;
    return static_cast<bool>(plane);
  };
  ASSERT_TRUE(waitFor(complete, [&] { g->publishPaced(out.plane); }))
      << "not every output arrived with a valid plane";

  const std::string frame = g->outputFrame();
  Eigen::Vector3d n_true;
  double d_true;
  g->planeTruth(n_true, d_true);
  auto planeDistance = [&](double x, double y, double z) {
    return n_true.dot(Eigen::Vector3d(x, y, z)) + d_true;
  };

  // lane_plane
  const auto plane = out.plane.withStamp(stamp);
  EXPECT_EQ(plane->header.frame_id, frame);
  expectPlaneNearTruth(*plane);
  EXPECT_FALSE(plane->support_points.empty());
  for (const auto& p : plane->support_points)
    EXPECT_LT(std::fabs(planeDistance(p.x, p.y, p.z)), 0.05);
  EXPECT_GT(plane->left_score, 0.f);
  EXPECT_GT(plane->right_score, 0.f);

  // lane_markings: left and right marker centre lines, near to far
  const auto markings = out.markings.withStamp(stamp);
  EXPECT_EQ(markings->header.frame_id, frame);
  ASSERT_GE(markings->left.size(), 2u);
  ASSERT_GE(markings->right.size(), 2u);
  for (const auto& p : markings->left) EXPECT_NEAR(g->lateral(p), g->scene.leftMarkerX(), 0.2);
  for (const auto& p : markings->right) EXPECT_NEAR(g->lateral(p), g->scene.rightMarkerX(), 0.2);
  EXPECT_LT(g->forward(markings->left.front()), g->forward(markings->left.back()));
  EXPECT_LT(g->forward(markings->right.front()), g->forward(markings->right.back()));
  EXPECT_GT(markings->left_score, 0.f);
  EXPECT_GT(markings->right_score, 0.f);

  // lane_points: one point per marking point, with score and side
  const auto cloud = out.points.withStamp(stamp);
  EXPECT_EQ(cloud->header.frame_id, frame);
  EXPECT_EQ(cloud->height, 1u);
  ASSERT_EQ(cloud->width, markings->left.size() + markings->right.size());
  sensor_msgs::PointCloud2ConstIterator<float> x(*cloud, "x"), y(*cloud, "y"), z(*cloud, "z"),
      s(*cloud, "score");
  sensor_msgs::PointCloud2ConstIterator<uint8_t> side(*cloud, "side");
  size_t lefts = 0;
  for (uint32_t i = 0; i < cloud->width; ++i, ++x, ++y, ++z, ++s, ++side) {
    EXPECT_LT(std::fabs(planeDistance(*x, *y, *z)), 0.05);
    EXPECT_GT(*s, 0.f);
    ASSERT_LE(*side, 1u);
    lefts += *side == 0;
  }
  EXPECT_EQ(lefts, markings->left.size());

  // lane_visualization
  const auto markers = out.markers.withStamp(stamp);
  // the plane and both markings in the target frame, then one line per lane-model position
  // (rgbd_lane_detector::kNumBoundaryPositions) in the lane model's frame
  ASSERT_EQ(markers->markers.size(), 3u + rgbd_lane_detector::kNumBoundaryPositions);
  double max_frame_gap = 1.0;  // the markers live as long as the lane is kept unseen
  ros::param::get(g->detector + "/max_frame_gap", max_frame_gap);
  for (size_t i = 0; i < 3; ++i) {
    const auto& m = markers->markers[i];
    EXPECT_EQ(m.header.frame_id, frame);
    EXPECT_EQ(m.action, visualization_msgs::Marker::ADD) << m.ns << " " << m.id;
  }
  for (const auto& m : markers->markers)
    EXPECT_EQ(m.lifetime, ros::Duration(max_frame_gap)) << m.ns << " " << m.id;
  int model_lines = 0;
  for (size_t i = 3; i < markers->markers.size(); ++i) {
    const auto& m = markers->markers[i];
    EXPECT_EQ(m.ns, conversions::kModelNs);
    model_lines += m.action == visualization_msgs::Marker::ADD;
  }
  std::string mode;
  ros::param::param<std::string>(g->detector + "/mode", mode, "improved");
  if (mode == "improved") EXPECT_GE(model_lines, 2) << "the ego lane's two boundaries";
  else EXPECT_EQ(model_lines, 0) << "paper mode tracks no lane model";
  EXPECT_EQ(markers->markers[0].type, visualization_msgs::Marker::TRIANGLE_LIST);
  EXPECT_EQ(markers->markers[1].type, visualization_msgs::Marker::LINE_STRIP);

  // images: the camera's optical frame, 32FC1 maps at the processing resolution, bgr8 overlay
  for (auto* c : {&out.left, &out.right, &out.geometric}) {
    const auto img = c->withStamp(stamp);
    EXPECT_EQ(img->header.frame_id, kOpticalFrame);
    EXPECT_EQ(img->encoding, "32FC1");
    EXPECT_EQ(img->width, static_cast<uint32_t>(g->scene.width));
    EXPECT_EQ(img->height, static_cast<uint32_t>(g->scene.height));
    double max_v = 0;
    cv::minMaxLoc(cv_bridge::toCvShare(img)->image, nullptr, &max_v);
    EXPECT_GT(max_v, 0.0);
  }
  const auto debug = out.debug.withStamp(stamp);
  EXPECT_EQ(debug->header.frame_id, kOpticalFrame);
  EXPECT_EQ(debug->encoding, "bgr8");
  EXPECT_EQ(debug->width, static_cast<uint32_t>(g->scene.width));
  EXPECT_EQ(debug->height, static_cast<uint32_t>(g->scene.height));
}

// The lane model planners consume, against the rendered road: the vehicle 0.3 m right of the
// centre of a 3.6 m lane, a dashed white line on the left and a solid one on the right, straight
// and level. Every frame is answered on lane_model with the image's stamp; after kModelFrames
// frames the model's geometry, labels, kinds and colours are the road's.
/// The detector's mode parameter (improved when unset).
std::string detectorMode() {
  std::string mode;
  ros::param::param<std::string>(g->detector + "/mode", mode, "improved");
  return mode;
}

/// The road of the lane-model tests: the vehicle 0.3 m right of the lane centre, the left line
/// dashed.
test::RoadScene laneScene() {
  test::RoadScene scene = g->scene;
  scene.lateral_offset = 0.3;  // + right of the lane centre
  scene.left_dashed = true;
  return scene;
}

TEST(LaneDetectorRos, LaneModelMatchesTheRoad) {
  g->prepare();
  if (detectorMode() == "paper") GTEST_SKIP() << "paper mode tracks no lane model";
  const test::RoadScene scene = laneScene();
  const InputSet in = g->inputsOf(scene);
  Outputs out;
  out.model.subscribe(g->nh, "lane_model");
  out.centre.subscribe(g->nh, "lane_centre_line");
  ASSERT_TRUE(waitFor([&] {
    return out.model.numPublishers() > 0 && out.centre.numPublishers() > 0 && inputsSubscribed(true);
  })) << "lane_model / lane_centre_line never connected";

  // frames one after another, each answered before the next (a frame the synchroniser loses is
  // sent again with a new stamp)
  constexpr int kModelFrames = 15;
  LaneModel::ConstPtr model;
  nav_msgs::Path::ConstPtr centre;
  int answered = 0;
  ASSERT_TRUE(waitFor([&] {
    const ros::Time stamp = g->publish(in);
    if (!waitFor([&] { return out.model.withStamp(stamp) && out.centre.withStamp(stamp); }, nullptr,
                 kPaceTimeout * 3))
      return false;
    model = out.model.withStamp(stamp);
    centre = out.centre.withStamp(stamp);
    return ++answered >= kModelFrames;
  })) << answered << " of " << kModelFrames << " frames answered on lane_model";

  // stamped with the image, in the model frame (base_link via tf, else the road frame)
  EXPECT_EQ(model->header.frame_id, g->modelFrame());
  EXPECT_EQ(model->centre_line.header.frame_id, g->modelFrame());
  EXPECT_EQ(model->centre_line.header.stamp, model->header.stamp);
  EXPECT_EQ(centre->header.stamp, model->header.stamp);
  EXPECT_EQ(centre->header.frame_id, model->header.frame_id);
  ASSERT_TRUE(model->valid);
  // REP-103: y left; the centre 0.3 m left of the vehicle, which is right of it (offset < 0)
  const double w = scene.lane_width, d = scene.lateral_offset;
  EXPECT_NEAR(model->width, w, 0.1);
  EXPECT_NEAR(model->lateral_offset, -d, 0.1);
  EXPECT_NEAR(model->heading_error, 0.0, 0.02);
  EXPECT_NEAR(model->curvature, 0.0, 1e-3);
  EXPECT_EQ(model->lane_changes, 0);
  ASSERT_EQ(model->boundaries.size(), 2u) << "two lines on the road: the ego lane's";
  const LaneBoundary* left = nullptr;
  const LaneBoundary* right = nullptr;
  for (const LaneBoundary& b : model->boundaries) {
    if (b.position == LaneBoundary::EGO_LEFT) left = &b;
    if (b.position == LaneBoundary::EGO_RIGHT) right = &b;
  }
  ASSERT_TRUE(left && right) << "ego_left and ego_right";
  const struct {
    const LaneBoundary* b;
    double c0;
    uint8_t kind;
  } expected[] = {{left, 0.5 * w + d, LaneBoundary::KIND_DASHED},
                  {right, -0.5 * w + d, LaneBoundary::KIND_SOLID}};
  for (const auto& e : expected) {
    const LaneBoundary& b = *e.b;
    SCOPED_TRACE(b.position == LaneBoundary::EGO_LEFT ? "ego_left" : "ego_right");
    EXPECT_NEAR(b.c0, e.c0, 0.1);
    EXPECT_NEAR(b.c1, 0.0, 0.02);
    EXPECT_NEAR(2.0 * b.c2, 0.0, 1e-3) << "curvature";
    EXPECT_NEAR(b.c0 + 20.0 * (b.c1 + 20.0 * (b.c2 + 20.0 * b.c3)), e.c0, 0.15) << "at 20 m";
    EXPECT_EQ(b.kind, e.kind);
    EXPECT_EQ(b.colour, LaneBoundary::COLOUR_WHITE);
    EXPECT_LT(b.x_min, 5.0);
    EXPECT_GT(b.x_max, 15.0);
    EXPECT_GT(b.confidence, 0.5f);
    EXPECT_LE(b.confidence, 1.0f);
    EXPECT_GT(b.lateral_std, 0.0f);
    EXPECT_LE(b.lateral_std, 0.15f);
  }
  // the centre line: near to far, midway between the two lines
  ASSERT_GE(model->centre_line.poses.size(), 2u);
  ASSERT_EQ(centre->poses.size(), model->centre_line.poses.size());
  double previous = -1.0;
  for (const auto& p : model->centre_line.poses) {
    EXPECT_GT(p.pose.position.x, previous);
    previous = p.pose.position.x;
    EXPECT_NEAR(p.pose.position.y, d, 0.15) << "at x = " << p.pose.position.x;
  }
}

// lane_grid on the same road as LaneModelMatchesTheRoad: every frame answered with the image's
// stamp in the lane model's frame, at the default size; after kGridFrames frames the true lines
// (2.1 m left and 1.5 m right of the vehicle) are occupied within one cell, the lane between them
// free, the cells half a metre beyond them not free. Paper mode (no lane model): all unknown.
TEST(LaneDetectorRos, LaneGridMatchesTheRoad) {
  g->prepare();
  const std::string mode = detectorMode();
  const test::RoadScene scene = laneScene();
  const InputSet in = g->inputsOf(scene);
  Outputs out;
  out.grid.subscribe(g->nh, "lane_grid");
  ASSERT_TRUE(waitFor([&] { return out.grid.numPublishers() > 0 && inputsSubscribed(true); }))
      << "lane_grid never connected";
  constexpr int kGridFrames = 15;
  nav_msgs::OccupancyGrid::ConstPtr grid;
  int answered = 0;
  ros::Time stamp;
  ASSERT_TRUE(waitFor([&] {
    stamp = g->publish(in);
    if (!waitFor([&] { return static_cast<bool>(out.grid.withStamp(stamp)); }, nullptr,
                 kPaceTimeout * 3))
      return false;
    grid = out.grid.withStamp(stamp);
    return ++answered >= kGridFrames;
  })) << answered << " of " << kGridFrames << " frames answered on lane_grid";

  EXPECT_EQ(grid->header.stamp, stamp);
  EXPECT_EQ(grid->header.frame_id, g->modelFrame());
  EXPECT_FLOAT_EQ(grid->info.resolution, 0.1f);
  ASSERT_EQ(grid->info.width, 400u);
  ASSERT_EQ(grid->info.height, 200u);
  ASSERT_EQ(grid->data.size(), 400u * 200u);
  EXPECT_DOUBLE_EQ(grid->info.origin.position.x, 0.0);
  EXPECT_DOUBLE_EQ(grid->info.origin.position.y, -10.0);
  EXPECT_DOUBLE_EQ(grid->info.origin.orientation.w, 1.0);
  auto cell = [&](double x, double y) {
    const int col = static_cast<int>(std::floor(x / 0.1));
    const int row = static_cast<int>(std::floor((y + 10.0) / 0.1));
    return grid->data[static_cast<size_t>(row) * grid->info.width + col];
  };
  if (mode == "paper") {
    for (int8_t v : grid->data) ASSERT_EQ(v, -1) << "paper mode tracks no lane model";
    return;
  }
  const double w = scene.lane_width, d = scene.lateral_offset;
  const double left = 0.5 * w + d, right = -0.5 * w + d;
  for (double x = 6.0; x <= 14.0; x += 2.0) {
    SCOPED_TRACE(testing::Message() << "x " << x);
    for (double y : {left, right}) {
      bool occupied = false;
      for (double dx : {-0.1, 0.0, 0.1})
        for (double dy : {-0.1, 0.0, 0.1}) occupied = occupied || cell(x + dx, y + dy) == 100;
      EXPECT_TRUE(occupied) << "the line at y " << y;
    }
    for (double y = right + 0.3; y <= left - 0.3; y += 0.1) EXPECT_EQ(cell(x, y), 0) << "y " << y;
    EXPECT_NE(cell(x, left + 0.5), 0) << "beyond the left line";
    EXPECT_NE(cell(x, right - 0.5), 0) << "beyond the right line";
  }
}

TEST(LaneDetectorRos, EveryColourEncodingAndFloatDepth) {
  g->prepare();
  Outputs out;
  out.plane.subscribe(g->nh, "lane_plane");
  struct Case {
    const char* encoding;
    int code;  // cvtColor code from bgr, -1: none
    bool float_depth;
  };
  const Case cases[] = {{"rgb8", cv::COLOR_BGR2RGB, true},
                        {"rgba8", cv::COLOR_BGR2RGBA, false},
                        {"bgra8", cv::COLOR_BGR2BGRA, true},
                        {"mono8", cv::COLOR_BGR2GRAY, false}};
  for (const Case& c : cases) {
    cv::Mat colour;
    cv::cvtColor(g->bgr, colour, c.code);
    const InputSet in = g->makeInputs(colour, c.encoding, c.float_depth ? g->depth_m : g->depth_mm,
                                      c.float_depth ? "32FC1" : "16UC1", g->scene.K);
    const ros::Time first = g->nextStamp();
    g->publish(in, first);
    ASSERT_TRUE(waitFor(
        [&] {
          return out.plane.find(
              [&](const LanePlane& m) { return m.header.stamp >= first && m.valid; });
        },
        [&] { g->publishPaced(out.plane, &in); }))
        << c.encoding << (c.float_depth ? " + 32FC1" : " + 16UC1") << ": no valid plane";
    expectPlaneNearTruth(
        *out.plane.find([&](const LanePlane& m) { return m.header.stamp >= first && m.valid; }));
  }
}

TEST(LaneDetectorRos, BadInputIsDroppedAndTheNodeSurvives) {
  g->prepare();
  Outputs out;
  out.plane.subscribe(g->nh, "lane_plane");
  ASSERT_TRUE(waitFor([&] { return out.plane.find([](const LanePlane& m) { return m.valid; }); },
                      [&] { g->publishPaced(out.plane); }));

  bool tracking = false;  // temporal lane model (improved mode): planes outlive a bad frame
  ros::param::get(g->detector + "/track_lanes", tracking);
  struct Case {
    std::string name;
    InputSet in;
    bool processed;  // true: published with valid = false; false: dropped (no output)
  };
  std::vector<Case> cases;
  const InputSet& good = g->good;
  auto add = [&](const std::string& name, bool processed,
                 const std::function<void(InputSet&)>& edit) {
    Case c{name, good, processed};
    edit(c.in);
    cases.push_back(c);
  };
  add("wrong colour encoding", false, [](InputSet& s) { s.colour.encoding = "rgb16"; });
  add("wrong depth encoding", false, [](InputSet& s) { s.depth.encoding = "8UC1"; });
  add("truncated colour data", false,
      [](InputSet& s) { s.colour.data.resize(s.colour.data.size() / 2); });
  add("depth step too small", false, [](InputSet& s) { s.depth.step = s.depth.width; });
  add("colour / depth size mismatch", false, [&](InputSet& s) {
    cv::Mat half;
    cv::resize(g->depth_mm, half, cv::Size(), 0.5, 0.5, cv::INTER_NEAREST);
    s.depth = g->makeInputs(g->bgr, "bgr8", half, "16UC1", g->scene.K).depth;
  });
  add("zero intrinsics", false, [](InputSet& s) {
    s.info.K.fill(0.0);
    s.info.P.fill(0.0);
  });
  add("empty images", false, [](InputSet& s) {
    for (sensor_msgs::Image* m : {&s.colour, &s.depth}) {
      m->width = m->height = m->step = 0;
      m->data.clear();
    }
    s.info.width = s.info.height = 0;
  });
  add("template larger than the image", false, [&](InputSet& s) {
    const cv::Rect crop(300, 340, 40, 30);
    Intrinsics K = g->scene.K;
    K.cx -= crop.x;
    K.cy -= crop.y;
    s = g->makeInputs(g->bgr(crop).clone(), "bgr8", g->depth_mm(crop).clone(), "16UC1", K);
  });
  add("all NaN depth", true, [&](InputSet& s) {
    const cv::Mat nan(g->depth_m.size(), CV_32FC1,
                      cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
    s.depth = g->makeInputs(g->bgr, "bgr8", nan, "32FC1", g->scene.K).depth;
  });
  add("all zero depth", true, [&](InputSet& s) {
    s.depth = g->makeInputs(g->bgr, "bgr8", cv::Mat::zeros(g->depth_mm.size(), CV_16UC1), "16UC1",
                            g->scene.K)
                  .depth;
  });
  add("huge depth", true, [&](InputSet& s) {
    const cv::Mat huge(g->depth_m.size(), CV_32FC1, cv::Scalar(1e30f));
    s.depth = g->makeInputs(g->bgr, "bgr8", huge, "32FC1", g->scene.K).depth;
  });

  for (const Case& c : cases) {
    const ros::Time bad = g->publish(c.in);
    // the node is alive and still detects: a valid plane for a later good frame
    ASSERT_TRUE(waitFor(
        [&] {
          return out.plane.find(
              [&](const LanePlane& m) { return m.header.stamp > bad && m.valid; });
        },
        [&] { g->publishPaced(out.plane); }))
        << c.name << ": no valid plane afterwards";
    const auto at_bad = out.plane.withStamp(bad);
    if (c.processed) {
      ASSERT_TRUE(static_cast<bool>(at_bad)) << c.name << ": frame not processed";
      // without depth there is no plane, unless a lane model carries the previous one
      if (!tracking) {
        EXPECT_FALSE(at_bad->valid) << c.name << ": a plane without valid depth";
      }
    } else {
      EXPECT_FALSE(static_cast<bool>(at_bad)) << c.name << ": bad frame was not dropped";
    }
  }
  // the drops are logged (first one; later ones are throttled) and counted in the diagnostics
  EXPECT_TRUE(waitFor([] { return g->logContains(rosgraph_msgs::Log::ERROR, "Dropping frame"); }));
  EXPECT_TRUE(waitFor(
      [] {
        return static_cast<bool>(g->diagnostics.find([](const diagnostic_msgs::DiagnosticArray& a) {
          for (const auto& s : a.status)
            for (const auto& kv : s.values)
              if (kv.key == "Frames dropped" && std::stoul(kv.value) >= 8) return true;
          return false;
        }));
      },
      [&] { g->publishPaced(out.plane); }))
      << "the diagnostics do not count the 8 dropped frames";
}

TEST(LaneDetectorRos, StampsGoingBackwardsResetTheDetector) {
  g->prepare();
  Outputs out;
  out.plane.subscribe(g->nh, "lane_plane");
  ASSERT_TRUE(waitFor([&] { return out.plane.find([](const LanePlane& m) { return m.valid; }); },
                      [&] { g->publishPaced(out.plane); }));
  const size_t lines_before = g->logCount(rosgraph_msgs::Log::WARN, "went back");
  const ros::Time back = g->last_stamp - ros::Duration(30.0);  // rosbag loop
  ASSERT_TRUE(
      waitFor([&] { return out.plane.withStamp(back); }, [&] { g->publish(g->good, back); }))
      << "the frame after the jump back was not processed";
  EXPECT_TRUE(waitFor([] {
    return g->logContains(rosgraph_msgs::Log::WARN, "went back", "reset the detector state");
  }));
  // frames after the jump go on (in the output frame: the static transform survived the reset)
  const ros::Time after = g->nextStamp();
  EXPECT_TRUE(waitFor(
      [&] {
        return out.plane.find(
            [&](const LanePlane& m) { return m.header.stamp >= after && m.valid; });
      },
      [&] { g->publishPaced(out.plane); }));
  EXPECT_EQ(g->logCount(rosgraph_msgs::Log::WARN, "went back"), lines_before + 1)
      << "one line per jump (the frame at the same stamp was sent several times)";
}

TEST(LaneDetectorRos, DynamicReconfigureAppliesFromTheNextFrame) {
  g->prepare();
  Outputs out;
  out.plane.subscribe(g->nh, "lane_plane");
  out.geometric.subscribe(g->nh, "response/geometric");
  auto maxOf = [](const sensor_msgs::Image& img) {
    double lo = 0, hi = 0;
    cv::minMaxLoc(cv_bridge::toCvCopy(img)->image, &lo, &hi);
    return std::max(std::fabs(lo), std::fabs(hi));
  };
  auto geometricAfter = [&](const ros::Time& t) {
    return out.geometric.find([&](const sensor_msgs::Image& m) { return m.header.stamp > t; });
  };
  ASSERT_TRUE(
      waitFor([&] { return geometricAfter(ros::Time(0)); }, [&] { g->publishPaced(out.plane); }));
  EXPECT_GT(maxOf(*geometricAfter(ros::Time(0))), 0.0) << "G is zero with use_depth on";

  // use_depth off: the first frame published afterwards has an all-zero G
  dynamic_reconfigure::Config applied;
  ASSERT_TRUE(setBool("use_depth", false, &applied));
  ros::Time t = g->last_stamp;
  ASSERT_TRUE(waitFor([&] { return geometricAfter(t); }, [&] { g->publishPaced(out.plane); }));
  EXPECT_EQ(maxOf(*geometricAfter(t)), 0.0) << "use_depth=false did not apply to the next frame";
  ASSERT_TRUE(setBool("use_depth", true));
  t = g->last_stamp;
  ASSERT_TRUE(waitFor([&] { return geometricAfter(t); }, [&] { g->publishPaced(out.plane); }));
  EXPECT_GT(maxOf(*geometricAfter(t)), 0.0);

  // processing_scale (a level-1 parameter: buffers are reallocated) resizes the next frame's maps
  auto leftAfter = [&](const ros::Time& after) {
    return out.left.find([&](const sensor_msgs::Image& m) { return m.header.stamp > after; });
  };
  out.left.subscribe(g->nh, "response/left");
  ASSERT_TRUE(setDouble("processing_scale", 0.5));
  t = g->last_stamp;
  ASSERT_TRUE(waitFor([&] { return leftAfter(t); }, [&] { g->publishPaced(out.plane); }));
  EXPECT_EQ(leftAfter(t)->width, static_cast<uint32_t>(g->scene.width / 2))
      << "processing_scale did not apply";
  EXPECT_EQ(leftAfter(t)->height, static_cast<uint32_t>(g->scene.height / 2));
  ASSERT_TRUE(setDouble("processing_scale", 1.0));
  t = g->last_stamp;
  ASSERT_TRUE(waitFor([&] { return leftAfter(t); }, [&] { g->publishPaced(out.plane); }));
  EXPECT_EQ(leftAfter(t)->width, static_cast<uint32_t>(g->scene.width));
  EXPECT_TRUE(waitFor(
      [&] {
        return out.plane.find([&](const LanePlane& m) { return m.header.stamp > t && m.valid; });
      },
      [&] { g->publishPaced(out.plane); }))
      << "no valid plane after restoring processing_scale";

  // sanitised values are reported back (the FALS window is odd)
  ASSERT_TRUE(setInt("normal_window", 4, &applied));
  int window = 0;
  for (const auto& i : applied.ints)
    if (i.name == "normal_window") window = i.value;
  EXPECT_EQ(window, 5);
  ASSERT_TRUE(setInt("normal_window", 5));
}

TEST(LaneDetectorRos, EveryInputFrameIsAccountedFor) {
  g->prepare();
  Outputs out;
  out.plane.subscribe(g->nh, "lane_plane");
  ASSERT_TRUE(waitFor([&] { return out.plane.find([](const LanePlane& m) { return m.valid; }); },
                      [&] { g->publishPaced(out.plane); }));
  // baseline: a report made after every frame published so far was answered
  ASSERT_TRUE(waitFor([&] { return out.plane.withStamp(g->last_published); },
                      [&] { g->publishPaced(out.plane); }));
  g->diagnostics.clear();
  std::map<std::string, std::string> base;
  auto latest = [&](std::map<std::string, std::string>& v) {
    std::map<std::string, std::string> last;
    g->diagnostics.find([&](const diagnostic_msgs::DiagnosticArray& a) {
      auto p = processingValues(a);
      if (!p.empty()) last = p;
      return false;
    });
    v = last;
    return !v.empty();
  };
  ASSERT_TRUE(waitFor([&] { return latest(base); })) << "no processing diagnostics";
  const uint64_t published_before = g->colour_published;
  // every colour frame published reached the nodelet or is counted as lost before it (roscpp
  // numbers header.seq per message sent: gaps are the losses)
  auto allReceived = [&] {
    std::map<std::string, std::string> v;
    return latest(v) && counter(v, "Frames received") - counter(base, "Frames received") +
                                counter(v, "Frames lost before the nodelet") -
                                counter(base, "Frames lost before the nodelet") ==
                            static_cast<long long>(g->colour_published - published_before);
  };

  InputSet wrong_encoding = g->good;
  wrong_encoding.colour.encoding = "rgb16";
  InputSet size_mismatch = g->good;
  cv::Mat half;
  cv::resize(g->depth_mm, half, cv::Size(), 0.5, 0.5, cv::INTER_NEAREST);
  size_mismatch.depth = g->makeInputs(g->bgr, "bgr8", half, "16UC1", g->scene.K).depth;
  for (int i = 0; i < 3; ++i) g->publish(wrong_encoding);
  ASSERT_TRUE(waitFor(allReceived)) << "wrong-encoding frames not received";
  for (int i = 0; i < 2; ++i) g->publish(size_mismatch);
  ASSERT_TRUE(waitFor(allReceived)) << "size-mismatch frames not received";
  // colour images without depth and camera_info: never synchronised, passed over by the next set
  auto publishColourOnly = [&](int n) {
    for (int i = 0; i < n; ++i) {
      auto colour = boost::make_shared<sensor_msgs::Image>(g->good.colour);
      colour->header.stamp = g->nextStamp();
      g->pub_colour.publish(colour);
      ++g->colour_published;
    }
  };
  publishColourOnly(4);
  for (int i = 0; i < 3; ++i) g->publish(g->good);
  ASSERT_TRUE(waitFor(allReceived)) << "unmatched colour frames not received";
  std::map<std::string, std::string> mid;
  ASSERT_TRUE(latest(mid));
  // a burst of 40 colour images may overflow the nodelet's subscriber queue (queue_size 10):
  // each one is then either received (and not synchronised) or lost before the nodelet
  publishColourOnly(40);
  g->publish(g->good);
  const ros::Time last_good = g->last_published;
  ASSERT_TRUE(waitFor([&] { return out.plane.withStamp(last_good); }))
      << "good frame after the bad ones not processed";
  std::map<std::string, std::string> end;
  ASSERT_TRUE(waitFor([&] {
    return allReceived() && latest(end) && counter(end, "Frames waiting") == 0;
  })) << "the frames sent are not all accounted for in the diagnostics";

  const auto delta = [&](const std::string& key, bool prefix = false) {
    return counter(end, key, prefix) - std::max(0LL, counter(base, key, prefix));
  };
  const long long sent = static_cast<long long>(g->colour_published - published_before);
  EXPECT_EQ(delta("Frames received") + delta("Frames lost before the nodelet"), sent);
  EXPECT_EQ(counter(mid, "Frames lost before the nodelet"),
            counter(base, "Frames lost before the nodelet"))
      << "frames lost while every group was waited for";
  EXPECT_EQ(delta("Dropped: unsupported colour encoding", true), 3);
  EXPECT_EQ(delta("Dropped: colour and depth images differ in size", true), 2);
  EXPECT_EQ(delta("Frames dropped"), 5);
  EXPECT_EQ(delta("Frames not synchronised") + delta("Frames lost before the nodelet"), 4 + 40);
  EXPECT_EQ(delta("Frames processed"), 4);
  EXPECT_EQ(delta("Frames skipped (no subscriber)"), 0);
  // depth and camera_info go out in pairs, never in a burst: none lost, as many of each
  EXPECT_EQ(delta("Depth images lost before the nodelet"), 0);
  EXPECT_EQ(delta("Camera infos lost before the nodelet"), 0);
  EXPECT_EQ(delta("Depth images received"), delta("Camera infos received"));
  EXPECT_GE(delta("Depth images received"), 4 + 5);  // the good sets and the dropped ones
  // the rule holds at every diagnostics update, not only at the end
  expectAccountingInEveryReport();
  for (const auto& kv : end)
    std::printf("  [accounting] %s: %s\n", kv.first.c_str(), kv.second.c_str());
}

TEST(LaneDetectorRos, DiagnosticsReportRateAndProcessingTime) {
  g->prepare();
  Outputs out;
  out.subscribeAll(g->nh);  // every output computed: the measured overhead is the full one
  auto value = [](const diagnostic_msgs::DiagnosticStatus& s, const std::string& key) {
    for (const auto& kv : s.values)
      if (kv.key == key) return std::atof(kv.value.c_str());
    return -1.0;
  };
  // a processing status whose window holds only frames of this test (all outputs subscribed):
  // 20 frames after the first report received here (each report starts a new window)
  g->diagnostics.clear();
  double processed_before = -1.0;
  diagnostic_msgs::DiagnosticStatus processing, rate;
  auto reported = [&] {
    auto array = g->diagnostics.find([&](const diagnostic_msgs::DiagnosticArray& a) {
      for (const auto& s : a.status) {
        if (s.name.find("processing") == std::string::npos) continue;
        const double n = value(s, "Frames processed");
        if (processed_before < 0) processed_before = n;  // first report seen by this test
        if (n >= processed_before + 20 && value(s, "Mean processing time (ms)") > 0.0) {
          processing = s;
          return true;
        }
      }
      return false;
    });
    if (!array) return false;
    for (const auto& s : array->status)
      if (s.name.find("output rate") != std::string::npos) rate = s;
    return true;
  };
  ASSERT_TRUE(waitFor(
      reported, [&] { g->publishPaced(out.plane); }, kTimeout, 0.05))
      << "no processing-time diagnostics while frames are processed";
  EXPECT_GT(value(processing, "Mean detector time (ms)"), 0.0);
  EXPECT_GE(value(processing, "Max processing time (ms)"),
            value(processing, "Mean processing time (ms)"));
  // one thread's CPU time within a callback is at most the callback's wall time (both printed
  // to 1 us)
  EXPECT_GT(value(processing, "Max processing CPU time (ms)"), 0.0);
  EXPECT_LE(value(processing, "Max processing CPU time (ms)"),
            value(processing, "Max processing time (ms)") + 0.001);
  EXPECT_GT(value(rate, "Actual frequency (Hz)"), 0.0) << "no output-rate diagnostics";
  for (const auto& kv : processing.values)
    std::printf("  [diagnostics, all outputs] %s: %s\n", kv.key.c_str(), kv.value.c_str());
}

// Declared last: the nodelet leaves its manager before the launch shuts down (the order that
// keeps the manager's exit clear of nodelet_core's bond use-after-free, docs/RELIABILITY.md), and
// unloading is checked (under ASan in make test-sanitize: the destructor runs instrumented).
TEST(LaneDetectorRos, UnloadsFromItsManager) {
  if (g->manager.empty()) GTEST_SKIP() << "standalone node: no manager";
  EXPECT_TRUE(unloadDetectorFromManager());
}

}  // namespace
}  // namespace rgbd_lane_detector

int main(int argc, char** argv) {
  return rgbd_lane_detector::ros_test::runTests(argc, argv, "test_lane_detector_ros");
}
