// Unit tests of the message <-> core conversions (no ROS master needed).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include <boost/any.hpp>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include "rgbd_lane_detector/ros/conversions.h"

namespace rgbd_lane_detector {
namespace {

namespace conv = conversions;
namespace enc = sensor_msgs::image_encodings;

sensor_msgs::Image makeImage(const std::string& encoding, uint32_t w, uint32_t h, uint32_t elem,
                             uint32_t padding = 0) {
  sensor_msgs::Image msg;
  msg.encoding = encoding;
  msg.width = w;
  msg.height = h;
  msg.step = w * elem + padding;
  msg.is_bigendian = false;
  msg.data.assign(static_cast<size_t>(msg.step) * h, 0);
  return msg;
}

TEST(Conversions, ColourEncodingsMapToPixelFormats) {
  const std::pair<std::string, PixelFormat> cases[] = {{enc::RGB8, PixelFormat::kRgb8},
                                                       {enc::BGR8, PixelFormat::kBgr8},
                                                       {enc::RGBA8, PixelFormat::kRgba8},
                                                       {enc::BGRA8, PixelFormat::kBgra8},
                                                       {enc::MONO8, PixelFormat::kMono8}};
  for (const auto& c : cases) {
    PixelFormat f = PixelFormat::kBgr8;
    EXPECT_TRUE(conv::pixelFormatFromEncoding(c.first, f)) << c.first;
    EXPECT_EQ(f, c.second) << c.first;
  }
  PixelFormat f;
  for (const char* bad : {"rgb16", "bayer_rggb8", "16UC1", "8UC3", ""})
    EXPECT_FALSE(conv::pixelFormatFromEncoding(bad, f)) << bad;
}

TEST(Conversions, FrameIdsAsTf2NamesThem) {
  EXPECT_EQ(conv::tfFrameId("camera_color_optical_frame"), "camera_color_optical_frame");
  EXPECT_EQ(conv::tfFrameId("/camera_color_optical_frame"), "camera_color_optical_frame");
  EXPECT_EQ(conv::tfFrameId("//camera/optical"), "camera/optical");
  EXPECT_EQ(conv::tfFrameId("/"), "");
  EXPECT_EQ(conv::tfFrameId(""), "");
}

TEST(Conversions, ColourIsReadInPlaceThroughStep) {
  sensor_msgs::Image msg = makeImage(enc::RGBA8, 7, 5, 4, 12);  // padded rows
  msg.data[2 * msg.step + 3 * 4 + 1] = 42;
  cv::Mat colour;
  PixelFormat f;
  ASSERT_EQ(conv::colourFromMsg(msg, colour, f), nullptr);
  EXPECT_EQ(f, PixelFormat::kRgba8);
  EXPECT_EQ(colour.type(), CV_8UC4);
  EXPECT_EQ(colour.data, msg.data.data());  // no copy
  EXPECT_EQ(colour.step[0], msg.step);
  EXPECT_EQ(colour.at<cv::Vec4b>(2, 3)[1], 42);
}

TEST(Conversions, MalformedImagesAreRejected) {
  cv::Mat m;
  PixelFormat f;
  sensor_msgs::Image short_data = makeImage(enc::BGR8, 10, 10, 3);
  short_data.data.resize(short_data.data.size() - 1);
  EXPECT_NE(conv::colourFromMsg(short_data, m, f), nullptr);
  sensor_msgs::Image small_step = makeImage(enc::BGR8, 10, 10, 3);
  small_step.step = 29;
  EXPECT_NE(conv::colourFromMsg(small_step, m, f), nullptr);
  sensor_msgs::Image wrong = makeImage("rgb16", 10, 10, 6);
  EXPECT_NE(conv::colourFromMsg(wrong, m, f), nullptr);

  double scale;
  cv::Mat swap;
  sensor_msgs::Image odd_step = makeImage(enc::TYPE_16UC1, 10, 10, 2, 1);
  EXPECT_NE(conv::depthFromMsg(odd_step, m, scale, swap), nullptr);
  sensor_msgs::Image depth_enc = makeImage(enc::MONO8, 10, 10, 1);
  EXPECT_NE(conv::depthFromMsg(depth_enc, m, scale, swap), nullptr);
  sensor_msgs::Image huge = makeImage(enc::TYPE_32FC1, 1, 1, 4);
  huge.width = 4000000000u;
  EXPECT_NE(conv::depthFromMsg(huge, m, scale, swap), nullptr);
}

TEST(Conversions, EmptyImageGivesEmptyMat) {
  sensor_msgs::Image msg = makeImage(enc::BGR8, 0, 0, 3);
  cv::Mat m;
  PixelFormat f;
  ASSERT_EQ(conv::colourFromMsg(msg, m, f), nullptr);
  EXPECT_TRUE(m.empty());  // the core reports Status::kEmptyImage
}

TEST(Conversions, DepthEncodingsAndScale) {
  cv::Mat depth, swap;
  double scale = 0;
  sensor_msgs::Image mm = makeImage(enc::TYPE_16UC1, 4, 3, 2, 4);
  reinterpret_cast<uint16_t*>(&mm.data[mm.step])[2] = 1500;
  ASSERT_EQ(conv::depthFromMsg(mm, depth, scale, swap), nullptr);
  EXPECT_EQ(depth.type(), CV_16UC1);
  EXPECT_DOUBLE_EQ(scale, 0.001);
  EXPECT_EQ(depth.data, mm.data.data());
  EXPECT_EQ(depth.at<uint16_t>(1, 2), 1500);
  EXPECT_TRUE(swap.empty());

  sensor_msgs::Image m = makeImage(enc::TYPE_32FC1, 4, 3, 4);
  reinterpret_cast<float*>(&m.data[2 * m.step])[3] = 7.5f;
  ASSERT_EQ(conv::depthFromMsg(m, depth, scale, swap), nullptr);
  EXPECT_EQ(depth.type(), CV_32FC1);
  EXPECT_DOUBLE_EQ(scale, 1.0);
  EXPECT_EQ(depth.data, m.data.data());
  EXPECT_FLOAT_EQ(depth.at<float>(2, 3), 7.5f);
}

TEST(Conversions, ForeignByteOrderDepthIsSwapped) {
  sensor_msgs::Image mm = makeImage(enc::TYPE_16UC1, 3, 2, 2);
  mm.is_bigendian = !(__BYTE_ORDER__ == __ORDER_BIG_ENDIAN__);
  mm.data[mm.step + 2] = 0x05;  // (1, 1) = 0x05DC = 1500 in the foreign order
  mm.data[mm.step + 3] = 0xDC;
  cv::Mat depth, swap;
  double scale;
  ASSERT_EQ(conv::depthFromMsg(mm, depth, scale, swap), nullptr);
  EXPECT_EQ(depth.data, swap.data);
  EXPECT_EQ(depth.at<uint16_t>(1, 1), 1500);
}

TEST(Conversions, DisparityImageReadInPlaceWithItsModel) {
  stereo_msgs::DisparityImage m;
  m.image.width = 3;
  m.image.height = 2;
  m.image.encoding = enc::TYPE_32FC1;
  m.image.is_bigendian = __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__;
  m.image.step = 16;  // one float of padding per row
  m.image.data.assign(32, 0);
  const float v = 42.f;
  std::memcpy(&m.image.data[16 + 4], &v, 4);  // (x 1, y 1)
  m.f = 700.f;
  m.T = 0.12f;
  m.min_disparity = 1.f;
  m.max_disparity = 64.f;
  m.delta_d = 0.0625f;
  m.valid_window.x_offset = 1;
  m.valid_window.width = 5;  // beyond the image: clipped
  m.valid_window.height = 2;
  cv::Mat d, swap;
  DisparityModel model;
  ASSERT_EQ(conv::disparityFromMsg(m, d, model, swap), nullptr);
  EXPECT_EQ(d.type(), CV_32FC1);
  EXPECT_EQ(d.data, m.image.data.data());  // no copy
  EXPECT_EQ(d.step, 16u);
  EXPECT_FLOAT_EQ(d.at<float>(1, 1), 42.f);
  EXPECT_FLOAT_EQ(model.focal, 700.f);
  EXPECT_FLOAT_EQ(model.baseline, 0.12f);
  EXPECT_FLOAT_EQ(model.min_disparity, 1.f);
  EXPECT_FLOAT_EQ(model.max_disparity, 64.f);
  EXPECT_FLOAT_EQ(model.delta_d, 0.0625f);
  EXPECT_EQ(model.valid_window, cv::Rect(1, 0, 2, 2));
  m.valid_window = sensor_msgs::RegionOfInterest();  // all zero: the whole image
  ASSERT_EQ(conv::disparityFromMsg(m, d, model, swap), nullptr);
  EXPECT_TRUE(model.valid_window.empty());
  // problems are named, the outputs left alone
  const DisparityModel before = model;
  auto bad = [&](const std::function<void(stereo_msgs::DisparityImage&)>& spoil) {
    stereo_msgs::DisparityImage b = m;
    spoil(b);
    cv::Mat out;
    DisparityModel mo = before;
    const char* problem = conv::disparityFromMsg(b, out, mo, swap);
    EXPECT_TRUE(out.empty());
    return problem ? std::string(problem) : std::string();
  };
  EXPECT_NE(bad([](auto& b) { b.image.encoding = enc::TYPE_16UC1; }).find("encoding"),
            std::string::npos);
  EXPECT_NE(bad([](auto& b) { b.image.width = 0; }).find("empty"), std::string::npos);
  EXPECT_NE(bad([](auto& b) { b.image.data.resize(20); }).find("shorter"), std::string::npos);
  EXPECT_NE(bad([](auto& b) { b.f = 0.f; }).find("focal"), std::string::npos);
  EXPECT_NE(bad([](auto& b) { b.T = 0.f; }).find("baseline"), std::string::npos);
  EXPECT_NE(bad([](auto& b) {
              b.valid_window.x_offset = 3;
              b.valid_window.width = b.valid_window.height = 1;
            }).find("valid_window"),
            std::string::npos);
}

TEST(Conversions, DistortionIsAnyNonZeroCoefficient) {
  sensor_msgs::CameraInfo info;
  EXPECT_FALSE(conv::hasDistortion(info));  // no coefficients: a pinhole
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  EXPECT_FALSE(conv::hasDistortion(info));  // a pinhole camera's plumb_bob of zeros
  for (size_t i = 0; i < 5; ++i) {
    info.D.assign(5, 0.0);
    info.D[i] = i == 4 ? 1e-6 : -0.3;
    EXPECT_TRUE(conv::hasDistortion(info)) << i;
  }
}

TEST(Conversions, SameCameraWithinHalfAPixelAtFiveHundredPixels) {
  const Intrinsics K{500, 510, 320, 240};
  EXPECT_TRUE(conv::sameCamera(K, K));
  // each of fx, fy, cx, cy: 0.5 px (1e-3 of fx) is the same camera, 0.6 px another
  for (int i = 0; i < 4; ++i) {
    for (const double d : {0.5, -0.5, 0.6, -0.6}) {
      Intrinsics J = K;
      double* v[] = {&J.fx, &J.fy, &J.cx, &J.cy};
      *v[i] += d;
      EXPECT_EQ(conv::sameCamera(K, J), std::abs(d) <= 0.5) << "parameter " << i << " by " << d;
    }
  }
  EXPECT_TRUE(conv::sameCamera(K, Intrinsics{502, 510, 320, 240}, 5e-3));
  EXPECT_FALSE(conv::sameCamera(K, Intrinsics{250, 255, 160, 120}));  // half resolution
  EXPECT_FALSE(conv::sameCamera(Intrinsics{}, Intrinsics{}));         // invalid: never the same
  EXPECT_FALSE(conv::sameCamera(K, Intrinsics{500, 510, std::nan(""), 240}));
}

TEST(Conversions, IntrinsicsFromProjectionElseK) {
  sensor_msgs::CameraInfo info;
  info.K = {500, 0, 320, 0, 510, 240, 0, 0, 1};
  Intrinsics K = conv::intrinsicsFromCameraInfo(info);  // P unset
  EXPECT_DOUBLE_EQ(K.fx, 500);
  EXPECT_DOUBLE_EQ(K.fy, 510);
  EXPECT_DOUBLE_EQ(K.cx, 320);
  EXPECT_DOUBLE_EQ(K.cy, 240);
  info.P = {400, 0, 300, 0, 0, 410, 200, 0, 0, 0, 1, 0};
  K = conv::intrinsicsFromCameraInfo(info);
  EXPECT_DOUBLE_EQ(K.fx, 400);
  EXPECT_DOUBLE_EQ(K.fy, 410);
  EXPECT_DOUBLE_EQ(K.cx, 300);
  EXPECT_DOUBLE_EQ(K.cy, 200);
  sensor_msgs::CameraInfo zero;
  EXPECT_FALSE(conv::intrinsicsFromCameraInfo(zero).valid());
}

TEST(Conversions, CameraInfoFromIntrinsicsRoundTrips) {
  std_msgs::Header h;
  h.frame_id = "cam";
  const Intrinsics K{266.37, 270.5, 320.25, 190.75};
  const sensor_msgs::CameraInfo info = conv::cameraInfoFromIntrinsics(K, 640, 380, h);
  EXPECT_EQ(info.header.frame_id, "cam");
  EXPECT_EQ(info.width, 640u);
  EXPECT_EQ(info.height, 380u);
  EXPECT_EQ(info.D, std::vector<double>(5, 0.0));
  const boost::array<double, 9> K_expected = {K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1};
  const boost::array<double, 9> identity = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  EXPECT_EQ(info.K, K_expected);
  EXPECT_EQ(info.R, identity);
  const Intrinsics back = conv::intrinsicsFromCameraInfo(info);
  EXPECT_DOUBLE_EQ(back.fx, K.fx);
  EXPECT_DOUBLE_EQ(back.fy, K.fy);
  EXPECT_DOUBLE_EQ(back.cx, K.cx);
  EXPECT_DOUBLE_EQ(back.cy, K.cy);
  // and the frame it describes is accepted with images of that size
  Frame frame;
  cv::Mat swap;
  sensor_msgs::Image colour = makeImage(enc::BGR8, 640, 380, 3);
  sensor_msgs::Image depth = makeImage(enc::TYPE_16UC1, 640, 380, 2);
  EXPECT_EQ(conv::frameFromMsgs(colour, depth, info, frame, swap), nullptr);
}

TEST(Conversions, FrameChecksCameraInfoSize) {
  sensor_msgs::Image colour = makeImage(enc::BGR8, 8, 6, 3);
  sensor_msgs::Image depth = makeImage(enc::TYPE_16UC1, 8, 6, 2);
  sensor_msgs::CameraInfo info;
  info.width = 8;
  info.height = 6;
  info.K = {5, 0, 4, 0, 5, 3, 0, 0, 1};
  Frame frame;
  cv::Mat swap;
  ASSERT_EQ(conv::frameFromMsgs(colour, depth, info, frame, swap), nullptr);
  EXPECT_EQ(frame.colour.data, colour.data.data());
  EXPECT_EQ(frame.depth.data, depth.data.data());
  EXPECT_DOUBLE_EQ(frame.intrinsics.fx, 5);
  info.width = 16;
  EXPECT_NE(conv::frameFromMsgs(colour, depth, info, frame, swap), nullptr);
}

// Every reconfigurable field survives Config -> Params -> Config: a field missing from either
// mapping keeps its default and fails here.
TEST(Conversions, ConfigParamsRoundTripCoversEveryField) {
  LaneDetectorConfig config = LaneDetectorConfig::__getDefault__();
  const LaneDetectorConfig& max = LaneDetectorConfig::__getMax__();
  const LaneDetectorConfig& min = LaneDetectorConfig::__getMin__();
  const LaneDetectorConfig& def = LaneDetectorConfig::__getDefault__();
  // move every field away from its default (to its max, or min when the default is the max)
  dynamic_reconfigure::Config def_msg, max_msg, min_msg;
  def.__toMessage__(def_msg);
  max.__toMessage__(max_msg);
  min.__toMessage__(min_msg);
  dynamic_reconfigure::Config changed;
  for (const auto& p : def_msg.bools) {
    dynamic_reconfigure::BoolParameter b = p;
    b.value = !p.value;
    changed.bools.push_back(b);
  }
  for (size_t i = 0; i < def_msg.ints.size(); ++i)
    changed.ints.push_back(def_msg.ints[i].value != max_msg.ints[i].value ? max_msg.ints[i] : min_msg.ints[i]);
  for (size_t i = 0; i < def_msg.doubles.size(); ++i)
    changed.doubles.push_back(def_msg.doubles[i].value != max_msg.doubles[i].value ? max_msg.doubles[i]
                                                                                   : min_msg.doubles[i]);
  ASSERT_TRUE(config.__fromMessage__(changed));
  Params p;
  EXPECT_EQ(conv::configToParams(config, p), 0) << "cfg parameters without a Params field";
  LaneDetectorConfig back = def;
  EXPECT_EQ(conv::paramsToConfig(p, back), 0);
  dynamic_reconfigure::Config a, b;
  config.__toMessage__(a);
  back.__toMessage__(b);
  ASSERT_EQ(a.bools.size(), b.bools.size());
  for (size_t i = 0; i < a.bools.size(); ++i) EXPECT_EQ(a.bools[i].value, b.bools[i].value) << a.bools[i].name;
  for (size_t i = 0; i < a.ints.size(); ++i) EXPECT_EQ(a.ints[i].value, b.ints[i].value) << a.ints[i].name;
  for (size_t i = 0; i < a.doubles.size(); ++i)
    EXPECT_EQ(a.doubles[i].value, b.doubles[i].value) << a.doubles[i].name;
  for (size_t i = 0; i < a.ints.size(); ++i)
    EXPECT_NE(b.ints[i].value, def_msg.ints[i].value) << a.ints[i].name << " was not changed";
}

// params.def is the one source of the defaults: the .cfg's defaults are Params{} (improved).
TEST(Conversions, ConfigDefaultsAreTheDefaultParamsAndEnumsMap) {
  Params p;
  conv::configToParams(LaneDetectorConfig::__getDefault__(), p);
  LaneDetectorConfig from_defaults = LaneDetectorConfig::__getDefault__();
  conv::paramsToConfig(Params(), from_defaults);
  dynamic_reconfigure::Config a, b;
  LaneDetectorConfig::__getDefault__().__toMessage__(a);
  from_defaults.__toMessage__(b);
  EXPECT_TRUE(a == b) << "cfg defaults differ from Params{}";
  EXPECT_EQ(LaneDetectorConfig::__getDefault__().plane_fit, static_cast<int>(PlaneFit::kRoadSurface));
  EXPECT_TRUE(LaneDetectorConfig::__getDefault__().lane_model);

  LaneDetectorConfig c = LaneDetectorConfig::__getDefault__();
  c.depth_term = 1;
  c.plane_fit = 1;
  conv::configToParams(c, p);
  EXPECT_EQ(p.depth_term, DepthTerm::kFarHigh);
  EXPECT_EQ(p.plane_fit, PlaneFit::kLeastSquares);
  c.depth_term = 0;
  c.plane_fit = 0;
  conv::configToParams(c, p);
  EXPECT_EQ(p.depth_term, DepthTerm::kNearHigh);
  EXPECT_EQ(p.plane_fit, PlaneFit::kThreePoint);
}

// The .cfg's ranges are sanitize()'s (both from params.def): every field at the .cfg's max (or
// min) is valid as it is, and every number beyond it is clamped back to exactly that value.
TEST(Conversions, ConfigRangesAreTheSanitizeRanges) {
  for (const bool upper : {true, false}) {
    const LaneDetectorConfig& bound = upper ? LaneDetectorConfig::__getMax__() : LaneDetectorConfig::__getMin__();
    dynamic_reconfigure::Config at, beyond;
    bound.__toMessage__(at);
    beyond = at;
    for (auto& i : beyond.ints) i.value += upper ? 1 : -1;
    for (auto& d : beyond.doubles) d.value += (upper ? 1.0 : -1.0) * (1.0 + std::fabs(d.value));
    for (const auto* msg : {&at, &beyond}) {
      LaneDetectorConfig config = LaneDetectorConfig::__getDefault__();
      ASSERT_TRUE(config.__fromMessage__(*const_cast<dynamic_reconfigure::Config*>(msg)));
      Params p;
      conv::configToParams(config, p);
      LaneDetectorConfig back = LaneDetectorConfig::__getDefault__();
      conv::paramsToConfig(sanitize(p), back);
      dynamic_reconfigure::Config b;
      back.__toMessage__(b);
      ASSERT_EQ(b.ints.size(), at.ints.size());
      ASSERT_EQ(b.doubles.size(), at.doubles.size());
      const char* what = msg == &at ? (upper ? "at max" : "at min") : (upper ? "above max" : "below min");
      dynamic_reconfigure::Config defaults;
      LaneDetectorConfig::__getDefault__().__toMessage__(defaults);
      for (size_t k = 0; k < at.ints.size(); ++k) {
        // an enum beyond its values is no value of it: the default
        const bool enumeration = at.ints[k].name == "depth_term" || at.ints[k].name == "plane_fit";
        const int expected = enumeration && msg == &beyond ? defaults.ints[k].value : at.ints[k].value;
        EXPECT_EQ(b.ints[k].value, expected) << at.ints[k].name << " " << what;
      }
      for (size_t k = 0; k < at.doubles.size(); ++k)
        EXPECT_DOUBLE_EQ(b.doubles[k].value, at.doubles[k].value) << at.doubles[k].name << " " << what;
    }
  }
}

Eigen::Isometry3d someTransform() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-1.2, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.4, -0.2, 1.5);
  return T;
}

TEST(Conversions, PlaneTransformKeepsPointsOnThePlane) {
  Eigen::Vector3d n = Eigen::Vector3d(0.1, -0.95, -0.2).normalized();
  double d = 1.4;
  const Eigen::Vector3d p = Eigen::Vector3d(2.0, 0.0, 10.0) - (n.dot(Eigen::Vector3d(2.0, 0.0, 10.0)) + d) * n;
  ASSERT_NEAR(n.dot(p) + d, 0.0, 1e-12);
  const Eigen::Isometry3d T = someTransform();
  const Eigen::Vector3d off = p + 0.5 * n;  // 0.5 m above the plane
  conv::transformPlane(T, n, d);
  EXPECT_NEAR(n.norm(), 1.0, 1e-12);
  EXPECT_NEAR(n.dot(T * p) + d, 0.0, 1e-12);
  EXPECT_NEAR(n.dot(T * off) + d, 0.5, 1e-12);  // signed distance (side) preserved
}

TEST(Conversions, UpAxisFromTransform) {
  // optical frame of a level camera: base_link z (up) is optical -y
  Eigen::Matrix3d R_optical_base;
  R_optical_base << 0, -1, 0,  //
      0, 0, -1,                //
      1, 0, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_optical_base;
  T.translation() = Eigen::Vector3d(1, 2, 3);  // ignored
  const Eigen::Vector3d up = conv::upAxisFromTransform(T);
  EXPECT_NEAR((up - Eigen::Vector3d(0, -1, 0)).norm(), 0.0, 1e-12);
}

Result makeResult() {
  Result r;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  r.left.found = true;
  r.left.peak_score = 1.5f;
  r.left.angle = 2.0;
  r.left.points = {{-1.8f, 1.5f, 5.f}, {nan, nan, nan}, {-1.8f, 1.5f, 10.f}};
  r.left.scores = {1.5f, 0.f, 1.2f};
  r.left.num_valid_points = 2;
  r.left.kind = BoundaryKind::kRoadEdge;
  r.left.confidence = 0.75f;
  r.right.found = false;  // traced but not reported
  r.right.confidence = 0.5f;
  r.right.peak_score = 0.5f;
  r.right.points = {{1.8f, 1.5f, 6.f}};
  r.right.scores = {0.5f};
  r.right.num_valid_points = 1;
  r.plane.valid = true;
  r.plane.normal = Eigen::Vector3d(0, -1, 0);
  r.plane.distance = 1.5;
  r.plane.support = {{-1.8f, 1.5f, 5.f}, {-1.8f, 1.5f, 10.f}, {1.8f, 1.5f, 6.f}};
  r.plane.rms = 0.01;
  r.plane.range = 32.5;
  r.plane.fit_method = 1;
  return r;
}

std_msgs::Header header() {
  std_msgs::Header h;
  h.frame_id = "cam";
  h.stamp = ros::Time(12, 34);
  return h;
}

TEST(Conversions, LanePlaneAndMarkings) {
  const Result r = makeResult();
  const Eigen::Isometry3d T = someTransform();
  LanePlane plane;
  conv::fillLanePlane(r, header(), T, plane);
  EXPECT_EQ(plane.header.stamp, header().stamp);
  EXPECT_TRUE(plane.valid);
  EXPECT_EQ(plane.fit_method, 1);
  EXPECT_FLOAT_EQ(plane.left_score, 1.5f);
  EXPECT_FLOAT_EQ(plane.right_score, 0.f);  // not reported
  ASSERT_EQ(plane.support_points.size(), 3u);
  const Eigen::Vector3d n(plane.normal.x, plane.normal.y, plane.normal.z);
  for (const auto& p : plane.support_points) EXPECT_NEAR(n.dot(Eigen::Vector3d(p.x, p.y, p.z)) + plane.distance, 0, 1e-6);

  LaneMarkings m;
  conv::fillLaneMarkings(r, header(), T, m);
  ASSERT_EQ(m.left.size(), 2u);  // NaN point omitted
  EXPECT_TRUE(m.right.empty());  // side not found
  const Eigen::Vector3d q = T * Eigen::Vector3d(-1.8, 1.5, 10.0);
  EXPECT_NEAR(m.left[1].x, q.x(), 1e-5);
  EXPECT_NEAR(m.left[1].y, q.y(), 1e-5);
  EXPECT_NEAR(m.left[1].z, q.z(), 1e-5);
  EXPECT_FLOAT_EQ(m.left_angle, 2.f);
  EXPECT_FLOAT_EQ(m.right_score, 0.f);
  EXPECT_EQ(m.left_kind, LaneMarkings::KIND_ROAD_EDGE);
  EXPECT_FLOAT_EQ(m.left_confidence, 0.75f);
  EXPECT_FLOAT_EQ(m.right_confidence, 0.f);  // not reported: no confidence
  EXPECT_FLOAT_EQ(plane.valid_range, 32.5f);

  Result none;
  conv::fillLanePlane(none, header(), T, plane);
  EXPECT_FALSE(plane.valid);
  EXPECT_TRUE(plane.support_points.empty());
}

TEST(Conversions, LanePointsLayout) {
  Result r = makeResult();
  r.left.kind = BoundaryKind::kPaint;
  r.right.found = true;
  r.right.kind = BoundaryKind::kRoadEdge;
  sensor_msgs::PointCloud2 cloud;
  conv::fillLanePoints(r, header(), Eigen::Isometry3d::Identity(), cloud);
  EXPECT_EQ(cloud.header.frame_id, "cam");
  EXPECT_EQ(cloud.height, 1u);
  ASSERT_EQ(cloud.width, 3u);  // 2 valid left + 1 right
  EXPECT_EQ(cloud.point_step, 20u);
  EXPECT_EQ(cloud.row_step, 60u);
  EXPECT_EQ(cloud.data.size(), 60u);
  EXPECT_TRUE(cloud.is_dense);
  ASSERT_EQ(cloud.fields.size(), 6u);
  const char* names[] = {"x", "y", "z", "score", "side", "kind"};
  for (size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(cloud.fields[i].name, names[i]);
    EXPECT_EQ(cloud.fields[i].offset % (i < 4 ? 4 : 1), 0u);
    EXPECT_EQ(cloud.fields[i].datatype, i < 4 ? sensor_msgs::PointField::FLOAT32 : sensor_msgs::PointField::UINT8);
  }
  sensor_msgs::PointCloud2ConstIterator<float> z(cloud, "z"), score(cloud, "score");
  sensor_msgs::PointCloud2ConstIterator<uint8_t> side(cloud, "side"), kind(cloud, "kind");
  const float zs[] = {5.f, 10.f, 6.f}, scores[] = {1.5f, 1.2f, 0.5f};
  const uint8_t sides[] = {0, 0, 1};
  const uint8_t kinds[] = {LaneMarkings::KIND_PAINT, LaneMarkings::KIND_PAINT,
                           LaneMarkings::KIND_ROAD_EDGE};
  for (int i = 0; i < 3; ++i, ++z, ++score, ++side, ++kind) {
    EXPECT_FLOAT_EQ(*z, zs[i]);
    EXPECT_FLOAT_EQ(*score, scores[i]);
    EXPECT_EQ(*side, sides[i]);
    EXPECT_EQ(*kind, kinds[i]);
  }
  Result none;
  conv::fillLanePoints(none, header(), Eigen::Isometry3d::Identity(), cloud);
  EXPECT_EQ(cloud.width, 0u);
  EXPECT_TRUE(cloud.data.empty());
}

TEST(Conversions, MarkersAreStableAndDeletedWhenAbsent) {
  Result r = makeResult();
  r.right.found = true;
  r.right.points.push_back({1.8f, 1.5f, 12.f});
  r.right.scores.push_back(0.7f);
  visualization_msgs::MarkerArray a;
  conv::fillLaneMarkers(r, header(), Eigen::Isometry3d::Identity(), a);
  ASSERT_EQ(a.markers.size(), 3u);
  EXPECT_EQ(a.markers[0].ns, conv::kPlaneNs);
  EXPECT_EQ(a.markers[0].type, visualization_msgs::Marker::TRIANGLE_LIST);
  EXPECT_EQ(a.markers[0].action, visualization_msgs::Marker::ADD);
  EXPECT_EQ(a.markers[0].points.size(), 6u);
  for (const auto& p : a.markers[0].points) EXPECT_NEAR(p.y, 1.5, 1e-6);  // on the plane y = 1.5
  EXPECT_EQ(a.markers[1].ns, conv::kMarkingsNs);
  EXPECT_EQ(a.markers[1].id, conv::kLeftId);
  EXPECT_EQ(a.markers[1].type, visualization_msgs::Marker::LINE_STRIP);
  EXPECT_EQ(a.markers[1].points.size(), 2u);
  EXPECT_EQ(a.markers[2].id, conv::kRightId);
  EXPECT_EQ(a.markers[2].action, visualization_msgs::Marker::ADD);
  for (const auto& m : a.markers) {
    EXPECT_EQ(m.header.frame_id, "cam");
    EXPECT_DOUBLE_EQ(m.pose.orientation.w, 1.0);
  }

  Result none;
  visualization_msgs::MarkerArray b;
  conv::fillLaneMarkers(none, header(), Eigen::Isometry3d::Identity(), b);
  ASSERT_EQ(b.markers.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(b.markers[i].action, visualization_msgs::Marker::DELETE);
    EXPECT_EQ(b.markers[i].ns, a.markers[i].ns);
    EXPECT_EQ(b.markers[i].id, a.markers[i].id);
  }
}

// The lane model's lines are drawn over their whole range: every metre from x_min and at x_max
// (a path or strip that stops up to a metre short, or a short boundary not drawn at all, was
// the model's range cut); an invalid model is all zeros, its lane-change count too.
TEST(Conversions, LaneModelLinesCoverTheirWholeRange) {
  LaneModelEstimate model;
  model.valid = true;
  model.x_min = 2.0;
  model.x_max = 10.5;
  model.centre = {{0.2, 0.01, 0.0, 0.0}};
  model.lane_changes = -1;
  LaneBoundaryModel& left = model.boundaries[static_cast<int>(BoundaryPosition::kEgoLeft)];
  left.valid = true;
  left.position = BoundaryPosition::kEgoLeft;
  left.c = {{1.8, 0.0, 0.001, 0.0}};
  left.x_min = 3.0;
  left.x_max = 7.25;
  LaneBoundaryModel& right = model.boundaries[static_cast<int>(BoundaryPosition::kEgoRight)];
  right.valid = true;
  right.position = BoundaryPosition::kEgoRight;
  right.x_min = 4.0;
  right.x_max = 4.6;  // shorter than a step
  LaneModel msg;
  conv::fillLaneModel(model, header(), msg);
  ASSERT_EQ(msg.centre_line.poses.size(), 10u);  // 2, 3, ..., 10, 10.5
  EXPECT_DOUBLE_EQ(msg.centre_line.poses.front().pose.position.x, 2.0);
  EXPECT_DOUBLE_EQ(msg.centre_line.poses.back().pose.position.x, 10.5);
  EXPECT_DOUBLE_EQ(msg.centre_line.poses.back().pose.position.y, 0.2 + 0.01 * 10.5);
  EXPECT_EQ(msg.lane_changes, -1);
  visualization_msgs::MarkerArray markers;
  conv::appendLaneModelMarkers(model, header(), markers);
  ASSERT_EQ(markers.markers.size(), static_cast<size_t>(kNumBoundaryPositions));
  const auto& l = markers.markers[static_cast<int>(BoundaryPosition::kEgoLeft)];
  ASSERT_EQ(l.action, visualization_msgs::Marker::ADD);
  ASSERT_EQ(l.points.size(), 6u);  // 3, 4, 5, 6, 7, 7.25
  EXPECT_DOUBLE_EQ(l.points.back().x, 7.25);
  EXPECT_DOUBLE_EQ(l.points.back().y, 1.8 + 0.001 * 7.25 * 7.25);
  const auto& r = markers.markers[static_cast<int>(BoundaryPosition::kEgoRight)];
  ASSERT_EQ(r.action, visualization_msgs::Marker::ADD) << "a boundary shorter than a step is drawn";
  ASSERT_EQ(r.points.size(), 2u);
  EXPECT_DOUBLE_EQ(r.points[1].x, 4.6);
  for (const auto& m : markers.markers)
    if (m.id != l.id && m.id != r.id) {
      EXPECT_EQ(m.action, visualization_msgs::Marker::DELETE);
    }

  model.valid = false;
  conv::fillLaneModel(model, header(), msg);
  EXPECT_FALSE(msg.valid);
  EXPECT_EQ(msg.lane_changes, 0);
  EXPECT_TRUE(msg.centre_line.poses.empty());
  EXPECT_TRUE(msg.boundaries.empty());
}

TEST(Conversions, ImagesFromMaps) {
  cv::Mat map(4, 6, CV_32FC1);
  for (int i = 0; i < 24; ++i) map.at<float>(i / 6, i % 6) = 0.5f * i;
  sensor_msgs::Image msg;
  conv::floatMapToImage(map, header(), msg);
  EXPECT_EQ(msg.encoding, enc::TYPE_32FC1);
  EXPECT_EQ(msg.width, 6u);
  EXPECT_EQ(msg.height, 4u);
  EXPECT_EQ(msg.step, 24u);
  float v;
  std::memcpy(&v, &msg.data[3 * msg.step + 5 * 4], 4);
  EXPECT_FLOAT_EQ(v, 11.5f);

  sensor_msgs::Image bgr;
  cv::Mat out = conv::prepareImage(3, 5, CV_8UC3, enc::BGR8, header(), bgr);
  EXPECT_EQ(out.data, bgr.data.data());
  EXPECT_EQ(bgr.step, 15u);
  out.setTo(cv::Scalar(1, 2, 3));
  EXPECT_EQ(bgr.data[14], 3);
}

// lane_grid: the grid's cells in OccupancyGrid order; a point of the vehicle frame finds its
// cell through info alone (origin, resolution, width), as costmap_2d and rviz read it.
TEST(Conversions, OccupancyGridOfTheLaneGrid) {
  LaneModelEstimate m;
  m.valid = true;
  for (int side = 0; side < 2; ++side) {
    LaneBoundaryModel& b = m.boundaries[side];
    b.valid = true;
    b.position = static_cast<BoundaryPosition>(side);
    b.c = {side == 0 ? 1.6 : -1.9, 0.02, 0.0, 0.0};
    b.x_min = 4.0;
    b.x_max = 25.0;
    b.lateral_std = 0.05f;
  }
  LaneGridSettings s;
  s.resolution = 0.2;
  s.length = 30.0;
  s.width = 12.0;
  LaneGrid grid;
  grid.build(m, s);
  std_msgs::Header header;
  header.stamp = ros::Time(12, 345);
  header.frame_id = "base_link";
  nav_msgs::OccupancyGrid msg;
  conv::fillOccupancyGrid(grid, header, msg);
  EXPECT_EQ(msg.header.stamp, header.stamp);
  EXPECT_EQ(msg.header.frame_id, "base_link");
  EXPECT_EQ(msg.info.map_load_time, header.stamp);
  EXPECT_FLOAT_EQ(msg.info.resolution, 0.2f);
  ASSERT_EQ(msg.info.width, 150u);
  ASSERT_EQ(msg.info.height, 60u);
  EXPECT_DOUBLE_EQ(msg.info.origin.position.x, 0.0);
  EXPECT_DOUBLE_EQ(msg.info.origin.position.y, -6.0);
  EXPECT_DOUBLE_EQ(msg.info.origin.orientation.w, 1.0);
  ASSERT_EQ(msg.data.size(), grid.cells().size());
  EXPECT_TRUE(std::equal(msg.data.begin(), msg.data.end(), grid.cells().begin()));
  auto at = [&](double x, double y) {
    const int col = static_cast<int>(std::floor((x - msg.info.origin.position.x) / msg.info.resolution));
    const int row = static_cast<int>(std::floor((y - msg.info.origin.position.y) / msg.info.resolution));
    return msg.data[static_cast<size_t>(row) * msg.info.width + col];
  };
  for (double x : {5.03, 10.13, 20.33}) {  // off the cell edges
    SCOPED_TRACE(x);
    EXPECT_EQ(at(x, 1.6 + 0.02 * x), LaneGrid::kOccupied);
    EXPECT_EQ(at(x, -1.9 + 0.02 * x), LaneGrid::kOccupied);
    EXPECT_EQ(at(x, -0.15 + 0.02 * x), LaneGrid::kFree);
    EXPECT_EQ(at(x, 3.0), LaneGrid::kUnknown);
  }
  EXPECT_EQ(at(2.0, 0.0), LaneGrid::kUnknown);  // before the published range
}

}  // namespace
}  // namespace rgbd_lane_detector
