// The same detections on every machine: detect() on a fixed drive of rendered roads (both modes,
// uint16 and float depth), written as text by one build and compared field by field by another
// (make test-arm64: the x86 build writes, the aarch64 build under qemu compares, on each of its
// targets). Environment:
//   RLD_DETECTIONS_WRITE=FILE      write this machine's detections (best target) and pass;
//   RLD_DETECTIONS_REFERENCE=FILE  compare every target of this machine with FILE;
//   neither: skipped (a machine alone is covered by EveryTargetGivesTheSameBits).
// Tolerances (docs/PERFORMANCE.md): counts, flags and kinds exact; pixels 1e-4 px; 3D points
// 1e-5 m; the plane (normal and offset), normals, angles 1e-6; scores and confidences 1e-5.
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rgbd_lane_detector/lane_detector.h"
#include "simd.h"  // private: the targets
#include "synthetic_scene.h"

namespace rgbd_lane_detector {
namespace {

// One line per value group: "<key> v1 v2 ...", numbers printed to round-trip exactly.
struct Writer {
  std::ostringstream out;
  void line(const std::string& key, std::initializer_list<double> values) {
    out << key;
    for (double v : values) out << ' ' << (std::isnan(v) ? std::string("nan") : fmt(v));
    out << '\n';
  }
  static std::string fmt(double v) {
    char buf[40];
    std::snprintf(buf, sizeof(buf), "%.17g", v);
    return buf;
  }
};

void writeSide(Writer& w, const std::string& k, const MarkerTrace& m) {
  w.line(k + ".flags", {double(m.found), double(static_cast<int>(m.kind)), double(m.angle_valid),
                        double(m.pixels.size()), double(m.num_valid_points)});
  w.line(k + ".seed", {m.seed.x, m.seed.y});
  w.line(k + ".angle", {m.angle});
  w.line(k + ".score", {m.peak_score, m.confidence});
  for (size_t i = 0; i < m.pixels.size(); ++i) {
    w.line(k + ".pixel", {m.pixels[i].x, m.pixels[i].y});
    w.line(k + ".point", {m.points[i].x(), m.points[i].y(), m.points[i].z()});
  }
}

// detect() over the drive on the current target.
std::string detections() {
  Writer w;
  for (const Params& params : {Params::paper(), Params::improved()}) {
    LaneDetector det(params);
    Result r;
    for (int i = 0; i < 6; ++i) {
      test::RoadScene scene;
      scene.right_dashed = true;
      scene.travelled = 2.0 * i;
      scene.lateral_offset = 0.25 * std::sin(0.7 * i);
      scene.pitch = 0.07 + 0.005 * i;
      cv::Mat bgr, depth, depth_m;
      scene.render(bgr, depth, &depth_m);
      Frame f;
      f.colour = bgr;
      f.depth = i % 2 ? depth_m : depth;  // both depth kernels
      f.depth_scale = 0.001;
      f.intrinsics = scene.K;
      const Status st = det.detect(f, r);
      const std::string k = (params.track_lanes ? "improved" : "paper") + std::to_string(i);
      w.line(k + ".status", {double(static_cast<int>(st))});
      writeSide(w, k + ".left", r.left);
      writeSide(w, k + ".right", r.right);
      w.line(k + ".plane", {double(r.plane.valid), r.plane.normal.x(), r.plane.normal.y(),
                            r.plane.normal.z(), r.plane.distance});
      w.line(k + ".templates", {r.template_angle_left, r.template_angle_right});
      w.line(k + ".model", {double(r.lane_model.valid)});
    }
  }
  return w.out.str();
}

// Tolerance of a value by its key's last part.
double tolerance(const std::string& key) {
  const std::string kind = key.substr(key.rfind('.') + 1);
  if (kind == "pixel" || kind == "seed") return 1e-4;
  if (kind == "point") return 1e-5;
  if (kind == "plane" || kind == "angle" || kind == "templates") return 1e-6;
  if (kind == "score") return 1e-5;
  return 0.0;  // flags, counts, status
}

// Field by field; returns the largest difference seen, by kind, through @p worst.
void compare(const std::string& expected, const std::string& actual, double& worst_px,
             double& worst_other) {
  std::istringstream e(expected), a(actual);
  std::string le, la;
  int line = 0;
  while (std::getline(e, le)) {
    ++line;
    ASSERT_TRUE(static_cast<bool>(std::getline(a, la))) << "missing line " << line << ": " << le;
    std::istringstream se(le), sa(la);
    std::string ke, ka;
    se >> ke;
    sa >> ka;
    ASSERT_EQ(ke, ka) << "line " << line;
    const double tol = tolerance(ke);
    std::string ve, va;
    while (se >> ve) {
      ASSERT_TRUE(static_cast<bool>(sa >> va)) << "line " << line << ": " << le;
      if (ve == "nan" || va == "nan") {
        EXPECT_EQ(ve, va) << "line " << line << ": " << ke;
        continue;
      }
      const double d = std::fabs(std::stod(ve) - std::stod(va));
      EXPECT_LE(d, tol) << "line " << line << ": " << ke << " " << ve << " vs " << va;
      double& worst = (ke.find("pixel") != std::string::npos) ? worst_px : worst_other;
      worst = std::max(worst, d);
    }
  }
  EXPECT_FALSE(static_cast<bool>(std::getline(a, la))) << "extra line: " << la;
}

TEST(GoldenDetections, EqualOnEveryMachine) {
  if (const char* out = std::getenv("RLD_DETECTIONS_WRITE")) {
    std::ofstream(out) << detections();
    std::printf("wrote the detections of %s to %s\n", simd::targetName(simd::currentTarget()), out);
    return;
  }
  const char* ref = std::getenv("RLD_DETECTIONS_REFERENCE");
  if (!ref) GTEST_SKIP() << "set RLD_DETECTIONS_REFERENCE or RLD_DETECTIONS_WRITE";
  std::ifstream in(ref);
  ASSERT_TRUE(in.good()) << ref;
  std::stringstream expected;
  expected << in.rdbuf();
  for (simd::Target t : simd::availableTargets()) {
    simd::forceTarget(t);
    SCOPED_TRACE(simd::targetName(t));
    double worst_px = 0.0, worst_other = 0.0;
    compare(expected.str(), detections(), worst_px, worst_other);
    std::printf("%s against %s: largest difference %.3g px (pixels), %.3g (other values)\n",
                simd::targetName(t), ref, worst_px, worst_other);
  }
  simd::forceTarget(simd::kBest);
}

}  // namespace
}  // namespace rgbd_lane_detector
