// The improved mode on the hand-labelled real frames of ../shared/realdata (skipped with a
// message when absent): every labelled boundary reported on its line with its kind (paint or road
// edge), nothing reported where there is no lane, with the LiDAR depth and with StereoSGBM depth
// from the colour pair; and the label file's own checks.
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector_tools/dataset/dataset.h"
#include "rgbd_lane_detector_tools/dataset/real_variants.h"
#include "rgbd_lane_detector_tools/real_labels.h"

namespace rgbd_lane_detector {
namespace {

namespace fs = std::filesystem;

std::string realdata() {
  const char* env = std::getenv("RGBD_LANE_REALDATA");
  return env ? env : REALDATA_DIR;
}

std::vector<tools::LabelledFrame> labels() {
  std::vector<tools::LabelledFrame> l;
  std::string error;
  EXPECT_TRUE(tools::readRealLabels(LABELS_FILE, l, error)) << error;
  return l;
}

// Run the improved mode on every labelled frame of a dataset with a depth source, as recorded
// and in the stress variants (mirrored: a left-hand kerb; no depth in the bottom 30% of the
// rows); skipped when the data is absent.
void scoreDataset(const std::string& dataset, const std::string& depth) {
  const fs::path dir = fs::path(realdata()) / dataset;
  if (!fs::is_directory(dir))
    GTEST_SKIP() << dir << " not found (set RGBD_LANE_REALDATA to the real-data folder)";
  const std::vector<tools::LabelledFrame> all = labels();
  tools::DatasetOptions opt;
  opt.path = dir.string();
  opt.depth = depth;
  std::string error;
  auto reader = tools::openDataset(opt, error);
  ASSERT_TRUE(reader) << error;
  LaneDetector detector(Params::improved());
  Result result;
  tools::DatasetFrame recorded;
  int scored = 0;
  while (reader->next(recorded)) {
    const tools::LabelledFrame* recorded_label = tools::findRealLabel(all, dataset, recorded.name);
    if (!recorded_label) continue;
    for (const tools::RealVariant variant : tools::allRealVariants()) {
      tools::DatasetFrame frame = recorded;
      tools::LabelledFrame variant_label = *recorded_label;
      tools::applyRealVariant(variant, frame, variant_label);
      const tools::LabelledFrame* label = &variant_label;
      SCOPED_TRACE(dataset + "/" + frame.name + " with " + frame.depth_source + " depth, " +
                   tools::realVariantName(variant));
      detector.reset();
      ASSERT_EQ(detector.detect(frame.toFrame(), result), Status::kOk);
      Eigen::Vector3d n(0, -1, 0);
      double d = 0.0;
      if (label->lane) {  // the labels are placed on the LiDAR road plane
        ASSERT_TRUE(frame.referenceRoadPlane(n, d));
      }
      const tools::RealFrameScore s = tools::scoreRealFrame(result, *label, frame.intrinsics, n, d);
      // nothing wrong anywhere; every painted boundary found; a kerb may be missed in the
      // image-quality variants (a miss is no wrong report), not as recorded
      for (const auto* side : {&s.left, &s.right}) {
        const tools::LabelledSide& labelled = side == &s.left ? label->left : label->right;
        EXPECT_FALSE(side->wrong) << (side == &s.left ? "left" : "right") << ": " << side->inliers
                                  << " of " << side->points << " points on the line, kind "
                                  << boundaryKindName(side->reported_kind);
        if (labelled.kind == BoundaryKind::kPaint || variant == tools::RealVariant::kAsIs ||
            variant == tools::RealVariant::kMirrored) {
          EXPECT_FALSE(side->missed) << (side == &s.left ? "left" : "right");
        }
      }
      // the road plane, markers or not, where the road is visible
      if (label->lane) {
        ASSERT_TRUE(result.plane.valid);
        EXPECT_LT(std::acos(std::min(1.0, std::fabs(n.dot(result.plane.normal)))) * 180.0 / M_PI,
                  1.5);
        EXPECT_NEAR(result.plane.distance, d,
                    variant == tools::RealVariant::kNoNearDepth ? 0.15 : 0.05);
      }
      ++scored;
    }
  }
  EXPECT_GT(scored, 0) << "no labelled frame of " << dataset << " was read";
}

TEST(RealData, LabelFileIsWellFormed) {
  const std::vector<tools::LabelledFrame> l = labels();
  ASSERT_GE(l.size(), 5u);
  int sides = 0, edges = 0, negatives = 0;
  for (const auto& f : l) {
    negatives += !f.lane;
    for (const auto* s : {&f.left, &f.right}) {
      sides += s->present;
      edges += s->present && s->kind == BoundaryKind::kRoadEdge;
      for (const auto& p : s->points) {  // inside a 1242x375 KITTI image
        EXPECT_GE(p.x, 0.0);
        EXPECT_LT(p.x, 1242.0);
        EXPECT_GE(p.y, 0.0);
        EXPECT_LT(p.y, 376.0);
      }
    }
  }
  EXPECT_EQ(sides, 4);
  EXPECT_EQ(edges, 1);  // the kerb of kitti2015/000001
  EXPECT_EQ(negatives, 3);
}

TEST(RealData, MalformedLabelsAreRefused) {
  const fs::path p = fs::temp_directory_path() / "rld_bad_labels.yaml";
  std::ofstream(p) << "%YAML:1.0\n---\nframes:\n  - dataset: a\n    frame: \"1\"\n    lane: 1\n"
                      "    left:\n      kind: kerb\n      points: [ 1., 2., 3., 4. ]\n";
  std::vector<tools::LabelledFrame> l;
  std::string error;
  EXPECT_FALSE(tools::readRealLabels(p.string(), l, error));
  EXPECT_NE(error.find("kerb"), std::string::npos) << error;
  std::ofstream(p) << "%YAML:1.0\n---\nframes:\n  - dataset: a\n    frame: \"1\"\n    lane: 1\n"
                      "    left:\n      kind: paint\n      points: [ 1., 2., 3. ]\n";
  EXPECT_FALSE(tools::readRealLabels(p.string(), l, error));
  fs::remove(p);
}

TEST(RealData, VariantsMirrorTheStreetAndRemoveTheNearDepth) {
  tools::DatasetFrame f;
  f.colour = cv::Mat(10, 20, CV_8UC3, cv::Scalar(0, 0, 0));
  f.colour.at<cv::Vec3b>(2, 3) = cv::Vec3b(255, 255, 255);
  f.depth = cv::Mat(10, 20, CV_16UC1, cv::Scalar(1000));
  f.lidar_depth = f.depth;  // the same buffer, as the LiDAR reader gives it
  f.intrinsics = Intrinsics{10.0, 10.0, 8.0, 5.0};
  tools::LabelledFrame label;
  label.lane = true;
  label.left.present = true;
  label.left.points = {cv::Point2d(3.0, 9.0), cv::Point2d(6.0, 5.0)};
  label.right.present = true;
  label.right.kind = BoundaryKind::kRoadEdge;
  label.right.points = {cv::Point2d(15.0, 9.0)};

  tools::DatasetFrame m = f;
  tools::LabelledFrame ml = label;
  tools::applyRealVariant(tools::RealVariant::kMirrored, m, ml);
  EXPECT_EQ(m.colour.at<cv::Vec3b>(2, 20 - 1 - 3), cv::Vec3b(255, 255, 255));
  EXPECT_DOUBLE_EQ(m.intrinsics.cx, 19.0 - 8.0);
  ASSERT_TRUE(ml.left.present && ml.right.present);
  EXPECT_EQ(ml.left.kind, BoundaryKind::kRoadEdge);  // the kerb is on the left now
  EXPECT_DOUBLE_EQ(ml.left.points[0].x, 19.0 - 15.0);
  EXPECT_DOUBLE_EQ(ml.right.points[1].x, 19.0 - 6.0);
  EXPECT_EQ(f.colour.at<cv::Vec3b>(2, 3), cv::Vec3b(255, 255, 255));  // the original is kept

  tools::DatasetFrame n = f;
  tools::LabelledFrame nl = label;
  tools::applyRealVariant(tools::RealVariant::kNoNearDepth, n, nl);
  EXPECT_EQ(cv::countNonZero(n.depth.rowRange(7, 10)), 0);  // bottom 30% of 10 rows
  EXPECT_EQ(cv::countNonZero(n.depth.rowRange(0, 7)), 7 * 20);
  EXPECT_EQ(cv::countNonZero(n.lidar_depth), 10 * 20);  // the LiDAR reference is kept
  EXPECT_EQ(nl.left.points[0].x, 3.0);

  tools::RealVariant v;
  EXPECT_TRUE(tools::realVariantFromName("no_near_depth", v));
  EXPECT_EQ(v, tools::RealVariant::kNoNearDepth);
  EXPECT_FALSE(tools::realVariantFromName("upside_down", v));
}

TEST(RealData, KittiWithLidarDepth) {
  scoreDataset("kitti2015", "dataset");
}
TEST(RealData, KittiWithStereoDepth) {
  scoreDataset("kitti2015", "sgbm");
}
TEST(RealData, StreetWithoutMarkingsWithLidarDepth) {
  scoreDataset("kitti_stereo_negative", "dataset");
}
TEST(RealData, StreetWithoutMarkingsWithStereoDepth) {
  scoreDataset("kitti_stereo_negative", "sgbm");
}
TEST(RealData, OfficeWithKinectDepth) {
  scoreDataset("tum_office", "dataset");
}

}  // namespace
}  // namespace rgbd_lane_detector
