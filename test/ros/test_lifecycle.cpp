// rostests of the nodelet's life cycle, with the harness of ros_harness.h:
//  - lifecycle.test (suite Lifecycle): the nodelet in a manager, loaded by this test through
//    load_nodelet (no bond) and unloaded last: a configured image transport whose plugin is
//    missing, camera_info / images changing resolution mid-stream, the camera driver restarting,
//    the manager unloading and loading the nodelet again;
//  - looped_bag.test (suite LoopedBag, /use_sim_time): a generated bag played by
//    `rosbag play -l --clock` through the nodelet (loaded by `nodelet load`, with a bond).
// Private parameters: those of the harness, ~tools (folder of generate_sequence).
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include <image_transport/image_transport.h>
#include <rosgraph_msgs/Clock.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include "rgbd_lane_detector/lane_detector.h"
#include "ros_harness.h"

extern char** environ;

namespace rgbd_lane_detector {
namespace {

using namespace ros_test;  // NOLINT: the harness of this test

/// Nodes publishing @p topic, from the master.
std::vector<std::string> publishersOf(const std::string& topic) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  std::vector<std::string> nodes;
  if (!ros::master::execute("getSystemState", args, result, payload, true)) return nodes;
  XmlRpc::XmlRpcValue& publishers = payload[0];
  for (int i = 0; i < publishers.size(); ++i)
    if (static_cast<std::string>(publishers[i][0]) == topic)
      for (int k = 0; k < publishers[i][1].size(); ++k)
        nodes.push_back(static_cast<std::string>(publishers[i][1][k]));
  return nodes;
}

/// Run a shell command; its exit status (-1 if it did not exit normally) and output.
int runCommand(const std::string& command, std::string& output) {
  output.clear();
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  char buffer[512];
  while (fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// A child process started with posix_spawnp, interrupted (SIGINT, then SIGKILL) and reaped.
class Child {
 public:
  explicit Child(const std::vector<std::string>& argv) {
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    if (posix_spawnp(&pid_, args[0], nullptr, nullptr, args.data(), environ) != 0) pid_ = -1;
  }
  ~Child() { stop(); }
  bool running() const { return pid_ > 0; }
  void stop() {
    if (pid_ <= 0) return;
    kill(pid_, SIGINT);
    for (int i = 0; i < 100 && waitpid(pid_, nullptr, WNOHANG) == 0; ++i) usleep(100000);
    if (waitpid(pid_, nullptr, WNOHANG) == 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

/// The latest processing status of the detector (empty when none yet).
std::map<std::string, std::string> latestProcessing() {
  std::map<std::string, std::string> last;
  g->diagnostics.find([&](const diagnostic_msgs::DiagnosticArray& a) {
    const auto v = processingValues(a);
    if (!v.empty()) last = v;
    return false;
  });
  return last;
}

/// A valid plane answers a frame published at or after @p t (frames published meanwhile).
::testing::AssertionResult validPlaneFrom(Outputs& out, const ros::Time& t,
                                          const InputSet* in = nullptr) {
  if (waitFor(
          [&] {
            return out.plane.find(
                [&](const LanePlane& m) { return m.valid && m.header.stamp >= t; });
          },
          [&] { g->publishPaced(out.plane, in); }))
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "no valid plane for frames from " << t;
}

// ---------------------------------------------------------------------------------------------
// Lifecycle (lifecycle.test)

TEST(Lifecycle, MissingTransportPluginFailsAtStartUp) {
  // Debian ships no transport plugin but raw; where image_transport_plugins is installed, the
  // two named cases do not apply (the unknown transport still does).
  image_transport::ImageTransport it(g->nh);
  const std::vector<std::string> loadable = it.getLoadableTransports();
  auto isLoadable = [&](const std::string& t) {
    return std::any_of(loadable.begin(), loadable.end(), [&](const std::string& l) {
      return l.size() > t.size() &&
             l.compare(l.size() - t.size() - 1, std::string::npos, "/" + t) == 0;
    });
  };
  struct Case {
    const char* param;
    const char* transport;
    const char* package;  // named in the message ("" = no known package)
  };
  const Case cases[] = {
      {"image_transport", "compressed", "compressed_image_transport"},
      {"depth_image_transport", "compressedDepth", "compressed_depth_image_transport"},
      {"image_transport", "no_such_transport", ""}};
  // the manager's fatal line reaches the collector only over an established connection
  ASSERT_TRUE(waitFor([] { return g->rosoutConnected(); })) << "/rosout never connected";
  for (const Case& c : cases) {
    if (isLoadable(c.transport)) {
      std::printf("  [transport] %s is installed here: case skipped\n", c.transport);
      continue;
    }
    const std::string name = g->nh.resolveName(std::string("missing_") + c.transport);
    ros::param::set(name + "/" + c.param, std::string(c.transport));
    EXPECT_FALSE(g->loadDetector(name)) << c.transport << ": loaded without its plugin";
    EXPECT_TRUE(waitFor([&] {
      return g->logContains(rosgraph_msgs::Log::FATAL, std::string("'") + c.transport + "'",
                            std::string("~") + c.param) &&
             g->logContains(rosgraph_msgs::Log::FATAL, std::string("'") + c.transport + "'",
                            c.package);
    })) << c.transport
        << ": no fatal message naming the transport, its parameter and package";
    std::vector<std::string> names;
    ASSERT_TRUE(g->loadedNodelets(names)) << "the manager does not answer after a failed load";
    EXPECT_EQ(std::count(names.begin(), names.end(), name), 0);
    ros::param::del(name);
  }
  // the standalone node refuses to start with the same message and exit status 1
  if (isLoadable("compressed")) return;
  std::string output;
  const int status = runCommand(
      "timeout 120 rosrun rgbd_lane_detector lane_detector_node __name:=transport_check "
      "_image_transport:=compressed",
      output);
  EXPECT_EQ(status, 1) << output;
  EXPECT_NE(output.find("compressed_image_transport"), std::string::npos) << output;
}

TEST(Lifecycle, LoadsIntoTheManager) {
  ASSERT_FALSE(g->manager.empty()) << "~manager not set";
  ASSERT_TRUE(g->loadDetector(g->detector));
  Outputs out;
  out.plane.subscribe(g->nh, "lane_plane");
  EXPECT_TRUE(validPlaneFrom(out, ros::Time(0)));
}

TEST(Lifecycle, ResolutionChangeReplansEveryBuffer) {
  // the processing scale the detector picks for each camera (processing_scale 0: automatic)
  Params p;
  ros::param::get(g->detector + "/processing_scale", p.processing_scale);
  ros::param::get(g->detector + "/camera_height", p.camera_height);
  test::RoadScene half = g->scene;  // the same road seen by a camera at half resolution
  half.width /= 2;
  half.height /= 2;
  half.K = Intrinsics{g->scene.K.fx / 2, g->scene.K.fy / 2, g->scene.K.cx / 2, g->scene.K.cy / 2};
  const InputSet small = g->inputsOf(half);
  Outputs out;
  out.plane.subscribe(g->nh, "lane_plane");
  out.left.subscribe(g->nh, "response/left");
  out.debug.subscribe(g->nh, "debug_image");
  out.points.subscribe(g->nh, "lane_points");

  // Every output answers its own input's size: the overlay at the input size, the response maps
  // at the processing size, a plane near the truth (the same road).
  auto expectSizes = [&](const ros::Time& stamp, int w, int h) {
    const Intrinsics& K = w == g->scene.width ? g->scene.K : half.K;
    const double scale = processingScale(p, cv::Size(w, h), K);
    const auto left = out.left.withStamp(stamp);
    const auto debug = out.debug.withStamp(stamp);
    ASSERT_TRUE(left && debug) << "no response map or overlay for " << w << "x" << h;
    EXPECT_EQ(left->width, static_cast<uint32_t>(std::lround(w * scale)));
    EXPECT_EQ(left->height, static_cast<uint32_t>(std::lround(h * scale)));
    EXPECT_EQ(left->data.size(), static_cast<size_t>(left->step) * left->height);
    EXPECT_EQ(debug->width, static_cast<uint32_t>(w));
    EXPECT_EQ(debug->height, static_cast<uint32_t>(h));
  };
  const struct {
    const InputSet* in;
    int w, h;
  } steps[] = {{&g->good, g->scene.width, g->scene.height},
               {&small, half.width, half.height},
               {&g->good, g->scene.width, g->scene.height},
               {&small, half.width, half.height}};
  for (const auto& s : steps) {
    const ros::Time first = g->publish(*s.in);
    std::shared_ptr<const LanePlane> plane;
    ASSERT_TRUE(waitFor(
        [&] {
          auto p = out.plane.find([&](const LanePlane& m) {
            return m.valid && m.header.stamp >= first && out.left.withStamp(m.header.stamp) &&
                   out.debug.withStamp(m.header.stamp);
          });
          if (p) plane.reset(new LanePlane(*p));
          return static_cast<bool>(p);
        },
        [&] { g->publishPaced(out.plane, s.in); }))
        << s.w << "x" << s.h << ": no valid plane with every output";
    expectPlaneNearTruth(*plane);
    expectSizes(plane->header.stamp, s.w, s.h);
  }
  // sizes alternating frame by frame: each output still matches its own frame
  std::vector<std::pair<ros::Time, int>> sent;
  for (int i = 0; i < 6; ++i) {
    const InputSet& in = i % 2 ? small : g->good;
    const ros::Time t = g->publish(in);
    sent.emplace_back(t, i % 2);
    ASSERT_TRUE(waitFor([&] { return out.debug.withStamp(t) && out.left.withStamp(t); }))
        << "frame " << i << " not answered";
  }
  for (const auto& s : sent)
    expectSizes(s.first, s.second ? half.width : g->scene.width,
                s.second ? half.height : g->scene.height);
}

// The inputs of `in` from a camera with the intrinsics K (the images unchanged).
InputSet withIntrinsics(const InputSet& in, const Intrinsics& K) {
  InputSet out = in;
  out.info.K[0] = out.info.P[0] = K.fx;
  out.info.K[4] = out.info.P[5] = K.fy;
  out.info.K[2] = out.info.P[2] = K.cx;
  out.info.K[5] = out.info.P[6] = K.cy;
  return out;
}

// The "Detector prepared" lines naming a camera with the focal length fx.
size_t preparedLines(double fx) {
  char text[64];
  std::snprintf(text, sizeof text, "(fx %.3f,", fx);
  return g->logCount(rosgraph_msgs::Log::INFO, "Detector prepared", text);
}

TEST(Lifecycle, CalibrationJitterKeepsThePreparedDetector) {
  // A driver that refines its calibration while it runs moves K by a fraction of a pixel from
  // message to message: the same camera, the detector prepared once (prepare() would re-plan
  // every buffer and reset the tracks on each message). A new calibration prepares it again.
  Outputs out;
  out.plane.subscribe(g->nh, "lane_plane");
  ASSERT_TRUE(validPlaneFrom(out, ros::Time(0), &g->good));
  const Intrinsics K = g->scene.K;
  const double d = 0.2e-3 * K.fx;  // well within sameCamera()'s 1e-3 fx
  const Intrinsics jitter[] = {{K.fx + d, K.fy, K.cx, K.cy},
                               {K.fx - d, K.fy - d, K.cx + d, K.cy},
                               {K.fx + 2 * d, K.fy + d, K.cx - d, K.cy + d}};
  for (const Intrinsics& J : jitter) {
    const InputSet in = withIntrinsics(g->good, J);
    EXPECT_TRUE(validPlaneFrom(out, g->nextStamp(), &in)) << "fx " << J.fx;
  }
  // recalibrated: 2% longer focal length, prepared once. /rosout keeps one node's lines in order,
  // so once that line is in, any line of the jittered calibrations would be in too.
  const Intrinsics recalibrated{K.fx * 1.02, K.fy * 1.02, K.cx, K.cy};
  const InputSet in = withIntrinsics(g->good, recalibrated);
  EXPECT_TRUE(validPlaneFrom(out, g->nextStamp(), &in));
  ASSERT_TRUE(waitFor([&] { return preparedLines(recalibrated.fx) > 0; }))
      << "no 'Detector prepared' line for the new calibration";
  EXPECT_EQ(preparedLines(recalibrated.fx), 1u);
  for (const Intrinsics& J : jitter)
    EXPECT_EQ(preparedLines(J.fx), 0u) << "prepared again for a jitter of fx to " << J.fx;
}

TEST(Lifecycle, CameraDriverRestartResumes) {
  Outputs out;
  out.plane.subscribe(g->nh, "lane_plane");
  ASSERT_TRUE(validPlaneFrom(out, ros::Time(0)));
  ASSERT_TRUE(waitFor([&] { return out.plane.withStamp(g->last_published); },
                      [&] { g->publishPaced(out.plane); }));
  std::map<std::string, std::string> base;
  g->diagnostics.clear();
  ASSERT_TRUE(waitFor([&] { return !(base = latestProcessing()).empty(); }));
  const size_t jump_lines = g->logCount(rosgraph_msgs::Log::WARN, "went back");
  const std::string colour_topic = g->nh.resolveName("rgb/image_rect_color");

  // 1. the driver stops (its publishers leave), then starts again: header.seq from 0, stamps
  //    after the gap
  g->shutdownInputs();
  ASSERT_TRUE(waitFor([&] { return publishersOf(colour_topic).empty(); }));
  g->advertiseInputs();
  ASSERT_TRUE(waitFor([] { return inputsSubscribed(true); })) << "the nodelet did not reconnect";
  const ros::Time restart = g->nextStamp();
  EXPECT_TRUE(validPlaneFrom(out, restart));
  ASSERT_TRUE(waitFor([&] { return out.plane.withStamp(g->last_published); },
                      [&] { g->publishPaced(out.plane); }));
  std::map<std::string, std::string> after;
  ASSERT_TRUE(waitFor([&] {
    after = latestProcessing();
    return counter(after, "Frames waiting") == 0 &&
           counter(after, "Frames processed") > counter(base, "Frames processed");
  }));
  EXPECT_EQ(counter(after, "Frames lost before the nodelet"),
            counter(base, "Frames lost before the nodelet"))
      << "the restarted header.seq counted as lost frames";
  EXPECT_EQ(g->logCount(rosgraph_msgs::Log::WARN, "went back"), jump_lines)
      << "stamps went on forward: no reset expected";

  // 2. the driver restarts with its device clock: stamps start again 100 s earlier
  g->shutdownInputs();
  ASSERT_TRUE(waitFor([&] { return publishersOf(colour_topic).empty(); }));
  g->advertiseInputs();
  ASSERT_TRUE(waitFor([] { return inputsSubscribed(true); }));
  ros::Time t = g->last_stamp - ros::Duration(100.0);
  for (int i = 0; i < 3; ++i, t += ros::Duration(0.1)) {
    const ros::Time stamp = t;
    EXPECT_TRUE(waitFor(
        [&] {
          return out.plane.find(
              [&](const LanePlane& m) { return m.header.stamp == stamp && m.valid; });
        },
        [&] { g->publish(g->good, stamp); }))
        << "frame " << i << " after the clock restart";
  }
  EXPECT_TRUE(waitFor([&] {
    return g->logCount(rosgraph_msgs::Log::WARN, "went back") == jump_lines + 1;
  })) << "not one line for the jump back";
  expectAccountingInEveryReport();
}

TEST(Lifecycle, ManagerReloadsTheNodelet) {
  const std::string colour_topic = g->nh.resolveName("rgb/image_rect_color");
  for (int round = 0; round < 3; ++round) {
    Outputs out;
    out.plane.subscribe(g->nh, "lane_plane");
    ASSERT_TRUE(validPlaneFrom(out, g->nextStamp())) << "round " << round;
    // a reconfigured value survives the reload (the server keeps it on the parameter server)
    const int tau_c = 20 + round;
    ASSERT_TRUE(setInt("tau_c", tau_c));
    ASSERT_TRUE(unloadDetectorFromManager()) << "round " << round;
    EXPECT_TRUE(waitFor([] { return inputsSubscribed(false); }))
        << "round " << round << ": the unloaded nodelet still subscribes";

    ASSERT_TRUE(g->loadDetector(g->detector)) << "round " << round;
    EXPECT_TRUE(validPlaneFrom(out, g->nextStamp())) << "round " << round << " after the reload";
    dynamic_reconfigure::Reconfigure current;  // an empty request answers the current config
    ASSERT_TRUE(ros::service::call(g->detector + "/set_parameters", current));
    int applied = -1;
    for (const auto& p : current.response.config.ints)
      if (p.name == "tau_c") applied = p.value;
    EXPECT_EQ(applied, tau_c) << "round " << round << ": the reconfigured tau_c was lost";
  }
}

// Declared last: the manager is left as the launch found it.
TEST(Lifecycle, UnloadsFromTheManager) {
  EXPECT_TRUE(unloadDetectorFromManager());
}

// ---------------------------------------------------------------------------------------------
// LoopedBag (looped_bag.test, /use_sim_time true)

/// Messages of one pass through the bag, in arrival order.
template <class M>
using Pass = std::vector<boost::shared_ptr<const M>>;

/// Split the messages received into passes through the bag (a new pass where the stamps go back).
template <class M>
std::vector<Pass<M>> passesOf(const Collector<M>& collector) {
  std::vector<Pass<M>> passes;
  collector.find([&](const M& m) {
    if (passes.empty() || m.header.stamp < passes.back().back()->header.stamp)
      passes.emplace_back();
    passes.back().push_back(boost::make_shared<const M>(m));
    return false;
  });
  return passes;
}

bool samePoints(const std::vector<geometry_msgs::Point>& a,
                const std::vector<geometry_msgs::Point>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].x != b[i].x || a[i].y != b[i].y || a[i].z != b[i].z) return false;
  return true;
}

TEST(LoopedBag, TimeGoingBackResetsOnceAndOutputsGoOn) {
  std::string tools;
  ros::param::get("~tools", tools);
  ASSERT_FALSE(tools.empty()) << "~tools (folder of generate_sequence) not set";
  char dir_template[] = "/tmp/rld_looped_bag_XXXXXX";
  ASSERT_NE(mkdtemp(dir_template), nullptr);
  const std::string dir = dir_template, bag = dir + "/loop.bag";
  std::string output;
  ASSERT_EQ(runCommand(tools +
                           "/generate_sequence --scenario summer --frames 25 --width 320 "
                           "--height 190 --quiet --out " +
                           dir + "/seq --bag " + bag,
                       output),
            0)
      << output;

  Outputs out;
  out.plane.subscribe(g->nh, "lane_plane");
  out.markings.subscribe(g->nh, "lane_markings");
  ASSERT_TRUE(waitFor([] { return inputsSubscribed(true); }));
  // a 2.5 s bag (10 Hz) in a loop, on its own clock (the bag's stamps, going back at each pass);
  // /clock, not <this test's namespace>/clock
  unsetenv("ROS_NAMESPACE");
  Child player({"rosbag", "play", "--clock", "--loop", "--quiet", "--wait-for-subscribers", bag});
  ASSERT_TRUE(player.running());
  // three jumps back seen in the outputs, and exactly one line of the nodelet per jump
  size_t jumps = 0, lines = 0;
  EXPECT_TRUE(waitFor(
      [&] {
        lines = g->logCount(rosgraph_msgs::Log::WARN, "went back");
        const auto passes = passesOf(out.plane);
        jumps = passes.empty() ? 0 : passes.size() - 1;
        return jumps >= 3 && passes.back().size() >= 5 && lines == jumps;
      },
      nullptr, 180.0))
      << jumps << " jumps back in the outputs, " << lines << " lines about them";
  player.stop();
  std::string rm_output;
  runCommand("rm -rf " + dir, rm_output);

  // Every pass starts from a reset detector: its first frames give the very planes and markings
  // of the first pass (a state carried over from the end of the previous pass would change them).
  const auto planes = passesOf(out.plane);
  const auto markings = passesOf(out.markings);
  ASSERT_GE(planes.size(), 3u);
  for (size_t k = 1; k + 1 < planes.size(); ++k) {  // the last pass may still be under way
    size_t common = 0;
    while (common < planes[0].size() && common < planes[k].size() &&
           planes[0][common]->header.stamp == planes[k][common]->header.stamp)
      ++common;
    EXPECT_GE(common, 3u) << "pass " << k << " does not start with the first pass's frames";
    size_t valid = 0;
    for (size_t i = 0; i < common; ++i) {
      const LanePlane &a = *planes[0][i], &b = *planes[k][i];
      const std::string where = "pass " + std::to_string(k) + ", frame " + std::to_string(i);
      valid += b.valid;
      EXPECT_EQ(a.valid, b.valid) << where;
      EXPECT_EQ(a.normal.x, b.normal.x) << where;
      EXPECT_EQ(a.normal.y, b.normal.y) << where;
      EXPECT_EQ(a.normal.z, b.normal.z) << where;
      EXPECT_EQ(a.distance, b.distance) << where;
      EXPECT_TRUE(samePoints(a.support_points, b.support_points)) << where;
      if (k < markings.size() && i < markings[0].size() && i < markings[k].size() &&
          markings[0][i]->header.stamp == a.header.stamp &&
          markings[k][i]->header.stamp == a.header.stamp) {
        EXPECT_TRUE(samePoints(markings[0][i]->left, markings[k][i]->left)) << where;
        EXPECT_TRUE(samePoints(markings[0][i]->right, markings[k][i]->right)) << where;
      } else {
        ADD_FAILURE() << where << ": lane_markings not received for the frame";
      }
    }
    EXPECT_GT(valid, 0u) << "no valid plane at the start of pass " << k;
  }
  // the static transform of the bag is used in every pass: no frame skipped for lack of it
  const auto last = latestProcessing();
  EXPECT_LE(counter(last, "Dropped: no transform to target_frame"), 0);
  EXPECT_GT(counter(last, "Frames processed"), 0);
  expectAccountingInEveryReport();
  // the nodelet leaves the manager before the launch shuts down (docs/RELIABILITY.md)
  EXPECT_TRUE(unloadDetectorFromManager());
}

}  // namespace
}  // namespace rgbd_lane_detector

int main(int argc, char** argv) {
  return rgbd_lane_detector::ros_test::runTests(argc, argv, "test_lifecycle");
}
