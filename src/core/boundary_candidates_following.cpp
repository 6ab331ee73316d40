// The candidates' classification, and the lines followed on the image: painted lines and road
// edges followed row by row from their traces, short traces from their seeds, the tracked painted
// lines where the lane model predicts them, and the road edges the depth shows.
#include "rgbd_lane_detector/boundary_candidates.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "rgbd_lane_detector/geometry.h"
#include "rgbd_lane_detector/lane_tracker.h"
#include "row_statistics.h"

namespace rgbd_lane_detector {
namespace {

constexpr double kFollowGap = 13.0;  // m: dash gaps a followed line crosses (9-12 m on motorways)
constexpr double kSeedReach = 0.3;   // m: a seed's paint is sought this far either side of it
constexpr double kSeedSpan = 1.0;    // m: the line through a seed starts this far either side
constexpr int kSeedRoadPoints = 5;   // measured points around a seed that tell its surface ...
constexpr double kSeedRoadSpread = 0.25;  // ... within this share of kerb_height of each other
constexpr double kMaxSeedHeading = 25.0 * M_PI / 180.0;  // a followed seed's line runs ahead within this
constexpr double kStrokeGap = 1.0;     // m without paint between two dashes of a followed line
constexpr double kRowsPerGap = 2.5;    // ... and more than this many image rows' road
constexpr double kStrokeLength = 8.0;  // m: one stretch of paint this long is a line (no arrow)
// m: a lone stroke shorter than the shortest lane-line dash (1 m, urban) is no lane line (a
// fragment of a marking, a glint)
constexpr double kMinStroke = 1.0;
constexpr double kDashGap = 2.0;       // m without a narrow band between two dashes of worn paint
constexpr int kMinDashes = 2;          // dashes that tell worn paint from a rail ...
constexpr double kMaxDashCoverage = 0.6;  // ... where they cover at most this share of the line
constexpr double kDashRange = 25.0;    // m ahead within which the dashes are counted
// Worn paint lies on one road surface: the road either side of it is the same asphalt, its
// brightness the same but for shading, little against the paint's own contrast. A narrow bright
// line whose two sides differ by more than this share of what it stands above the brighter one
// is the rim along a change of surface (the seam of a flush concrete strip or a patch: the two
// surfaces differ about as much as the rim stands out, more so where the camera saturates one),
// broken like dashes where the seam is filled: no paint (worn dashes measure 0.3 at most)
constexpr float kMaxSideStep = 0.5f;
// Raised pavement markers between worn dashes join them into one stretch (kDashGap): a line that
// measures paint width on at least kWornPaintRows of its rows (no rail head, seam or crack does)
// is covered where its rows are found, each row standing for at most kRowCell of road more
// than its image row (the follower measures rows about that far apart)
constexpr double kWornPaintRows = 0.25;
constexpr double kRowCell = 0.1;
// m of road around a row found within which another makes it part of a stretch of paint: rows
// along paint are found every kFollowSpacing (0.1 m) or image row; a raised pavement marker is
// 10 cm long
constexpr double kLonePoint = 0.5;
// m: a raised pavement marker's length at most (10 cm markers and Botts' dots; ceramic ones up to
// 15 cm): rows found together (each within kLonePoint of the next) that span no more than it
// and one row step (kRowCell or one image row: the rows that touch its ends) are a marker, no
// stretch of paint and no bridge between two (two rows on one marker are no dash)
constexpr double kMarkerLength = 0.15;
// share of a line's rows with paint width that make it paint somewhere (its lone rows raised
// markers): a rail head or a seam measures none
constexpr double kMarkerPaintRows = 0.1;
constexpr double kEdgeGap = 2.0;     // m: a followed road edge ends where it is not seen this long
constexpr double kEdgeReach = 0.3;   // m: a traced road edge this near a depth edge is the same
constexpr double kPredictedReach = 0.4;  // m: a predicted line's paint is sought this close
// The lane beside a painted side (traceBesidePaint()): a lane is at least this wide (m; the
// narrowest urban lanes, 2.5-2.75 m) and at most lane_width_max, and its other boundary runs
// parallel to the painted one
constexpr double kNarrowestLane = 2.5;
constexpr double kSideMaxHeading = 0.35;  // rad: a lane boundary runs along the road (the fit's)
// m ahead between which the other side's band is sought (nearer, a car's bonnet or the image's
// bottom; farther, a lane's width narrows to a few pixels and the road ahead may bend)
constexpr double kPriorNear = 3.0;
constexpr double kPriorFar = 30.0;
constexpr double kPriorShare = 0.6;  // share of the line found there that lies in the band
// One dash alone (traceLoneDash()): a ridge of paint width on an image row is a centre of
// kDashCore m (10-15 cm paint) kDashMargin clear of two flanks of kDashFlank m of road each
constexpr double kDashCore = 0.12;
constexpr double kDashMargin = 0.05;
constexpr double kDashFlank = 0.15;
// m of road within which the next row's ridge continues a stroke (rows along paint are found on
// every image row, a few centimetres to half a metre of road apart); across it, within
// kMaxSeedHeading of the road's direction and kDashSlack of lateral play (a pixel's rounding)
constexpr double kDashLink = 0.5;
constexpr double kDashSlack = 0.05;
// m of road between the rows scanned for ridges: a quarter of a link, so that a stroke bridges
// up to three rows without a ridge (dappled paint), a dash (2-10 m, kLoneDashMin) gets 16 rows
// or more, and the wobble of a sunlit strip between leaf shadows (decimetres to a metre across)
// is sampled several times per period. Near the car the image rows are a few millimetres of
// road apart (0.3 cm at 3 m on a 1080p camera) and span the widest columns: scanning each of
// them found the same ridges many times over (the scan cost 3 ms per side on a 1080p frame).
// Farther, where the rows are coarser than this, every row is scanned.
constexpr double kDashRowStep = kDashLink / 4;
// m: a lone dash, followed across no gap, is 2-10 m of road: lane-line dashes are 3-6 m of
// paint (issue 26; the rows at either end add up to a row's road, half a metre at 30 m); a
// shorter stroke is a marking's fragment, a longer one no dash (a line the templates find)
constexpr double kLoneDashMin = 2.0;
constexpr double kLoneDashMax = 10.0;
// m: machine-laid paint is straight: its ridge rows lie within a centimetre or two of a straight
// line on the road (and half a pixel's rounding); a strip of sunlight between the shadows of
// leaves wobbles by several centimetres
constexpr double kDashWobble = 0.02;

// The first index from @p i on (up to @p n) whose flag is set in @p flags, which has
// kFlagBlock zero bytes past @p n: a block of flags at a time (most are clear).
constexpr int kFlagBlock = 8;
int nextFlag(const uint8_t* flags, int i, int n) {
  for (uint64_t block = 0; i < n; i += kFlagBlock) {
    std::memcpy(&block, flags + i, kFlagBlock);
    if (block != 0) break;
  }
  while (i < n && flags[i] == 0) ++i;
  return std::min(i, n);
}

// @p sums[i]: the sum of @p grey[0 .. i - 1], for i = 0 .. n (four at a time: one add each).
void prefixSums(const uint8_t* grey, int n, int* sums) {
  int acc = 0, i = 0;
  *sums++ = 0;
  for (; i + 4 <= n; i += 4, grey += 4, sums += 4) {
    sums[0] = acc += grey[0];
    sums[1] = acc += grey[1];
    sums[2] = acc += grey[2];
    sums[3] = acc += grey[3];
  }
  for (; i < n; ++i) *sums++ = acc += *grey++;
}

// Road-plane coordinates (forward, lateral left) of the input pixel (u, v): its ray met with the
// road plane of @p f in @p frame; false where the ray does not meet the road ahead.
bool roadCoordinates(const CandidateFrame& f, const RoadFrame& frame, double u, double v,
                     Eigen::Vector2d& q) {
  const Eigen::Vector3d ray = f.K.ray(u, v);
  double z = 0.0;
  if (!rayPlaneDepth(*f.road, ray, z)) return false;
  q = frame.toRoad(ray * z);
  return true;
}

// A trace cut short by the classifier (cutAtObject: the line ends at a vehicle) keeps its
// points and scores for its pixels only.
void matchLengths(MarkerTrace& m) {
  if (m.points.size() > m.pixels.size()) m.points.resize(m.pixels.size());
  if (m.scores.size() > m.pixels.size()) m.scores.resize(m.pixels.size());
}


// The processing pixel of input pixel @p p (pixel centres scaled; columns rounded toward the
// image centre, as the tracing does).
cv::Point processingPixel(const CandidateFrame& f, const cv::Point2f& p) {
  const cv::Point2d q = f.toProcessing(p);
  return cv::Point(roundColumn(q.x, f.proc_size.width), static_cast<int>(std::lround(q.y)));
}

}  // namespace

void BoundaryCandidateFinder::classify(const CandidateFrame& f) {
  if (!params_.classify_boundaries || f.road == nullptr || !f.road->valid) {
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < counts_[side]; ++k) {
        BoundaryEvidence& ev = candidates_[side][k].evidence;
        ev = BoundaryEvidence();
        ev.boundary = true;  // unclassified: every traced line is taken as paint
        ev.margin = 0.5f;
      }
    return;
  }
  classifierInputOf(f, *f.road, classifier_input_);
  for (int side = 0; side < 2; ++side)
    for (int k = 0; k < counts_[side]; ++k) classifyCandidate(f, side, candidates_[side][k], false);
  followPredictedLines(f);
  addRoadEdgesFromDepth(f);
}

void BoundaryCandidateFinder::classifyCandidate(const CandidateFrame& f, int side,
                                                BoundaryCandidate& c, bool prior) {
  const ClassifierInput& in = classifier_input_;
  if (static_cast<int>(c.trace.pixels.size()) < params_.min_marker_points)
    followFromSeed(f, side == 0, c.trace, prior);
  classifier_.classify(in, c.trace.pixels, side == 0, params_, c.evidence);
  matchLengths(c.trace);
  // (a narrow line: a rail head, or one that no depth measures; either may be worn paint)
  if (c.evidence.kind == BoundaryKind::kRoadEdge && c.evidence.narrowLine())
    dashedNarrowLine(f, side, c);
  // a painted line: on the paint's centre, row by row, and as far as it goes (where most of
  // its rows measured paint width, only rows of paint-like width steer it; worn paint's
  // narrow core is followed on its narrow rows)
  if (c.evidence.boundary && c.evidence.kind == BoundaryKind::kPaint) {
    classifier_.followLine(in, c.trace.pixels, c.trace.points, params_, kFollowGap,
                           params_.max_depth, BoundaryClassifier::kTraceReach,
                           2 * c.evidence.paint_rows > c.evidence.rows);
    if (classifier_.cutAtObject(in, c.trace.pixels, side == 0, params_)) matchLengths(c.trace);
    double stroke = 0.0;  // m of road a lone stroke covers
    if (loneStroke(f, c.trace.pixels, &stroke)) {
      if (stroke < kMinStroke) {  // (no marking's fragment is a lane line)
        c.evidence.boundary = false;
        c.evidence.reason = "short stroke";
        return;
      }
      if (classifier_.arrowHead(in, c.trace.pixels, params_)) {
        c.evidence.boundary = false;
        c.evidence.reason = "lane arrow";
        return;
      }
    }
    const bool moved =
        classifier_.centreDoubleLine(in, c.trace.pixels, c.trace.points, params_);
    // a trace where depth is missing (near the car) told its kind by colour alone: the line
    // followed into the depth tells it again (a kerb's bright top is no paint); it is cut at
    // a vehicle already (cutAtObject() above), again only if the double line's centre moved
    // it
    if (!std::isfinite(c.evidence.line_height)) {
      classifier_.classify(in, c.trace.pixels, side == 0, params_, c.evidence, moved);
      matchLengths(c.trace);
      if (c.evidence.kind == BoundaryKind::kRoadEdge && c.evidence.narrowLine())
        dashedNarrowLine(f, side, c);
    }
  }
  // a kerb or an unpainted edge: where the road surface ends, as far as it goes (not a
  // rail: its head is it)
  if (c.evidence.boundary && c.evidence.kind == BoundaryKind::kRoadEdge &&
      !c.evidence.narrowLine())
    classifier_.followEdge(in, c.trace.pixels, c.trace.points, side == 0, params_, kEdgeGap,
                           params_.max_depth);
}

bool BoundaryCandidateFinder::hasPaintedBoundary(int side) const {
  for (int k = 0; k < counts_[side]; ++k)
    if (candidates_[side][k].evidence.boundary &&
        candidates_[side][k].evidence.kind == BoundaryKind::kPaint)
      return true;
  return false;
}

bool BoundaryCandidateFinder::paintedSideLine(const CandidateFrame& f, int side, double& a,
                                              double& b) {
  // the nearest painted line of the side where an ego boundary can be, as a straight line on the
  // road (the lane fit measures it so)
  const RoadFrame& frame = classifier_input_.frame;
  bool have = false;
  for (int k = 0; k < counts_[side]; ++k) {
    const BoundaryCandidate& c = candidates_[side][k];
    if (!c.evidence.boundary || c.evidence.kind != BoundaryKind::kPaint) continue;
    prior_road_.clear();
    for (const auto& px : c.trace.pixels) {
      Eigen::Vector2d q;
      if (roadCoordinates(f, frame, px.x, px.y, q) && q.x() > 0.0) prior_road_.push_back(q);
    }
    if (static_cast<int>(prior_road_.size()) < params_.min_marker_points) continue;
    double ca = 0.0, cb = 0.0;
    if (!fitRobustLine(prior_road_, 0.3, ca, cb)) continue;
    const double beside = side == 0 ? ca : -ca;
    if (beside < params_.boundary_offset_min || beside > params_.boundary_offset_max ||
        std::fabs(std::atan(cb)) > kSideMaxHeading)
      continue;
    if (have && std::fabs(ca) >= std::fabs(a)) continue;
    a = ca;
    b = cb;
    have = true;
  }
  return have;
}

void BoundaryCandidateFinder::traceBesidePaint(const CandidateFrame& f, cv::Mat& R_left,
                                               cv::Mat& R_right) {
  if (!params_.classify_boundaries || f.road == nullptr || !f.road->valid) return;
  const ClassifierInput& in = classifier_input_;  // set by classify()
  for (int side = 0; side < 2; ++side) {
    // a side whose search found no painted boundary, beside one found on paint
    double a = 0.0, b = 0.0;
    if (hasPaintedBoundary(side) || !paintedSideLine(f, 1 - side, a, b)) continue;
    // where this side's boundary can be: a lane's width from the painted one, parallel to it,
    // and where an ego boundary can be (lateral at the vehicle, + left)
    const double sign = side == 0 ? 1.0 : -1.0;
    const double w_max = params_.lane_width_max > 0.0 ? params_.lane_width_max
                                                      : std::numeric_limits<double>::infinity();
    double lo = a + sign * kNarrowestLane, hi = a + sign * w_max;
    if (lo > hi) std::swap(lo, hi);
    const double own_lo = side == 0 ? params_.boundary_offset_min : -params_.boundary_offset_max;
    const double own_hi = side == 0 ? params_.boundary_offset_max : -params_.boundary_offset_min;
    lo = std::max(lo, own_lo);
    hi = std::min(hi, own_hi);
    if (!(lo < hi)) continue;
    cv::Mat& R = side == 0 ? R_left : R_right;
    if (!laneBand(f, in.frame, lo, hi, b)) continue;
    // the best match there off the lines already traced on this side (put back afterwards)
    restore_.clear();
    for (int k = 0; k < counts_[side]; ++k)
      excludeTrace(f, R, candidates_[side][k].trace, cv::Point(-1, -1));
    float best = 0.f;
    cv::Point peak(-1, -1);
    for (int y = f.roi.y; y < f.roi.y + f.roi.height; ++y) {
      const int l = band_lo_[y], h = band_hi_[y];
      if (l > h) continue;
      const float* r = R.ptr<float>(y);
      const int step = side == 0 ? -1 : 1;  // of equal ones the innermost
      for (int x = side == 0 ? h : l, n = h - l + 1; n > 0; x += step, --n)
        if (r[x] > best) {
          best = r[x];
          peak = cv::Point(x, y);
        }
    }
    for (const auto& r : restore_) *r.first = r.second;
    restore_.clear();
    // a match the geometric map is trusted on (priorSeedScore()): the lane beside the painted
    // side is the prior that the seed search lacks
    if (!(best > priorSeedScore()) || offRoad(f, peak)) continue;
    BoundaryCandidate& c = next(side);
    MarkerTrace& m = c.trace;
    startTrace(m);
    m.angle_valid = false;  // (its line is followed from the seed, or traced on the template's)
    m.angle = f.template_angle[side];
    buildTrace(f, R, peak, best, m.angle, m);
    m.peak_score = best;
    classifyCandidate(f, side, c, true);
    // paint by its width: a narrow line (BoundaryEvidence::narrowLine()) is paint only by
    // inference (worn dashes), too little on a match under the trace threshold (a seam's or a
    // flush concrete strip's rim, broken by shadows, reads so)
    if (!c.evidence.boundary || c.evidence.kind != BoundaryKind::kPaint ||
        c.evidence.narrowLine())
      continue;
    // the line found lies in the band (a followed line can run off it)
    int inside = 0, total = 0;
    for (const auto& px : m.pixels) {
      Eigen::Vector2d q;
      if (!roadCoordinates(f, in.frame, px.x, px.y, q)) continue;
      ++total;
      const double off = q.y() - b * q.x();
      inside += off >= lo && off <= hi;
    }
    if (total < params_.min_marker_points || inside < kPriorShare * total) continue;
    ++counts_[side];
  }
}

bool BoundaryCandidateFinder::laneBand(const CandidateFrame& f, const RoadFrame& frame,
                                       double lo, double hi, double b) {
  // per processing row, the columns between the road lines lateral = lo + b x and hi + b x
  // (straight on the road: straight on the image, between kPriorNear and kPriorFar ahead)
  band_lo_.assign(f.proc_size.height, 1);
  band_hi_.assign(f.proc_size.height, 0);
  cv::Point2d ends[2][2];
  for (int e = 0; e < 2; ++e) {
    const double lat = e == 0 ? lo : hi;
    for (int k = 0; k < 2; ++k) {
      const double x = k == 0 ? kPriorNear : kPriorFar;
      const Eigen::Vector3d p = frame.toCamera(x, lat + b * x);
      if (!(p.z() > 0.1)) return false;
      ends[e][k] = f.toProcessing(f.K.project(p));
    }
  }
  bool any = false;
  const int y0 =
      std::max(f.roi.y, static_cast<int>(std::ceil(std::max(ends[0][1].y, ends[1][1].y))));
  const int y1 = std::min(f.roi.y + f.roi.height - 1,
                          static_cast<int>(std::floor(std::min(ends[0][0].y, ends[1][0].y))));
  for (int y = y0; y <= y1; ++y) {
    double u[2];
    for (int e = 0; e < 2; ++e) {
      const cv::Point2d& n = ends[e][0];
      const cv::Point2d& r = ends[e][1];
      if (!(std::fabs(n.y - r.y) > 1e-6)) return false;
      u[e] = n.x + (y - n.y) * (r.x - n.x) / (r.y - n.y);
    }
    const int l = std::max(f.roi.x, static_cast<int>(std::floor(std::min(u[0], u[1]))));
    const int h = std::min(f.roi.x + f.roi.width - 1,
                           static_cast<int>(std::ceil(std::max(u[0], u[1]))));
    if (l > h) continue;
    band_lo_[y] = l;
    band_hi_[y] = h;
    any = true;
  }
  return any;
}

int BoundaryCandidateFinder::paintStretches(const CandidateFrame& f,
                                            const std::vector<cv::Point2f>& pixels, double gap,
                                            double* extent, double* painted, double max_forward,
                                            double* rows_cover, bool lone_points) const {
  int stretches = 0;
  double near_f = std::numeric_limits<double>::infinity(), far_f = -near_f, last_f = 0.0;
  double start_f = 0.0, covered = 0.0, cells = 0.0, last_cell = 0.0;
  const RoadFrame& frame = classifier_input_.frame;
  // forward distance of pixels[i] (NaN: not on the road)
  const auto forwardAt = [&](size_t i) {
    Eigen::Vector2d q;
    return i < pixels.size() && roadCoordinates(f, frame, pixels[i].x, pixels[i].y, q)
               ? q.x()
               : std::numeric_limits<double>::quiet_NaN();
  };
  // metres of road one image row spans at pixels[i] (infinite: not on the road)
  const auto rowMetres = [&](size_t i, double fwd) {
    Eigen::Vector2d q1;
    return roadCoordinates(f, frame, pixels[i].x, pixels[i].y - 1.0, q1)
               ? std::fabs(q1.x() - fwd)
               : std::numeric_limits<double>::infinity();
  };
  // rows pixels[i] and pixels[i + 1] lie within kLonePoint of road of each other (kRowsPerGap
  // rows far away): one group of rows found together
  const auto together = [&](size_t i) {
    const double a = forwardAt(i), b = forwardAt(i + 1);
    if (!std::isfinite(a) || !std::isfinite(b)) return false;
    const double ra = rowMetres(i, a), rb = rowMetres(i + 1, b);
    const double row_m =
        std::max(std::isfinite(ra) ? ra : 0.0, std::isfinite(rb) ? rb : 0.0);
    const double near_gap = std::max(kLonePoint, kRowsPerGap * row_m);
    return std::fabs(b - a) <= near_gap;
  };
  size_t group_end = 0;      // one past the last row of the group pixels[i] is in
  bool group_point = false;  // that group is a point on the line
  for (size_t i = 0; i < pixels.size(); ++i) {  // near to far
    const cv::Point2f& px = pixels[i];
    Eigen::Vector2d q;
    if (lone_points && i >= group_end) {
      // a group of rows found together that spans no more than a raised pavement marker (one
      // row, or two on one marker) is a point on the line (a marker, a grain of paint): no
      // stretch of paint, and no bridge between two
      group_end = i + 1;
      while (group_end < pixels.size() && together(group_end - 1)) ++group_end;
      const double a = forwardAt(i), b = forwardAt(group_end - 1);
      const double step = std::max(kRowCell, std::isfinite(b) ? rowMetres(group_end - 1, b) : 0.0);
      group_point = !(std::fabs(b - a) > kMarkerLength + step);
    }
    if (lone_points && group_point) continue;
    if (!roadCoordinates(f, frame, px.x, px.y, q)) continue;
    const double fwd = q.x();
    if (fwd > max_forward) continue;
    // far away one image row spans more road than the gap: rows found on neighbouring rows
    // are one stretch (kRowsPerGap rows without paint make a gap there)
    const double row_m = rowMetres(i, fwd);
    if (stretches > 0) cells += std::min(last_cell, std::fabs(fwd - last_f));
    last_cell = kRowCell + (std::isfinite(row_m) ? row_m : 0.0);
    if (stretches == 0 || std::fabs(fwd - last_f) > std::max(gap, kRowsPerGap * row_m)) {
      if (stretches > 0) covered += std::fabs(last_f - start_f);
      ++stretches;
      start_f = fwd;
    }
    last_f = fwd;
    near_f = std::min(near_f, fwd);
    far_f = std::max(far_f, fwd);
  }
  if (stretches > 0) covered += std::fabs(last_f - start_f);
  if (extent) *extent = stretches > 0 ? far_f - near_f : 0.0;
  if (painted) *painted = covered;
  if (rows_cover) *rows_cover = cells;
  return stretches;
}

bool BoundaryCandidateFinder::followed(const ClassifierInput& in, double reach,
                                       bool seed_line) {
  // seed_pixels_ followed row by row; the rows found replace them (with their points) only when
  // there are enough of them
  const int found = classifier_.followLine(in, seed_pixels_, seed_points_, params_, kFollowGap,
                                           params_.max_depth, reach, false, seed_line);
  return found >= std::max(params_.min_marker_points, 3) &&
         seed_points_.size() == seed_pixels_.size();
}

bool BoundaryCandidateFinder::runsAhead(const CandidateFrame& f,
                                         const std::vector<cv::Point2f>& pixels) const {
  // from its nearest to its farthest row, in road coordinates
  Eigen::Vector2d a(0.0, 0.0), b(0.0, 0.0);
  bool have = false;
  for (const auto& px : pixels) {
    Eigen::Vector2d q;
    if (!roadCoordinates(f, classifier_input_.frame, px.x, px.y, q)) continue;
    if (!have) a = q;
    b = q;
    have = true;
  }
  const Eigen::Vector2d t = b - a;
  return have && t.x() > 0.0 && std::fabs(t.y()) <= std::tan(kMaxSeedHeading) * t.x();
}

bool BoundaryCandidateFinder::loneStroke(const CandidateFrame& f,
                                          const std::vector<cv::Point2f>& pixels,
                                          double* length) const {
  // paint on two stretches (dashes) or over a length no arrow has is a lane line
  double extent = 0.0;
  const bool lone =
      paintStretches(f, pixels, kStrokeGap, &extent) < 2 && !(extent >= kStrokeLength);
  if (length) *length = extent;
  return lone;
}

void BoundaryCandidateFinder::dashedNarrowLine(const CandidateFrame& f, int side,
                                               BoundaryCandidate& c) {
  // paint lies flat on the road: a line that the depth measures as a height step is a kerb, and
  // its lit lip broken into pieces (shadows, leaves, a worn edge) is no worn paint
  if (c.evidence.raised) return;
  // a rail head runs on without a break; a line narrower than paint that comes in dashes is worn
  // paint (the bright core of a faded dash measures a few centimetres)
  seed_pixels_.assign(c.trace.pixels.begin(), c.trace.pixels.end());
  seed_points_.clear();
  const ClassifierInput& in = classifier_input_;
  double extent = 0.0, painted = 0.0;
  if (!followed(in, BoundaryClassifier::kTraceReach)) return;
  // (a line followed past a vehicle ahead is the line up to it: no dash on the vehicle counts)
  if (classifier_.cutAtObject(in, seed_pixels_, side == 0, params_))
    seed_points_.resize(seed_pixels_.size());
  // within kDashRange, where a rail head is resolved on every row (farther, any thin line
  // breaks up)
  double rows_cover = 0.0;
  // (on a line that measures paint width on some of its rows, a raised marker found alone in a
  // dash gap is no stretch of paint and joins no dashes)
  const bool markers = c.evidence.paint_rows >= kMarkerPaintRows * c.evidence.rows;
  const int dashes = paintStretches(f, seed_pixels_, kDashGap, &extent, &painted, kDashRange,
                                    &rows_cover, markers);
  // markers nearer each other join dashes into stretches: on a line that measures paint width
  // on enough of its rows (no rail head, seam or crack does), the rows found tell the cover
  if (c.evidence.paint_rows >= kWornPaintRows * c.evidence.rows) painted = rows_cover;
  if (dashes < kMinDashes) return;  // unbroken: a rail head
  if (std::fabs(c.evidence.step_contrast) > kMaxSideStep * c.evidence.ridge_contrast) {
    c.evidence.boundary = false;
    c.evidence.reason = "rim of a surface change";
    return;
  }
  if (painted > kMaxDashCoverage * extent) {
    // broken by gaps of kDashGap, which no rail head has, but not into dashes (it covers more
    // of the line than dashes do): the bright rim of a seam or a crack, no lane boundary
    c.evidence.boundary = false;
    c.evidence.reason = "broken narrow line";
    return;
  }
  c.trace.pixels.assign(seed_pixels_.begin(), seed_pixels_.end());
  c.trace.points.assign(seed_points_.begin(), seed_points_.end());
  c.trace.scores.resize(c.trace.pixels.size(), c.trace.peak_score);
  c.evidence.boundary = true;
  c.evidence.kind = BoundaryKind::kPaint;
  c.evidence.reason = "narrow dashes (worn paint)";
}

bool BoundaryCandidateFinder::followFromSeed(const CandidateFrame& f, bool left, MarkerTrace& m,
                                             bool prior) {
  const ClassifierInput& in = classifier_input_;  // set by classify()
  const double seed_score = prior ? priorSeedScore() : params_.trace_threshold;
  if (!(m.peak_score > seed_score) || m.seed.x < 0.f) return false;
  // the seed lies on the road where the depth measures it (a match without depth, on a wall, a
  // car or a kerb top, or where the road plane only fills missing depth, is followed nowhere);
  // with a prior (a lane's width beside a painted line) a seed that no depth measures is
  // followed, one that the depth puts off the road is not
  const Eigen::Vector3f& sp = m.seed_point;
  if (!sp.allFinite()) {
    if (!prior) return false;
  } else if (std::fabs(f.road->normal.cast<float>().dot(sp) +
                       static_cast<float>(f.road->distance)) > params_.kerb_height &&
             !roadAround(f, m.seed)) {
    return false;
  }
  if (f.filled != nullptr && !prior) {
    const cv::Point q = processingPixel(f, m.seed);
    const int px = q.x, py = q.y;
    if (px >= 0 && py >= 0 && px < f.filled->cols && py < f.filled->rows && f.filled->at<uint8_t>(py, px) != 0)
      return false;
  }
  Eigen::Vector2d q;
  if (!roadCoordinates(f, in.frame, m.seed.x, m.seed.y, q)) return false;
  // an ego-lane boundary's distance beside the camera (lateral: + left)
  const double beside = left ? q.y() : -q.y();
  if (beside < params_.boundary_offset_min || beside > params_.boundary_offset_max) return false;
  // the line through the seed straight ahead on the road (ego-lane lines run with the vehicle)
  seed_pixels_.clear();
  seed_points_.clear();
  for (double df : {-kSeedSpan, 0.0, kSeedSpan}) {
    const Eigen::Vector3d p = in.frame.toCamera(q.x() + df, q.y());
    if (!(p.z() > 0.1)) continue;
    seed_pixels_.emplace_back(f.K.project(p));
  }
  if (seed_pixels_.size() < 2 || !followed(in, kSeedReach, true)) return false;
  if (loneStroke(f, seed_pixels_) || !runsAhead(f, seed_pixels_)) return false;
  m.pixels.assign(seed_pixels_.begin(), seed_pixels_.end());
  m.points.assign(seed_points_.begin(), seed_points_.end());
  m.scores.assign(m.pixels.size(), m.peak_score);
  m.num_valid_points = 0;
  for (const auto& p : m.points) m.num_valid_points += !std::isnan(p.z());
  return true;
}

bool BoundaryCandidateFinder::roadAround(const CandidateFrame& f, const cv::Point2f& seed) {
  // the measured points (not the plane filled in) around the seed's processing pixel: on the
  // road, and agreeing with each other (clean depth), so that the seed's own point, off the
  // road, is a stray return (a scan line's end); on noisy depth no point can be told stray
  const cv::Point c = processingPixel(f, seed);
  const int cx = c.x, cy = c.y;
  const int h = std::max(1, params_.template_size / 4);
  const cv::Rect box = cv::Rect(cx - h, cy - h, 2 * h + 1, 2 * h + 1) & f.roi;
  const Eigen::Vector3f n = f.road->normal.cast<float>();
  const float d = static_cast<float>(f.road->distance);
  seed_heights_.clear();
  for (int y = box.y; y < box.y + box.height; ++y) {
    const cv::Vec3f* p = f.points->ptr<cv::Vec3f>(y);
    const uint8_t* fill = f.filled != nullptr ? f.filled->ptr<uint8_t>(y) : nullptr;
    for (int x = box.x; x < box.x + box.width; ++x) {
      if ((fill != nullptr && fill[x] != 0) || std::isnan(p[x][2])) continue;
      seed_heights_.push_back(n.x() * p[x][0] + n.y() * p[x][1] + n.z() * p[x][2] + d);
    }
  }
  if (static_cast<int>(seed_heights_.size()) < kSeedRoadPoints) return false;
  const float road = median(seed_heights_);
  if (!(std::fabs(road) <= params_.kerb_height)) return false;
  for (float& v : seed_heights_) v = std::fabs(v - road);  // their spread: the median deviation
  return median(seed_heights_) <= kSeedRoadSpread * params_.kerb_height;
}

template <typename Lateral>
bool BoundaryCandidateFinder::candidateOnLine(const CandidateFrame& f, int side, BoundaryKind kind,
                                              const RoadFrame& frame, double reach,
                                              Lateral&& lateral) const {
  for (int k = 0; k < counts_[side]; ++k) {
    const BoundaryCandidate& c = candidates_[side][k];
    if (!c.evidence.boundary || c.evidence.kind != kind) continue;
    int near = 0, total = 0;
    for (const auto& px : c.trace.pixels) {
      Eigen::Vector2d q;
      if (!roadCoordinates(f, frame, px.x, px.y, q)) continue;
      ++total;
      if (std::fabs(q.y() - lateral(q.x())) <= reach) ++near;
    }
    if (total >= params_.min_marker_points && near >= 0.6 * total) return true;
  }
  return false;
}

void BoundaryCandidateFinder::followPredictedLines(const CandidateFrame& f) {
  const PlaneEstimate& previous = f.fitter->previousPlane();
  if (!params_.track_lanes || !previous.valid) return;
  const ClassifierInput& in = classifier_input_;  // set by classify()
  const RoadFrame frame = RoadFrame::fromPlane(*f.road);
  for (int side = 0; side < 2; ++side) {
    if (!f.fitter->tracker().valid(side) || f.fitter->sideKind(side) != BoundaryKind::kPaint)
      continue;
    const LaneTracker& tracker = f.fitter->tracker();
    if (candidateOnLine(f, side, BoundaryKind::kPaint, frame, kPredictedReach,
                        [&](double f) { return tracker.lateral(side, f); }))
      continue;  // the seeds found it: nothing to add
    BoundaryCandidate& c = next(side);
    MarkerTrace& m = c.trace;
    m.pixels.clear();
    m.points.clear();
    m.scores.clear();
    f.fitter->tracker().sample(side, frame, 1.0, samples_);
    for (const auto& q : samples_) {
      if (!(q.z() > 0.1f)) continue;
      const cv::Point2f px(f.K.project(q));
      m.pixels.push_back(px);
      m.points.push_back(pointAt(f, cv::Point2f(f.toProcessing(px))));
      m.scores.push_back(0.f);
    }
    if (m.pixels.size() < 2) continue;
    if (classifier_.followLine(in, m.pixels, m.points, params_, kFollowGap, params_.max_depth,
                               kPredictedReach) < params_.min_marker_points)
      continue;
    classifier_.classify(in, m.pixels, side == 0, params_, c.evidence);
    matchLengths(m);
    if (!c.evidence.boundary || c.evidence.kind != BoundaryKind::kPaint) continue;
    m.found = false;
    m.kind = BoundaryKind::kPaint;
    m.peak_score = static_cast<float>(params_.trace_threshold);
    m.seed = m.pixels.front();
    m.seed_point = m.points.front();
    m.angle_valid = false;
    m.num_valid_points = static_cast<int>(m.points.size());
    for (size_t i = 0; i < m.scores.size(); ++i) m.scores[i] = m.peak_score;
    m.scores.resize(m.pixels.size(), m.peak_score);
    ++counts_[side];
  }
}

void BoundaryCandidateFinder::addRoadEdgesFromDepth(const CandidateFrame& f) {
  RoadEdgeSettings s;
  s.kerb_height = params_.kerb_height;
  s.offset_min = params_.boundary_offset_min;
  s.offset_max = params_.boundary_offset_max;
  s.max_range = std::max(params_.road_fit_range, 1.0);
  s.normal_window = params_.normal_window;
  edge_finder_.find(*f.points, f.filled, f.roi_rows, f.K, *f.col_map, *f.row_map, *f.road, s,
                    depth_edges_[0], depth_edges_[1]);
  const ClassifierInput& in = classifier_input_;  // set by classify()
  for (int side = 0; side < 2; ++side) {
    const RoadEdgeLine& e = depth_edges_[side];
    if (!e.found) continue;
    const double a = e.offset, b = std::tan(e.heading);
    if (candidateOnLine(f, side, BoundaryKind::kRoadEdge, in.frame, kEdgeReach,
                        [a, b](double f) { return a + b * f; }))
      continue;  // traced already
    BoundaryCandidate& c = next(side);
    MarkerTrace& m = c.trace;
    m.found = false;
    m.kind = BoundaryKind::kRoadEdge;
    m.pixels.assign(e.pixels.begin(), e.pixels.end());
    m.points.assign(e.points.begin(), e.points.end());
    m.scores.assign(e.pixels.size(), static_cast<float>(params_.trace_threshold));
    m.peak_score = static_cast<float>(params_.trace_threshold);
    m.seed = m.pixels.front();
    m.seed_point = m.points.front();
    m.angle_valid = false;
    m.num_valid_points = static_cast<int>(m.points.size());
    // (its rows are the depth's own measurement of the edge: not moved by the colours, which a
    // gutter's leaves or an overexposed kerb mislead)
    classifier_.classify(in, m.pixels, side == 0, params_, c.evidence);
    matchLengths(m);
    if (!c.evidence.boundary || c.evidence.kind != BoundaryKind::kRoadEdge) continue;
    ++counts_[side];
  }
}

bool BoundaryCandidateFinder::longestRidgeStroke(const CandidateFrame& f, int side) {
  const ClassifierInput& in = classifier_input_;  // set by classify()
  const double sign = side == 0 ? 1.0 : -1.0;  // lateral: + left
  ridges_.clear();
  strokes_.clear();
  live_.clear();
  const int v0 = std::max(in.grey_rows.start, 0);
  const int v1 = std::min(in.grey_rows.end, f.input_size.height);
  double scanned = -std::numeric_limits<double>::infinity();  // the last scanned row's distance
  for (int v = v1 - 1; v >= v0; --v) {  // near to far
    double fc = 0.0, ppm = 0.0;
    if (!in.roadAt(f.K.cx, v, fc, ppm) || fc < kPriorNear || fc > kPriorFar ||
        fc - scanned < kDashRowStep)
      continue;
    // the strokes a ridge of this row can continue (those ended farther behind are done; with
    // a quarter of the distance's margin: across a row of a rolled road the forward distance
    // changes by several percent per degree of roll)
    live_.erase(std::remove_if(live_.begin(), live_.end(),
                               [&](int k) {
                                 return fc - strokes_[k].last.x() > kDashLink + 0.25 * fc;
                               }),
                live_.end());
    const ImageRow row(in, v);
    if (!row.valid()) continue;
    // the columns where an ego boundary can be on this row (straight ahead at its distance)
    const Eigen::Vector3d a = in.frame.toCamera(fc, sign * params_.boundary_offset_min);
    const Eigen::Vector3d b = in.frame.toCamera(fc, sign * params_.boundary_offset_max);
    if (!(a.z() > 0.1) || !(b.z() > 0.1)) continue;
    const double ua = f.K.project(a).x, ub = f.K.project(b).x;
    const int hw = std::max(1, static_cast<int>(std::lround(0.5 * kDashCore * ppm)));
    const int gap = std::max(1, static_cast<int>(std::lround(kDashMargin * ppm)));
    const int fw = std::max(2, static_cast<int>(std::lround(kDashFlank * ppm)));
    const int reach = hw + gap + fw;
    const int lo = std::max(static_cast<int>(std::floor(std::min(ua, ub))), reach);
    const int hi = std::min(static_cast<int>(std::ceil(std::max(ua, ub))),
                            f.input_size.width - 1 - reach);
    if (lo > hi) continue;
    scanned = fc;
    // the row's grey prefix sums from lo - reach
    const int first = lo - reach, n = hi + reach - first + 1;
    row_grey_.resize(static_cast<size_t>(n));
    row.greyRun(first, n, row_grey_.data());
    row_sums_.resize(static_cast<size_t>(n) + 1);
    prefixSums(row_grey_.data(), n, row_sums_.data());
    const auto mean = [&](int u, int count) {
      return static_cast<float>(row_sums_[u - first + count] - row_sums_[u - first]) / count;
    };
    // the columns whose core's mean stands above the brighter flank's by a ridge's least rise
    // (kMinContrast, and paint_contrast of the flank), on the integer sums each scaled by the
    // other window's width (no division), less a hundredth of a grey level for the float means'
    // rounding below: a branch-free pass the compiler vectorises, so that only the few columns
    // it keeps are measured exactly. (In float: the sums and their products are whole numbers
    // below 2^24 up to 4K images, so exact, and above it rounded by far less than the allowance.)
    const int core = 2 * hw + 1, cols = hi - lo + 1;
    const float core_f = static_cast<float>(core), fw_f = static_cast<float>(fw);
    const float allowance = 0.01f * core_f * fw_f;
    const float min_rise = BandProfile::kMinContrast * core_f * fw_f - allowance;
    const float contrast = static_cast<float>(params_.paint_contrast) * core_f;
    row_kept_.assign(static_cast<size_t>(cols) + kFlagBlock, 0);
    const int* sums = row_sums_.data();  // column lo + i: its left flank from sums[i] on
    uint8_t* kept = row_kept_.data();
    for (int i = 0; i < cols; ++i) {
      const float centre = static_cast<float>(sums[i + reach + hw + 1] - sums[i + reach - hw]);
      const float left = static_cast<float>(sums[i + fw] - sums[i]);
      const float right = static_cast<float>(sums[i + 2 * reach + 1] - sums[i + 2 * reach + 1 - fw]);
      const float back = std::max(left, right);
      kept[i] = centre * fw_f - back * core_f >= std::max(min_rise, contrast * back - allowance);
    }
    // each run of columns whose centre stands out of both flanks (the same road either side:
    // kMaxSideStep) gives its strongest column as the row's ridge
    int best_u = -1;
    float best = 0.f;
    for (int i = 0; i <= cols; ++i) {
      if (best_u < 0) i = nextFlag(kept, i, cols);  // no run open: on to the next kept column
      const int u = lo + i;
      float ridge = 0.f;
      if (i < cols && kept[i]) {
        const float centre = mean(u - hw, core);
        const float l = mean(u - hw - gap - fw, fw), r = mean(u + hw + gap + 1, fw);
        const float back = std::max(l, r);
        const float rise = centre - back;
        if (rise >= std::max(BandProfile::kMinContrast,
                             static_cast<float>(params_.paint_contrast) * back) &&
            std::fabs(l - r) <= kMaxSideStep * rise)
          ridge = rise;
      }
      if (ridge > 0.f) {
        if (ridge > best) best = ridge, best_u = u;
        continue;
      }
      if (best_u < 0) continue;
      Eigen::Vector2d q;
      const cv::Point2f px(static_cast<float>(best_u), static_cast<float>(v));
      best_u = -1;
      best = 0.f;
      if (!roadCoordinates(f, in.frame, px.x, px.y, q)) continue;
      // the first stroke it continues (its last ridge within kDashLink behind, along the road)
      int stroke = -1;
      for (size_t i = 0; i < live_.size() && stroke < 0; ++i) {
        const Stroke& s = strokes_[live_[i]];
        const double df = q.x() - s.last.x();
        if (df >= 0.0 && df <= kDashLink &&
            std::fabs(q.y() - s.last.y()) <= std::tan(kMaxSeedHeading) * df + kDashSlack)
          stroke = live_[i];
      }
      if (stroke < 0) {
        stroke = static_cast<int>(strokes_.size());
        strokes_.push_back({q, q, 0});
        live_.push_back(stroke);
      }
      strokes_[stroke].last = q;
      ++strokes_[stroke].rows;
      ridges_.push_back({px, q, stroke});
    }
  }
  int longest = -1;
  for (size_t k = 0; k < strokes_.size(); ++k) {
    const Stroke& s = strokes_[k];
    const double length = s.last.x() - s.first.x();
    if (s.rows >= params_.min_marker_points && length >= kMinStroke &&
        (longest < 0 || length > strokes_[longest].last.x() - strokes_[longest].first.x()))
      longest = static_cast<int>(k);
  }
  if (longest < 0) return false;
  stroke_pixels_.clear();
  for (const Ridge& r : ridges_)
    if (r.stroke == longest) stroke_pixels_.push_back(r.pixel);
  return true;
}

double BoundaryCandidateFinder::lateralWobble(const CandidateFrame& f,
                                              const std::vector<cv::Point2f>& pixels) {
  std::vector<Eigen::Vector2d>& q = wobble_road_;
  q.clear();
  for (const auto& px : pixels) {
    Eigen::Vector2d r;
    if (roadCoordinates(f, classifier_input_.frame, px.x, px.y, r)) q.push_back(r);
  }
  if (q.size() < 3) return std::numeric_limits<double>::infinity();
  LineSums sums;
  for (const auto& r : q) sums.add(r.x(), r.y());
  double a = 0.0, b = 0.0;
  if (!sums.fit(1e-12, a, b)) return std::numeric_limits<double>::infinity();
  double ss = 0.0;
  for (const auto& r : q) ss += (r.y() - a - b * r.x()) * (r.y() - a - b * r.x());
  return std::sqrt(ss / sums.n);
}

void BoundaryCandidateFinder::traceLoneDash(const CandidateFrame& f) {
  if (!params_.classify_boundaries || f.road == nullptr || !f.road->valid) return;
  const ClassifierInput& in = classifier_input_;  // set by classify()
  for (int side = 0; side < 2; ++side) {
    // a side without a painted candidate, and without a tracked boundary (the lane model
    // predicts that one; a lone dash is a frame's first sight of a line)
    if (hasPaintedBoundary(side) ||
        (params_.track_lanes && f.fitter != nullptr && f.fitter->tracker().valid(side)))
      continue;
    if (!longestRidgeStroke(f, side)) continue;
    // as straight as paint: the ridge rows' wobble about their line, and half a pixel's rounding
    // at the stroke's near end
    double f0 = 0.0, ppm = 0.0;
    if (!in.roadAt(stroke_pixels_.front().x, stroke_pixels_.front().y, f0, ppm) ||
        !(lateralWobble(f, stroke_pixels_) <= kDashWobble + 0.5 / ppm))
      continue;
    BoundaryCandidate& c = next(side);
    MarkerTrace& m = c.trace;
    startTrace(m);
    m.angle_valid = false;
    m.angle = f.template_angle[side];
    m.seed = stroke_pixels_.front();
    m.peak_score = static_cast<float>(params_.trace_threshold);
    for (const auto& px : stroke_pixels_) {
      m.pixels.push_back(px);
      m.points.push_back(pointAt(f, cv::Point2f(f.toProcessing(px))));
    }
    m.seed_point = m.points.front();
    // paint by its width
    classifier_.classify(in, m.pixels, side == 0, params_, c.evidence);
    matchLengths(m);
    if (!c.evidence.boundary || c.evidence.kind != BoundaryKind::kPaint || c.evidence.narrowLine())
      continue;
    // the dash, row by row, across no gap (a dash gap's sunlit flecks are no part of it)
    if (classifier_.followLine(in, m.pixels, m.points, params_, kStrokeGap, params_.max_depth,
                               BoundaryClassifier::kTraceReach, true) < params_.min_marker_points)
      continue;
    if (classifier_.cutAtObject(in, m.pixels, side == 0, params_)) matchLengths(m);
    double extent = 0.0;
    paintStretches(f, m.pixels, kStrokeGap, &extent);
    if (extent < kLoneDashMin || extent > kLoneDashMax || !runsAhead(f, m.pixels)) continue;
    // flat on the road with road on both sides: paint, no height step where depth measures it
    BoundaryEvidence& ev = c.evidence;
    classifier_.classify(in, m.pixels, side == 0, params_, ev);
    matchLengths(m);
    const auto flat = [&](float h) { return !std::isfinite(h) || std::fabs(h) <= params_.kerb_height; };
    if (!ev.boundary || ev.kind != BoundaryKind::kPaint || ev.raised || !flat(ev.inner_height) ||
        !flat(ev.line_height) || !flat(ev.outer_height))
      continue;
    if (classifier_.arrowHead(in, m.pixels, params_)) continue;  // a turn arrow's shaft
    m.scores.assign(m.pixels.size(), m.peak_score);
    m.num_valid_points = 0;
    for (const auto& p : m.points) m.num_valid_points += !std::isnan(p.z());
    ev.reason = "lone dash";
    ++counts_[side];
  }
}

}  // namespace rgbd_lane_detector
