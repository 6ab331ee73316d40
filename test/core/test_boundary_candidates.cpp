// Candidate boundaries of a frame: lines traced from a response map, best seed first, the next
// seeds off the lines already traced, the map restored; unclassified lines taken as paint; a
// narrow line told as a rail head or as worn dashed paint (also where raised markers join its
// dashes; a kerb's lip or a seam's rim in pieces is no paint); a short match followed from its
// seed when the depth around it is the road (its own point a stray return or not); a faint match
// a lane's width beside a painted line followed.
#include <cmath>
#include <functional>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector/boundary_candidates.h"
#include "road_cross_section.h"
#include "synthetic_scene.h"

namespace rgbd_lane_detector {
namespace {

constexpr int kW = 320, kH = 190;
const Intrinsics kK{133.0, 133.0, 160.0, 95.0};

struct Fixture {
  cv::Mat points, empty_map, colour, grey;
  PlaneEstimate road;
  LaneFitter fitter;
  CandidateFrame f;
  Params params = Params::improved();
  BoundaryCandidateFinder finder;

  Fixture() {
    test::DepthScene scene;
    scene.image_width = kW;
    scene.image_height = kH;
    scene.K = kK;
    points = scene.render();
    road.valid = true;
    road.normal = scene.normal();
    road.distance = scene.height;
    colour = cv::Mat(kH, kW, CV_8UC3, cv::Scalar::all(90));
    grey = cv::Mat(kH, kW, CV_8UC1, cv::Scalar(90));
    f.colour = &colour;
    f.grey = &grey;
    f.grey_rows = cv::Range(0, kH);
    f.K = kK;
    f.input_size = f.proc_size = cv::Size(kW, kH);
    f.roi = cv::Rect(0, static_cast<int>(0.41 * kH), kW, kH - static_cast<int>(0.41 * kH));
    f.roi_rows = cv::Range(f.roi.y, kH);
    f.col_map = f.row_map = &empty_map;
    f.points = &points;
    f.road = &road;
    f.fitter = &fitter;
    f.template_angle = {3 * M_PI / 4, M_PI / 4};
    params.boundary_candidates = 2;
    params.classify_boundaries = false;
    finder.setParams(params);
  }
};

// A right-side response map with two lines ("\" direction): a stronger one and a weaker one.
cv::Mat twoLines() {
  cv::Mat R(kH, kW, CV_32FC1, cv::Scalar(0.f));
  cv::line(R, cv::Point(170, 90), cv::Point(235, 170), cv::Scalar(1.4), 8);
  cv::line(R, cv::Point(200, 90), cv::Point(288, 170), cv::Scalar(1.1), 8);
  return R;
}

TEST(BoundaryCandidateFinder, TracesTheBestLineFirstThenTheNext) {
  Fixture fx;
  cv::Mat R = twoLines();
  const cv::Mat before = R.clone();
  fx.finder.clear();
  fx.finder.traceLines(fx.f, 1, R);
  int n = 0;
  const BoundaryCandidate* c = fx.finder.candidates(1, n);
  ASSERT_EQ(n, 2);
  EXPECT_NEAR(c[0].trace.peak_score, 1.4f, 1e-4f);
  EXPECT_NEAR(c[1].trace.peak_score, 1.1f, 1e-4f);
  for (int k = 0; k < 2; ++k) {
    ASSERT_GE(c[k].trace.pixels.size(), 5u) << k;
    EXPECT_EQ(c[k].trace.pixels.size(), c[k].trace.points.size());
    for (const auto& p : c[k].trace.points) EXPECT_TRUE(p.allFinite());  // the road's depth
  }
  // the first line's pixels lie on the stronger line, the second's on the weaker one
  for (const auto& px : c[0].trace.pixels)
    EXPECT_NEAR(px.x, 170.0 + (px.y - 90.0) * 65.0 / 80.0, 6.0) << px;
  for (const auto& px : c[1].trace.pixels)
    EXPECT_NEAR(px.x, 200.0 + (px.y - 90.0) * 88.0 / 80.0, 6.0) << px;
  EXPECT_EQ(cv::countNonZero(R != before), 0);  // the published map is put back
  int none = 0;
  fx.finder.candidates(0, none);
  EXPECT_EQ(none, 0);
}

TEST(BoundaryCandidateFinder, UnclassifiedLinesArePaint) {
  Fixture fx;
  cv::Mat R = twoLines();
  fx.finder.clear();
  fx.finder.traceLines(fx.f, 1, R);
  fx.finder.classify(fx.f);  // classify_boundaries off: the paper's view
  int n = 0;
  const BoundaryCandidate* c = fx.finder.candidates(1, n);
  ASSERT_EQ(n, 2);
  for (int k = 0; k < n; ++k) {
    EXPECT_TRUE(c[k].evidence.boundary);
    EXPECT_EQ(c[k].evidence.kind, BoundaryKind::kPaint);
  }
  fx.finder.clear();
  fx.finder.candidates(1, n);
  EXPECT_EQ(n, 0);
}

TEST(BoundaryCandidateFinder, NothingAboveTheTraceThreshold) {
  Fixture fx;
  cv::Mat R(kH, kW, CV_32FC1, cv::Scalar(0.5f));
  fx.finder.clear();
  fx.finder.traceLines(fx.f, 0, R);
  int n = 0;
  const BoundaryCandidate* c = fx.finder.candidates(0, n);
  ASSERT_LE(n, 1);  // at most the best seed, untraced (the paper reports its score)
  if (n == 1) {
    EXPECT_TRUE(c[0].trace.pixels.empty());
  }
}

// A finder on @p road (its colour, points and plane) at the input size, the rows below 41%
// searched, one candidate per side, improved mode.
struct RenderedRoadFinder {
  const cv::Mat no_maps;
  LaneFitter fitter;
  CandidateFrame f;
  BoundaryCandidateFinder finder;

  explicit RenderedRoadFinder(const test::RenderedRoad& road) {
    f.colour = &road.bgr;
    f.format = PixelFormat::kBgr8;
    f.grey = &road.grey;
    f.grey_rows = cv::Range(0, test::kH);
    f.K = test::kK;
    f.input_size = f.proc_size = cv::Size(test::kW, test::kH);
    f.roi = cv::Rect(0, static_cast<int>(0.41 * test::kH), test::kW,
                     test::kH - static_cast<int>(0.41 * test::kH));
    f.roi_rows = cv::Range(f.roi.y, test::kH);
    f.col_map = f.row_map = &no_maps;
    f.points = &road.points;
    f.road = &road.plane;
    f.fitter = &fitter;
    f.template_angle = {3 * M_PI / 4, M_PI / 4};
    Params p = Params::improved();
    p.boundary_candidates = 1;
    finder.setParams(p);
    finder.clear();
  }
};

// The left side's first candidate on @p road traced from the response @p R and classified.
BoundaryCandidate firstLeftCandidate(const test::RenderedRoad& road, cv::Mat& R) {
  RenderedRoadFinder fx(road);
  const CandidateFrame& f = fx.f;
  BoundaryCandidateFinder& finder = fx.finder;
  finder.traceLines(f, 0, R);
  finder.classify(f);
  int n = 0;
  const BoundaryCandidate* c = finder.candidates(0, n);
  return n > 0 ? c[0] : BoundaryCandidate();
}

// A narrow bright band (5 cm, a rail head's width, or @p width(z) m) 1.8 m left of the camera
// on a level road, painted where @p painted(z) holds, traced from its response from 4 m to
// @p traced m ahead and classified: the left side's first candidate. Without @p depth no point
// is measured (a sparse LiDAR's, or its blind zone). With @p kerb > 0 the band is the lit lip of
// a kerb that high: a footpath raised beyond it, the band on its top 5 mm from the edge (its face,
// at -1.77 m, is asphalt grey). The surface beyond the band is @p outer grey (the road's 80: the
// same asphalt).
BoundaryCandidate narrowLine(const std::function<bool(double)>& painted, double traced,
                             const std::function<double(double)>& width = nullptr,
                             bool depth = true, double kerb = 0.0, int outer = 80) {
  test::CrossSection cs;
  if (kerb > 0.0) cs.boxes.push_back({-20.0, -1.8 + 0.03, kerb});
  cs.colour = [painted, width, outer](double x, double z) {
    const double half = 0.5 * (width ? width(z) : 0.05);
    if (std::fabs(x + 1.8) < half && painted(z)) return test::grey(235);
    return x < -1.8 ? test::grey(outer) : test::grey(80);
  };
  test::RenderedRoad road;
  road.render(cs);
  if (!depth) road.points.setTo(cv::Scalar::all(std::nanf("")));
  // its response: a band along the line's image
  cv::Mat R(test::kH, test::kW, CV_32FC1, cv::Scalar(0.f));
  const std::vector<cv::Point2f> px = test::linePixels(-1.8, kerb);
  for (size_t i = 1; i < px.size() && test::roadForward(px[i]) <= traced; ++i)
    cv::line(R, px[i - 1], px[i], cv::Scalar(1.2), 5);
  return firstLeftCandidate(road, R);
}

TEST(BoundaryCandidateFinder, NarrowLineInOnePieceIsARailHead) {
  const BoundaryCandidate c = narrowLine([](double) { return true; }, 7.0);
  EXPECT_TRUE(c.evidence.boundary) << c.evidence.reason;
  EXPECT_EQ(c.evidence.kind, BoundaryKind::kRoadEdge) << c.evidence.reason;
}

TEST(BoundaryCandidateFinder, NarrowLineThatNoDepthPutsOnTheRoadIsNoRailHead) {
  // (a rail head lies in the road; a narrow bright line may as well be a vehicle's trim)
  const BoundaryCandidate c = narrowLine([](double) { return true; }, 7.0, nullptr, false);
  EXPECT_FALSE(c.evidence.boundary) << c.evidence.reason;
}

TEST(BoundaryCandidateFinder, NarrowLineOfWornDashesIsPaint) {
  // a worn dash's narrow core from 4 to 7 m, then, 2.5 m on, what is left of the next dash up
  // to 14 m: 0.2 m fragments every metre (worn paint, raised markers), closer together than the
  // 2 m gap between two dashes; the band shows on about half of the rows followed (a rail head
  // on all of them)
  const BoundaryCandidate c = narrowLine(
      [](double z) {
        return (z >= 4.0 && z < 7.0) || (z >= 9.5 && z < 14.0 && std::fmod(z, 1.0) < 0.2);
      },
      7.0);
  EXPECT_TRUE(c.evidence.boundary) << c.evidence.reason;
  EXPECT_EQ(c.evidence.kind, BoundaryKind::kPaint) << c.evidence.reason;
  EXPECT_STREQ(c.evidence.reason, "narrow dashes (worn paint)");
  ASSERT_FALSE(c.trace.pixels.empty());
  for (const auto& q : c.trace.pixels) EXPECT_NEAR(test::roadLateral(q), -1.8, 0.1) << q;
  // also where no depth measures it
  const BoundaryCandidate d = narrowLine(
      [](double z) {
        return (z >= 4.0 && z < 7.0) || (z >= 9.5 && z < 14.0 && std::fmod(z, 1.0) < 0.2);
      },
      7.0, nullptr, false);
  EXPECT_TRUE(d.evidence.boundary) << d.evidence.reason;
  EXPECT_STREQ(d.evidence.reason, "narrow dashes (worn paint)");
}

TEST(BoundaryCandidateFinder, SeamRimInPiecesIsNoWornPaint) {
  // the same pieces as the worn dashes above, but along the seam of a flush concrete strip
  // beyond the line (grey 150 against the asphalt's 80: the sides differ by 70 grey levels, the
  // rim stands 85 above the brighter one); worn paint has the same road either side of it
  const auto pieces = [](double z) {
    return (z >= 4.0 && z < 7.0) || (z >= 9.5 && z < 14.0 && std::fmod(z, 1.0) < 0.2);
  };
  const BoundaryCandidate c = narrowLine(pieces, 7.0, nullptr, true, 0.0, 150);
  EXPECT_FALSE(c.evidence.boundary) << c.evidence.reason;
  EXPECT_STREQ(c.evidence.reason, "rim of a surface change");
  // the road beyond a little lighter (a sunlit side, grey 95: 15 levels, against the paint's
  // 140 above it) leaves the worn dashes paint
  const BoundaryCandidate d = narrowLine(pieces, 7.0, nullptr, true, 0.0, 95);
  EXPECT_TRUE(d.evidence.boundary) << d.evidence.reason;
  EXPECT_STREQ(d.evidence.reason, "narrow dashes (worn paint)");
}

TEST(BoundaryCandidateFinder, KerbLipInPiecesIsNoWornPaint) {
  // the same pieces as the worn dashes above, but on the edge of a footpath 10 cm above the road
  // (a kerb's lip lit between shadows, leaves on it): the depth measures the step, and paint
  // lies flat on the road; the line stays the kerb it is
  const BoundaryCandidate c = narrowLine(
      [](double z) {
        return (z >= 4.0 && z < 7.0) || (z >= 9.5 && z < 14.0 && std::fmod(z, 1.0) < 0.2);
      },
      7.0, nullptr, true, 0.10);
  EXPECT_TRUE(c.evidence.boundary) << c.evidence.reason;
  EXPECT_EQ(c.evidence.kind, BoundaryKind::kRoadEdge) << c.evidence.reason;
  EXPECT_STREQ(c.evidence.reason, "height step");
  EXPECT_TRUE(c.evidence.raised);
}

// Worn dashes with raised markers between them: a dash from 4 to 6 m, nothing for 2.5 m, markers
// 0.1 m long every metre from 8.5 to 11.5 m, a dash from 12 to 14 m; the line's band is 12 cm wide
// (paint) on its first @p paint_width m, 5 cm (a worn dash's core) elsewhere. The markers join
// the dash gap into one stretch (gaps shorter than 2 m), which covers 73% of the line: only the
// rows found (48%) tell the dashes.
BoundaryCandidate wornDashesWithMarkers(double paint_width) {
  return narrowLine(
      [](double z) {
        return (z >= 4.0 && z < 6.0) || (z >= 8.5 && z < 11.5 && std::fmod(z - 8.5, 1.0) < 0.1) ||
               (z >= 12.0 && z < 14.0);
      },
      6.0, [paint_width](double z) { return z < 4.0 + paint_width ? 0.12 : 0.05; });
}

TEST(BoundaryCandidateFinder, WornDashesJoinedByMarkersArePaint) {
  // paint width on about a third of the traced rows (a worn dash's best-kept part)
  const BoundaryCandidate c = wornDashesWithMarkers(0.4);
  EXPECT_TRUE(c.evidence.boundary) << c.evidence.reason;
  EXPECT_EQ(c.evidence.kind, BoundaryKind::kPaint) << c.evidence.reason;
  EXPECT_STREQ(c.evidence.reason, "narrow dashes (worn paint)");
  ASSERT_FALSE(c.trace.pixels.empty());
  for (const auto& q : c.trace.pixels) EXPECT_NEAR(test::roadLateral(q), -1.8, 0.1) << q;
  EXPECT_GE(test::roadForward(c.trace.pixels.back()), 12.0);  // followed across the markers
}

TEST(BoundaryCandidateFinder, ARaisedMarkerJoinsNoWornDashes) {
  // worn dashes (paint width on their first 0.4 m, a 5 cm core elsewhere) and one raised marker in
  // the gap between them: a point on the line, which joins the dashes into no stretch (one
  // stretch would cover the whole line, as a rail head does)
  struct Case {
    const char* what;
    double dash0[2], marker[2], dash1[2], traced;
  };
  const Case cases[] = {
      // a quarter of the rows measured; the marker 0.1 m long, in a 3 m gap, on one image row
      {"a marker on one row", {4.0, 7.0}, {8.45, 8.55}, {10.0, 11.0}, 11.0},
      // the marker 0.13 m long in a 2.5 m gap, where two image rows (0.11 m apart at 6.6 m) both
      // find it
      {"a marker on two rows", {4.0, 5.5}, {6.54, 6.67}, {8.0, 9.0}, 5.5},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.what);
    const BoundaryCandidate c = narrowLine(
        [&k](double z) {
          return (z >= k.dash0[0] && z < k.dash0[1]) || (z >= k.marker[0] && z < k.marker[1]) ||
                 (z >= k.dash1[0] && z < k.dash1[1]);
        },
        k.traced, [](double z) { return z < 4.4 ? 0.12 : 0.05; });
    EXPECT_TRUE(c.evidence.boundary) << c.evidence.reason;
    EXPECT_EQ(c.evidence.kind, BoundaryKind::kPaint) << c.evidence.reason;
    EXPECT_STREQ(c.evidence.reason, "narrow dashes (worn paint)");
  }
}

TEST(BoundaryCandidateFinder, NarrowLineWithoutPaintWidthJoinedByMarkersIsNoBoundary) {
  // the same line no row of which measures paint width (a seam's rim): its stretches tell its
  // cover, 75% of it, too much for dashes, and its 2.5 m break is none a rail head has
  const BoundaryCandidate c = wornDashesWithMarkers(0.0);
  EXPECT_FALSE(c.evidence.boundary) << c.evidence.reason;
  EXPECT_STREQ(c.evidence.reason, "broken narrow line");
}

TEST(BoundaryCandidateFinder, BrokenNarrowLineIsNoRailHead) {
  // a narrow bright line from 4 to 8 m and from 10.5 to 14 m (the rim of a seam, broken where
  // the seam is filled): a rail head runs on without a break, and the two pieces cover 75% of
  // the line, more than a dashed line's paint: no boundary
  const BoundaryCandidate c =
      narrowLine([](double z) { return (z >= 4.0 && z < 8.0) || (z >= 10.5 && z < 14.0); }, 14.0);
  EXPECT_FALSE(c.evidence.boundary) << c.evidence.reason;
  EXPECT_STREQ(c.evidence.reason, "broken narrow line");
}

// A dashed lane line (15 cm, 3 m dashes every 9 m) 1.8 m left of the camera on a level road; the
// response only a short stretch of it around 8 m ahead (too short to trace: the seed is followed
// on the image), the seed's own point at @p seed_height above the road, the other points'
// heights alternating +-@p spread. The left side's first candidate after classification.
BoundaryCandidate seededLine(double seed_height, double spread) {
  test::CrossSection cs;
  cs.colour = [](double x, double z) {
    return std::fabs(x + 1.8) < 0.075 && std::fmod(z, 9.0) < 3.0 ? test::grey(220)
                                                                   : test::grey(80);
  };
  test::RenderedRoad road;
  road.render(cs);
  // the points at the height of a ray: the ray's point scaled along it
  auto atHeight = [](cv::Vec3f& p, double h) {
    const double s = (test::kHeight - h) / test::kHeight;
    p *= static_cast<float>(s);
  };
  cv::Mat R(test::kH, test::kW, CV_32FC1, cv::Scalar(0.f));
  const auto at = [](double z) {
    return cv::Point2f(static_cast<float>(test::kK.fx * -1.8 / z + test::kK.cx),
                       static_cast<float>(test::kK.fy * test::kHeight / z + test::kK.cy));
  };
  cv::line(R, at(7.8), at(8.2), cv::Scalar(1.2), 3);
  // the seed: of the equal best matches the topmost, then the innermost (findBestMatch())
  cv::Point seed(-1, -1);
  for (int v = 0; v < test::kH && seed.y < 0; ++v)
    for (int u = 0; u < test::kW; ++u)
      if (R.at<float>(v, u) > 0.f) seed = cv::Point(u, v);
  bool odd = false;
  for (int v = 0; v < test::kH; ++v)
    for (int u = 0; u < test::kW; ++u) {
      cv::Vec3f& p = road.points.at<cv::Vec3f>(v, u);
      if (std::isnan(p[2])) continue;
      if (cv::Point(u, v) == seed) {
        atHeight(p, seed_height);
      } else if (spread > 0.0) {
        atHeight(p, (odd = !odd) ? spread : -spread);
      }
    }
  return firstLeftCandidate(road, R);
}

// The dashed line followed as paint along its whole length (x = -1.8 m).
void expectFollowedPaint(const BoundaryCandidate& c) {
  EXPECT_TRUE(c.evidence.boundary) << c.evidence.reason;
  EXPECT_EQ(c.evidence.kind, BoundaryKind::kPaint) << c.evidence.reason;
  ASSERT_GE(c.trace.pixels.size(), 20u);
  for (const auto& q : c.trace.pixels) EXPECT_NEAR(test::roadLateral(q), -1.8, 0.1) << q;
}

TEST(BoundaryCandidateFinder, SeedOnTheRoadIsFollowed) {
  expectFollowedPaint(seededLine(0.0, 0.0));
}

TEST(BoundaryCandidateFinder, SeedOnAStrayReturnAmidTheRoadIsFollowed) {
  // the seed's own point 10 cm below the road (a scan line's end), the road's around it
  expectFollowedPaint(seededLine(-0.10, 0.0));
}

TEST(BoundaryCandidateFinder, SeedOffTheRoadAmidNoisyDepthIsNotFollowed) {
  // the same seed amid depth that scatters +-3 cm (more than a quarter of the kerb height): no
  // point there can be told a stray return, and the seed's is off the road
  const BoundaryCandidate c = seededLine(-0.10, 0.03);
  EXPECT_FALSE(c.evidence.boundary && c.trace.pixels.size() >= 20u) << c.evidence.reason;
}

// A lane 3.6 m wide on a level road: a solid 15 cm line 1.8 m right of the camera, traced (its
// response 1.2), and a dashed 15 cm line (3 m dashes every 9 m) 1.8 m left whose response is
// a short stretch around 8 m ahead at @p left_score (below the trace threshold: fog, a worn line)
// and where no depth is measured (a stereo pair's smear, a LiDAR's gap). With @p right_line off
// the right line is neither painted nor matched. The left side's candidates after
// classification and traceBesidePaint(); @p added: how many traceBesidePaint() added.
std::vector<BoundaryCandidate> besidePaint(double left_score, bool right_line, int* added) {
  test::CrossSection cs;
  cs.colour = [right_line](double x, double z) {
    const bool left = std::fabs(x + 1.8) < 0.075 && std::fmod(z, 9.0) < 3.0;
    const bool right = right_line && std::fabs(x - 1.8) < 0.075;
    return left || right ? test::grey(220) : test::grey(80);
  };
  test::RenderedRoad road;
  road.render(cs);
  for (int v = 0; v < test::kH; ++v)  // no depth left of the camera's column
    for (int u = 0; u < test::kW / 2; ++u) road.points.at<cv::Vec3f>(v, u) = cv::Vec3f::all(NAN);
  const auto at = [](double x, double z) {
    return cv::Point2f(static_cast<float>(test::kK.fx * x / z + test::kK.cx),
                       static_cast<float>(test::kK.fy * test::kHeight / z + test::kK.cy));
  };
  cv::Mat R_left(test::kH, test::kW, CV_32FC1, cv::Scalar(0.f));
  cv::Mat R_right(test::kH, test::kW, CV_32FC1, cv::Scalar(0.f));
  cv::line(R_left, at(-1.8, 7.8), at(-1.8, 8.2), cv::Scalar(left_score), 3);
  if (right_line) {
    const std::vector<cv::Point2f> px = test::linePixels(1.8);
    for (size_t i = 1; i < px.size() && test::roadForward(px[i]) <= 20.0; ++i)
      cv::line(R_right, px[i - 1], px[i], cv::Scalar(1.2), 5);
  }
  RenderedRoadFinder fx(road);
  const CandidateFrame& f = fx.f;
  BoundaryCandidateFinder& finder = fx.finder;
  finder.traceLines(f, 0, R_left);
  finder.traceLines(f, 1, R_right);
  finder.classify(f);
  int classified = 0;
  finder.candidates(0, classified);
  const cv::Mat before = R_left.clone();
  finder.traceBesidePaint(f, R_left, R_right);
  EXPECT_EQ(cv::countNonZero(R_left != before), 0);  // the map is put back
  int n = 0;
  const BoundaryCandidate* c = finder.candidates(0, n);
  *added = n - classified;
  return std::vector<BoundaryCandidate>(c, c + n);
}

TEST(BoundaryCandidateFinder, FaintLineALaneWidthBesidePaintIsFollowed) {
  // the right line on paint: the left match at 0.6 (above tau_g 0.5) a lane's width from it is
  // followed without depth, along the dashed line (x = -1.8 m)
  int added = 0;
  const std::vector<BoundaryCandidate> c = besidePaint(0.6, true, &added);
  EXPECT_EQ(added, 1);
  int painted = 0;
  for (const BoundaryCandidate& k : c) {
    if (!k.evidence.boundary || k.evidence.kind != BoundaryKind::kPaint) continue;
    ++painted;
    expectFollowedPaint(k);
  }
  EXPECT_EQ(painted, 1);
}

TEST(BoundaryCandidateFinder, FaintLineWithoutPaintBesideIsNotFollowed) {
  // no painted line on the right: the same match stays below the trace threshold, unfollowed;
  // beside paint, a match under tau_g is not followed either
  for (const bool right_line : {false, true}) {
    int added = -1;
    const std::vector<BoundaryCandidate> c =
        besidePaint(right_line ? 0.45 : 0.6, right_line, &added);
    EXPECT_EQ(added, 0) << (right_line ? "a match under tau_g" : "no paint beside");
    for (const BoundaryCandidate& k : c) EXPECT_FALSE(k.evidence.boundary) << k.evidence.reason;
  }
}

// One 15 cm dash 1.8 m left of the camera, @p near to @p far m ahead, on a level road and nothing
// else (no template match: every map is zero), its centre wobbling by @p wobble m (a sine of 1 m
// period along the road): the left side's candidates after classification, traceBesidePaint()
// and traceLoneDash().
std::vector<BoundaryCandidate> loneDash(double wobble, double near = 10.0, double far = 15.0) {
  test::CrossSection cs;
  cs.colour = [wobble, near, far](double x, double z) {
    const double centre = -1.8 + wobble * std::sin(2.0 * M_PI * z);
    return std::fabs(x - centre) < 0.075 && z >= near && z <= far ? test::grey(220)
                                                                   : test::grey(80);
  };
  test::RenderedRoad road;
  road.render(cs);
  cv::Mat R_left(test::kH, test::kW, CV_32FC1, cv::Scalar(0.f));
  cv::Mat R_right(test::kH, test::kW, CV_32FC1, cv::Scalar(0.f));
  RenderedRoadFinder fx(road);
  BoundaryCandidateFinder& finder = fx.finder;
  finder.traceLines(fx.f, 0, R_left);
  finder.traceLines(fx.f, 1, R_right);
  finder.classify(fx.f);
  finder.traceBesidePaint(fx.f, R_left, R_right);
  finder.traceLoneDash(fx.f);
  int n = 0;
  const BoundaryCandidate* c = finder.candidates(0, n);
  return std::vector<BoundaryCandidate>(c, c + n);
}

// A straight dash rendered alone @p near .. @p far m ahead: one painted candidate, a lone dash,
// on its line (x = -1.8 m) over the dash's length
void expectLoneDashOnItsLine(double near, double far, double near_tol, double far_tol) {
  int painted = 0;
  for (const BoundaryCandidate& k : loneDash(0.0, near, far)) {
    if (!k.evidence.boundary || k.evidence.kind != BoundaryKind::kPaint) continue;
    ++painted;
    EXPECT_STREQ(k.evidence.reason, "lone dash");
    double nearest = 1e9, farthest = 0.0;
    for (const auto& px : k.trace.pixels) {
      const double z = test::roadForward(px);
      nearest = std::min(nearest, z);
      farthest = std::max(farthest, z);
      EXPECT_NEAR(test::kK.fx * -1.8 / z + test::kK.cx, px.x, 1.5) << "row " << px.y;
    }
    EXPECT_NEAR(nearest, near, near_tol);
    EXPECT_NEAR(farthest, far, far_tol);
  }
  EXPECT_EQ(painted, 1);
}

TEST(BoundaryCandidateFinder, OneStraightDashAloneIsPaint) {
  // no seed: the dash is found by its ridge rows, followed across no gap and taken as paint on
  // its line (x = -1.8 m, 10-15 m ahead)
  expectLoneDashOnItsLine(10.0, 15.0, 0.5, 0.7);
}

TEST(BoundaryCandidateFinder, ANearDashIsFoundOnRowsSpacedAlongTheRoad) {
  // 4-8 m ahead the image rows are 4-16 cm of road apart: the ridge scan reads one row per
  // 12.5 cm of road there, and the dash is still found whole, on its line
  expectLoneDashOnItsLine(4.0, 8.0, 0.3, 0.5);
}

TEST(BoundaryCandidateFinder, AWobblingStripAloneIsNoDash) {
  // the same stroke wobbling 8 cm either side (RMS 5.7 cm about its line, over the 2 cm and half
  // a pixel that paint keeps): a strip of light between shadows, no dash
  // and 4-9 m ahead, where the rows are read every 12.5 cm of road, as visibly
  for (const double near : {10.0, 4.0})
    for (const BoundaryCandidate& k : loneDash(0.08, near, near + 5.0))
      EXPECT_FALSE(k.evidence.boundary && k.evidence.kind == BoundaryKind::kPaint)
          << k.evidence.reason << " at " << near << " m";
}

}  // namespace
}  // namespace rgbd_lane_detector
