// InputSynchroniser (src/ros/input_sync.h) fed through its subscribers' entry points, no
// roscore: sets are synchronised (ExactTime, ApproximateTime), every colour image and
// camera_info is seen first, a jump back in time replaces the synchroniser once and drops the
// late messages from before it; a missing transport plugin is named with its package.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <boost/make_shared.hpp>

#include "../../../src/ros/input_sync.h"

namespace rgbd_lane_detector {
namespace {

using Image = sensor_msgs::Image;
using CameraInfo = sensor_msgs::CameraInfo;

struct Recorder {
  std::vector<const Image*> received;
  std::vector<double> infos;
  struct Set {
    double colour, depth, info;
  };
  std::vector<Set> sets;
  std::vector<InputSynchroniser::Jump> jumps;
  std::vector<std::string> out_of_order;

  InputSynchroniser::Callbacks callbacks() {
    InputSynchroniser::Callbacks c;
    c.colour_received = [this](const Image& m) { received.push_back(&m); };
    c.camera_info = [this](const CameraInfo& m) { infos.push_back(m.header.stamp.toSec()); };
    c.frame = [this](const sensor_msgs::ImageConstPtr& colour, const sensor_msgs::ImageConstPtr& depth,
                     const sensor_msgs::CameraInfoConstPtr& info) {
      sets.push_back({colour->header.stamp.toSec(), depth->header.stamp.toSec(),
                      info->header.stamp.toSec()});
    };
    c.jumped = [this](const InputSynchroniser::Jump& j) { jumps.push_back(j); };
    c.out_of_order = [this](const char* input, double back) {
      out_of_order.push_back(std::string(input) + " " + std::to_string(back));
    };
    return c;
  }
};

class InputSync : public ::testing::Test {
 protected:
  void SetUp() override { ros::Time::init(); }  // message events' receipt times; no master

  static boost::shared_ptr<const Image> image(double stamp) {
    auto m = boost::make_shared<Image>();
    m->header.stamp = ros::Time(stamp);
    return m;
  }
  static void feed(InputSynchroniser& in, double colour, double depth, double info) {
    auto c = boost::make_shared<CameraInfo>();
    c->header.stamp = ros::Time(info);
    in.infoIn(InputSynchroniser::CameraInfoEvent(boost::shared_ptr<const CameraInfo>(c)));
    in.depthIn(InputSynchroniser::ImageEvent(image(depth)));
    in.colourIn(InputSynchroniser::ImageEvent(image(colour)));
  }
};

TEST_F(InputSync, ExactTimePairsIdenticalStamps) {
  Recorder r;
  InputSynchroniser in(false, 5, r.callbacks());
  EXPECT_FALSE(in.subscribed()) << "nothing is subscribed until the owner asks";
  feed(in, 1.0, 1.0, 1.0);
  feed(in, 2.0, 2.5, 2.0);  // no depth at 2.0: never emitted
  feed(in, 3.0, 3.0, 3.0);
  ASSERT_EQ(r.sets.size(), 2u);
  EXPECT_EQ(r.sets[0].colour, 1.0);
  EXPECT_EQ(r.sets[1].colour, 3.0);
  EXPECT_EQ(r.sets[1].depth, 3.0);
  EXPECT_EQ(r.received.size(), 3u) << "every colour image is counted";
  EXPECT_EQ(r.infos, (std::vector<double>{1.0, 2.0, 3.0})) << "every camera_info is seen";
  EXPECT_TRUE(r.jumps.empty());
}

TEST_F(InputSync, ApproximateTimePairsTheNearestStamps) {
  Recorder r;
  InputSynchroniser in(true, 5, r.callbacks());
  for (int i = 0; i < 6; ++i) feed(in, 1.0 + i * 0.1, 1.0 + i * 0.1 + 0.003, 1.0 + i * 0.1 - 0.002);
  ASSERT_GE(r.sets.size(), 4u);  // ApproximateTime emits a set once a later one proves it best
  for (const auto& s : r.sets) {
    EXPECT_NEAR(s.depth, s.colour + 0.003, 1e-9);
    EXPECT_NEAR(s.info, s.colour - 0.002, 1e-9);
  }
}

// A sparse depth stream (a 2 Hz LiDAR projected into the camera) beside colour images that were
// lost for a while: ApproximateTime pairs each depth image with the nearest colour image left,
// however far that is; max_sync_interval refuses a colour image of another moment.
TEST_F(InputSync, ApproximateTimeMakesNoSetWiderThanTheMaximumInterval) {
  for (const double max_interval : {0.0, 0.1}) {
    Recorder r;
    InputSynchroniser in(true, 10, r.callbacks(), max_interval);
    auto info = [&](double t) {
      auto c = boost::make_shared<CameraInfo>();
      c->header.stamp = ros::Time(t);
      in.infoIn(InputSynchroniser::CameraInfoEvent(boost::shared_ptr<const CameraInfo>(c)));
    };
    for (int i = 0; i <= 40; ++i) {
      const double t = 10.0 + i * 0.1;  // colour and camera_info at 10 Hz
      if (i % 5 == 0) in.depthIn(InputSynchroniser::ImageEvent(image(t)));
      if (i >= 13 && i <= 17) continue;  // colour lost around the depth at 11.5
      info(t);
      in.colourIn(InputSynchroniser::ImageEvent(image(t)));
    }
    std::vector<double> wide;  // colour stamps of sets whose depth is more than 0.1 s away
    for (const auto& s : r.sets)
      if (std::fabs(s.depth - s.colour) > 0.1 + 1e-9) wide.push_back(s.colour);
    EXPECT_GE(r.sets.size(), 6u) << "max " << max_interval;
    if (max_interval > 0.0)
      EXPECT_TRUE(wide.empty()) << "the colour image at " << wide.front() << " s is in a set "
                                << "with a depth image more than 0.1 s away";
    else
      EXPECT_FALSE(wide.empty()) << "without a limit the depth at 11.5 s pairs with a colour "
                                    "image 0.3 s away (the test's premise)";
  }
}

// A depth image stamped a millisecond before the one before it (a driver's clock jittering back)
// is dropped and said, and nothing restarts: the synchroniser goes on pairing the next sets.
TEST_F(InputSync, AStampAMillisecondBackIsDroppedNotAJump) {
  Recorder r;
  InputSynchroniser in(false, 5, r.callbacks());
  feed(in, 100.0, 100.0, 100.0);
  in.depthIn(InputSynchroniser::ImageEvent(image(99.999)));
  EXPECT_TRUE(r.jumps.empty());
  ASSERT_EQ(r.out_of_order.size(), 1u);
  EXPECT_EQ(r.out_of_order[0].rfind("depth image 0.001", 0), 0u) << r.out_of_order[0];
  feed(in, 100.033, 100.033, 100.033);
  ASSERT_EQ(r.sets.size(), 2u) << "the synchroniser was not replaced";
  EXPECT_EQ(r.sets[1].colour, 100.033);
}

TEST_F(InputSync, AJumpBackResetsOnceAndDropsTheLateMessagesOfTheOldEpoch) {
  Recorder r;
  InputSynchroniser in(false, 5, r.callbacks());
  feed(in, 100.0, 100.0, 100.0);
  feed(in, 101.0, 101.0, 101.0);
  ASSERT_EQ(r.sets.size(), 2u);
  auto info = boost::make_shared<CameraInfo>();
  info->header.stamp = ros::Time(50.0);  // camera_info goes back first: a new epoch
  in.infoIn(InputSynchroniser::CameraInfoEvent(boost::shared_ptr<const CameraInfo>(info)));
  ASSERT_EQ(r.jumps.size(), 1u);
  EXPECT_NEAR(r.jumps[0].seconds_back, 51.0, 1e-6);
  EXPECT_TRUE(r.jumps[0].log);
  EXPECT_NE(r.jumps[0].text(true).find("and the tf buffer"), std::string::npos);
  EXPECT_EQ(r.jumps[0].text(false).find("tf buffer"), std::string::npos);
  // a late depth of the old epoch is dropped; the old epoch's colour joins the new one's pair
  in.depthIn(InputSynchroniser::ImageEvent(image(102.0)));
  in.depthIn(InputSynchroniser::ImageEvent(image(50.0)));
  in.colourIn(InputSynchroniser::ImageEvent(image(50.0)));
  ASSERT_EQ(r.sets.size(), 3u);
  EXPECT_EQ(r.sets[2].colour, 50.0);
  EXPECT_EQ(r.jumps.size(), 1u) << "the other inputs join the epoch without a second reset";
  feed(in, 51.0, 51.0, 51.0);
  EXPECT_EQ(r.sets.size(), 4u);
}

TEST(Transports, AMissingPluginIsNamedWithItsPackage) {
  const std::vector<std::string> loadable = {"image_transport/raw", "theora_image_transport/theora"};
  EXPECT_EQ(transportProblem("image_transport", "raw", {}), "");
  EXPECT_EQ(transportProblem("image_transport", "theora", loadable), "");
  const std::string p = transportProblem("depth_image_transport", "compressedDepth", loadable);
  EXPECT_NE(p.find("~depth_image_transport"), std::string::npos) << p;
  EXPECT_NE(p.find("compressed_depth_image_transport"), std::string::npos) << p;
  EXPECT_NE(p.find("image_transport/raw, theora_image_transport/theora"), std::string::npos) << p;
  int asked = 0;
  const auto names = [&] {
    ++asked;
    return loadable;
  };
  EXPECT_EQ(missingTransports("raw", "raw", names), "");
  EXPECT_EQ(asked, 0) << "raw needs no plugin lookup";
  const std::string both = missingTransports("compressed", "compressedDepth", names);
  EXPECT_EQ(asked, 1);
  EXPECT_NE(both.find("~image_transport"), std::string::npos);
  EXPECT_NE(both.find("~depth_image_transport"), std::string::npos);
}

}  // namespace
}  // namespace rgbd_lane_detector
