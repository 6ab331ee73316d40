#include "rgbd_lane_detector/boundary_classifier.h"

#include <algorithm>
#include <cmath>

#include "rgbd_lane_detector/geometry.h"
#include "row_statistics.h"

namespace rgbd_lane_detector {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr double kHeightNear = 0.3;          // m: heights of the sides are read here
constexpr double kHeightFar = 0.5;
constexpr float kObjectHeight = 0.3f;        // a line higher than this above the road is an object
constexpr double kStepShare = 0.7;           // share of a line's rows that must show its step
constexpr float kRidgeShare = 0.5f;          // share of measured rows that must show a band
constexpr int kMinRows = BandProfile::kMinRows;
constexpr size_t kMaxMeasuredRows = BandProfile::kMaxMeasuredRows;
constexpr size_t kMaxPaintRows = 24;         // rows a paint measurement measures at most
constexpr int kMinHeights = 3;
constexpr double kMinShift = 0.02;           // m: smaller offsets of the paint are not applied
constexpr float kShadowRatio = 1.4f;         // a shadow's sunlit side is at least this much brighter
constexpr double kCoverageReach = 0.15;      // m: paint this close to the line covers it
// a channel this bright is clipped: sunlit yellow paint clips its red and green first and then
// reads whiter than it is (a pixel clipped in every channel is white, or as white as can be told)
constexpr float kSaturated = 250.0f;
// grey levels the road beside a worn line needs in every channel for the colour of its thin core
// against it: on a darker road (night) the channels' ratios over so few pixels are the noise
constexpr double kMinWornColourLevel = 20.0;
constexpr double kMinCoverageLength = 3.0;   // m of measured road for a coverage
// m of unbroken paint width: a dash, which no rail head widens to (the shortest lane-line dash
// is 1 m, urban; a worn dash keeps its paint width over only part of its length, its rows
// alternating paint width and a narrower worn core) ...
constexpr double kDashLength = 1.0;
constexpr int kDashRows = 8;                  // ... measured on this many rows at least
constexpr double kArrowReach = 2.5;           // m beyond a stroke's far end where an arrow's head is sought
constexpr double kArrowBack = 3.0;            // ... and from this far before it
constexpr double kArrowHalfWidth = 0.8;       // m either side of the stroke's extension looked at
constexpr double kArrowTaper = 0.5;           // an arrow's head narrows below this share of its base
constexpr double kArrowWidthShare = 1.0;      // a head is wider than paint_width_max (no lane line is)
// m: beyond the narrowing, a head's tip keeps tapering: it halves its width again (or ends)
// within this much road (heads are up to 2.5 m long, their narrow half up to 1.25 m); paint of
// a line's width running on this far without tapering is a line beyond a wide bright patch (a
// dash through a patch of sunlight), no arrow's tip
constexpr double kArrowTip = 1.5;
constexpr double kWidthPixelsPerMetre = BandProfile::kWidthPixelsPerMetre;
constexpr int kMaxProfileHalf = BandProfile::kMaxProfileHalf;
constexpr float kMinContrast = BandProfile::kMinContrast;
constexpr double kSideNear = BandProfile::kSideNear;
constexpr double kSideFar = BandProfile::kSideFar;

// The row's two sides differ as sunlit and shaded road do (a shadow's edge across the line, a
// vehicle's dark flank or its shade beside it): the brighter side at least kShadowRatio times
// the darker one.
bool sidesAShadowApart(const RowMeasure& m) {
  const int dark = m.bg[0] < m.bg[1] ? 0 : 1;
  return m.bg[1 - dark] >= kShadowRatio * std::max(m.bg[dark], 1.0f);
}

// Column of an image polyline (near to far, rows decreasing) at row v, linear between its points.
double columnAt(const std::vector<cv::Point2f>& line, int v) {
  for (size_t i = 1; i < line.size(); ++i)
    if ((v <= line[i - 1].y && v >= line[i].y) || (v >= line[i - 1].y && v <= line[i].y)) {
      const double dy = line[i].y - line[i - 1].y;
      return std::fabs(dy) > 1e-6 ? line[i - 1].x + (v - line[i - 1].y) * (line[i].x - line[i - 1].x) / dy
                                  : line[i].x;
    }
  return line.back().x;
}

}  // namespace

BoundaryClassifier::BoundaryClassifier() {
  // the per-line buffers at their largest, so that no frame grows them
  object_.reserve(kReservedPixels);
  row_grey_.reserve(2 * kMaxProfileHalf + 1);
  for (auto* v : {&ridge_, &step_, &chroma_, &width_, &line_h_, &inner_h_, &outer_h_, &shift_,
                  &far_step_})
    v->reserve(kMaxMeasuredRows);
  pair_step_.reserve(2 * kMaxMeasuredRows);
  pair_raise_.reserve(2 * kMaxMeasuredRows);
  yellow_.reserve(kMaxPaintRows);
  yellow_worn_.reserve(kMaxPaintRows);
}

int BoundaryClassifier::followLine(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                                   std::vector<Eigen::Vector3f>& points, const Params& p,
                                   double max_gap, double max_range, double reach,
                                   bool painted, bool seed_line) {
  return follower_.followLine(in, pixels, points, p, max_gap, max_range, reach, painted,
                              seed_line);
}

int BoundaryClassifier::followEdge(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                                   std::vector<Eigen::Vector3f>& points, bool left,
                                   const Params& p, double max_gap, double max_range,
                                   double reach) {
  return follower_.followEdge(in, pixels, points, left, p, max_gap, max_range, reach);
}

bool BoundaryClassifier::centreDoubleLine(const ClassifierInput& in,
                                          std::vector<cv::Point2f>& pixels,
                                          std::vector<Eigen::Vector3f>& points, const Params& p) {
  return follower_.centreDoubleLine(in, pixels, points, p);
}

bool BoundaryClassifier::arrowHead(const ClassifierInput& in, const std::vector<cv::Point2f>& pixels,
                                   const Params& p) {
  // beyond the far end of a painted stroke (up to kArrowReach of road), a bright band much
  // wider than paint around its extension on a few rows: the head of a lane arrow
  if (pixels.size() < 3 || in.plane == nullptr || !in.plane->valid) return false;
  const cv::Point2f& a = pixels[pixels.size() - 3];
  const cv::Point2f& b = pixels.back();
  if (!(b.y < a.y - 0.5f)) return false;
  const double du = (b.x - a.x) / (b.y - a.y);  // column change per row, toward the top
  double f0 = 0.0, ppm0 = 0.0;
  if (!in.roadAt(b.x, b.y, f0, ppm0)) return false;
  // from kArrowBack before the far end (the follow may have run up the head's narrow tip)
  int v_start = static_cast<int>(std::lround(b.y)) - 1;
  for (size_t i = pixels.size(); i-- > 0;) {
    double f = 0.0, ppm = 0.0;
    if (!in.roadAt(pixels[i].x, pixels[i].y, f, ppm) || f0 - f > kArrowBack) break;
    v_start = static_cast<int>(std::lround(pixels[i].y));
  }
  int wide = 0, widest = 0;
  // after the narrowing (a tip's start): where it started and its widest row since
  bool narrowed = false;
  double tip_start = 0.0;
  int tip_widest = 0;
  for (int v = v_start; v >= 0; --v) {
    const double u = v >= b.y ? columnAt(pixels, v) : b.x + du * (v - b.y);
    double f = 0.0, ppm = 0.0;
    if (!in.roadAt(u, v, f, ppm) || (!narrowed && f - f0 > kArrowReach)) break;
    if (ppm < kWidthPixelsPerMetre) break;
    const ImageRow row(in, v);
    if (!row.valid()) break;
    const int W = std::min(kMaxProfileHalf, static_cast<int>(std::lround(kArrowHalfWidth * ppm)));
    const int u0 = roundColumn(u, in.colour->cols);
    if (u0 - W < 0 || u0 + W >= in.colour->cols) break;
    row_grey_.clear();
    for (int x = u0 - W; x <= u0 + W; ++x) row_grey_.push_back(row.grey(x));
    const float bg = greyMedian(row_grey_);
    const float level = bg + std::max(kMinContrast, static_cast<float>(p.paint_contrast) * std::max(bg, 1.0f));
    // the bright run through the nearest bright pixel to the extension
    int c = -1;
    for (int k = 0; k <= W / 4 && c < 0; ++k)
      for (int x : {u0 - k, u0 + k})
        if (c < 0 && row.grey(x) >= level) c = x;
    int width = 0;
    bool bounded = true;
    if (c >= 0) {
      int l = c, r = c;
      while (l - 1 >= u0 - W && row.grey(l - 1) >= level) --l;
      while (r + 1 <= u0 + W && row.grey(r + 1) >= level) ++r;
      width = r - l + 1;
      bounded = l > u0 - W && r < u0 + W;  // a stop line runs across the whole road
      // a bright run that the depth measures above the road on most of its measured pixels is
      // a vehicle's body (a white car's bumper, narrowing to its corner like a head to its tip):
      // the road beyond the stroke is hidden from there on, and no head is seen
      int measured = 0, raised = 0;
      for (int x = l; x <= r; ++x) {
        const float h = in.heightAt(x, v);
        if (!std::isfinite(h)) continue;
        ++measured;
        raised += h > kObjectHeight;
      }
      if (measured >= kMinHeights && 2 * raised > measured) break;
    }
    if (narrowed) {
      // the tip tapers on (to half its width, or below paint width) before kArrowTip; a line
      // keeps its paint width past it
      tip_widest = std::max(tip_widest, width);
      if (width < p.paint_width_min * ppm || width > p.paint_width_max * ppm ||
          2 * width < tip_widest)
        return true;
      if (f - tip_start >= kArrowTip) return false;
      continue;
    }
    if (bounded && width > kArrowWidthShare * p.paint_width_max * ppm) {
      ++wide;
      widest = std::max(widest, width);
    } else if (wide >= kMinRows && width > 0 && width < kArrowTaper * widest) {
      // the head narrows to its tip (a zebra stripe keeps its width, then ends)
      narrowed = true;
      tip_start = f;
      tip_widest = width;
    }
  }
  return narrowed;
}

bool BoundaryClassifier::cutAtObject(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                                     bool left, const Params& p) {
  // the first pixel (near to far) from which the line or the road beside it on the vehicle's
  // side reads depth well above the road on two of three measured pixels; the line before it
  // must lie on the road (within the kerb height) on most of its measured pixels (on all of
  // them where fewer than kMinHeights are measured)
  if (in.plane == nullptr || !in.plane->valid) return false;
  const Intrinsics& K = in.K;
  object_.clear();  // per pixel: 1 object, 0 road, 2 off the road but no object, -1 no depth
  for (const auto& c : pixels) {
    const int u = roundColumn(c.x, in.colour->cols);
    const int v = static_cast<int>(std::lround(c.y));
    // kHeightNear across the road in pixels (0: the pixel is not on the road)
    const double near_px = roadPixelsAcross(K, *in.plane, K.ray(u, v), kHeightNear);
    if (!(near_px > 0.0)) {
      object_.push_back(-1);
      continue;
    }
    const int inner = static_cast<int>(std::lround(near_px));
    const float h = in.heightAt(u, v);
    const float hi = in.heightAt(left ? u + inner : u - inner, v);
    const bool object = (std::isfinite(h) && h > kObjectHeight) || (std::isfinite(hi) && hi > kObjectHeight);
    object_.push_back(object ? 1 : std::isfinite(h) ? (std::fabs(h) <= p.kerb_height ? 0 : 2) : -1);
  }
  int on_road = 0, measured = 0;
  for (size_t i = 0; i < pixels.size(); ++i) {
    if (object_[i] == 1) {
      int objects = 0, seen = 0;
      for (size_t j = i; j < object_.size() && seen < 3; ++j) {
        if (object_[j] < 0) continue;
        ++seen;
        objects += object_[j] == 1;
      }
      if (objects < 2) continue;  // a lone reading (a pole's foot, noise)
      // (sparse depth may measure none of the line before it: then none may contradict it)
      if ((measured < kMinHeights ? on_road < measured : on_road < kStepShare * measured) ||
          static_cast<int>(i) < kMinRows)
        return false;
      pixels.resize(i);
      return true;
    }
    if (object_[i] < 0) continue;
    ++measured;
    on_road += object_[i] == 0;
  }
  return false;
}

void BoundaryClassifier::classify(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                                  bool left, const Params& p, BoundaryEvidence& ev, bool cut) {
  ev = BoundaryEvidence();
  for (auto* v : {&ridge_, &step_, &chroma_, &width_, &line_h_, &inner_h_, &outer_h_, &shift_,
                  &pair_step_, &pair_raise_, &far_step_})
    v->clear();
  if (in.plane == nullptr || !in.plane->valid || !in.frame.valid()) {
    ev.reason = "no plane";
    return;
  }
  if (pixels.size() < 2) {
    ev.reason = "too short";
    return;
  }
  // a line on the road that runs up to a vehicle ahead (its far rows, or the lane beside them,
  // read the vehicle's depth) is the line up to the vehicle
  if (cut) cutAtObject(in, pixels, left, p);
  const Intrinsics& K = in.K;
  const double cos_heading = in.cosHeading(pixels);

  int paint_rows = 0, narrow_rows = 0, wide_rows = 0;
  // the longest stretch of road painted without a break (measured rows with a band of paint
  // width, at most one row between them without)
  double run_start = 0.0, run_end = 0.0, longest_run = 0.0;
  int run_misses = 2, run_rows = 0, longest_rows = 0;
  RowMeasure m;
  // at most kMaxMeasuredRows rows, spread evenly along the line (a followed line has a point on
  // every image row; its medians need no more)
  const size_t stride = (pixels.size() + kMaxMeasuredRows - 1) / kMaxMeasuredRows;
  for (size_t i = 0; i < pixels.size(); i += stride) {
    const cv::Point2f& c = pixels[i];
    if (!profile_.measureRow(in, c, left, p, cos_heading, m)) continue;
    ++ev.rows;
    ridge_.push_back(m.peak - m.top);
    step_.push_back(m.bg[1] - m.bg[0]);
    // colour change across the line, unless it is the blue cast of a shadow: the darker side
    // much darker and bluer (sky-lit) than the sunlit one
    {
      const int dark = m.bg[0] < m.bg[1] ? 0 : 1;
      const float dr = m.chroma[1][0] - m.chroma[0][0], dg = m.chroma[1][1] - m.chroma[0][1];
      const float blue_dark = 1.f - m.chroma[dark][0] - m.chroma[dark][1];
      const float blue_light = 1.f - m.chroma[1 - dark][0] - m.chroma[1 - dark][1];
      const float dist = std::hypot(dr, dg);
      const bool shadow = sidesAShadowApart(m) && blue_dark - blue_light > 0.5f * dist;
      chroma_.push_back(shadow ? 0.0f : dist);
    }
    if (m.peak - m.top >= m.contrast) ++ev.ridge_rows;
    const Band* chosen = m.paint ? m.paint : m.narrow ? m.narrow : m.wide;
    if (!m.paint) ++run_misses;
    if (chosen) {
      width_.push_back(static_cast<float>((chosen->hi - chosen->lo) / m.ppm * cos_heading));
      if (m.paint) {
        ++paint_rows;
        double fwd, ppm;
        if (in.roadAt(c.x, c.y, fwd, ppm)) {
          if (run_misses > 1) {
            run_start = fwd;
            run_rows = 0;
          }
          run_end = fwd;
          run_misses = 0;
          ++run_rows;
          if (std::fabs(run_end - run_start) > longest_run) {
            longest_run = std::fabs(run_end - run_start);
            longest_rows = run_rows;
          }
        }
        shift_.push_back(static_cast<float>(0.5 * (m.paint->lo + m.paint->hi) / m.ppm));
      } else if (m.narrow) {
        ++narrow_rows;
      } else {
        ++wide_rows;
      }
    }
    // heights of the line and of the surfaces beside it (where depth exists)
    const float hl = in.heightAt(m.u0, m.v);
    if (std::isfinite(hl)) line_h_.push_back(hl);
    for (double off : {kHeightNear, kHeightFar}) {
      const int k = static_cast<int>(std::lround(off * m.ppm));
      const float hi = in.heightAt(m.u0 - m.outer_dir * k, m.v);
      const float ho = in.heightAt(m.u0 + m.outer_dir * k, m.v);
      if (std::isfinite(hi)) inner_h_.push_back(hi);
      if (std::isfinite(ho)) outer_h_.push_back(ho);
      // the same row's steps, against the road on the vehicle's side: a tilted or offset plane
      // cancels out, and noisy depth shows no step in most rows
      if (std::isfinite(hi) && std::isfinite(ho)) {
        pair_step_.push_back(ho - hi);
        if (off == kHeightFar) far_step_.push_back(ho - hi);
      }
      if (std::isfinite(hi) && std::isfinite(hl)) pair_raise_.push_back(hl - hi);
    }
  }
  ev.paint_rows = paint_rows;
  ev.narrow_rows = narrow_rows;
  ev.wide_rows = wide_rows;

  ev.ridge_contrast = median(ridge_);
  ev.step_contrast = median(step_);
  ev.chroma_step = median(chroma_);
  ev.width = width_.size() >= 2 ? median(width_) : kNaN;  // of the chosen bands
  if (static_cast<int>(line_h_.size()) >= kMinHeights) ev.line_height = median(line_h_);
  if (static_cast<int>(inner_h_.size()) >= kMinHeights) ev.inner_height = median(inner_h_);
  if (static_cast<int>(outer_h_.size()) >= kMinHeights) ev.outer_height = median(outer_h_);
  if (ev.rows < kMinRows) {
    ev.reason = "too far to measure";
    // no profile: a line the depth places on the road is taken as paint (the paper's view)
    if (std::isfinite(ev.line_height) && std::fabs(ev.line_height) <= p.kerb_height) {
      ev.boundary = true;
      ev.kind = BoundaryKind::kPaint;
      ev.margin = 0.2f;
    }
    return;
  }

  // 1. well above the road, or beyond something that is: an object (a truck's stripe, a guard
  // rail's beam, a cyclist; a line on the road is cut where it runs into a vehicle, before)
  if ((std::isfinite(ev.line_height) && ev.line_height > kObjectHeight) ||
      (std::isfinite(ev.inner_height) && ev.inner_height > kObjectHeight)) {
    ev.reason = "above the road";
    return;
  }
  // 2. a height step: the surface beyond the line is raised (kerb), or the line itself is;
  // row by row against the road on the vehicle's side of it, in most rows where both are
  // measured (a plane a few centimetres off, or noisy far depth, raises nothing); without such
  // pairs, the sides' medians against the plane; the surface beyond raised against the road that
  // the depth measures on the vehicle's side (beside the line, else the line itself, on the
  // road): where no depth measures that side (a LiDAR's blind zone, sparse rows that only hit a
  // vehicle in the next lane), nothing shows that the step rises from the road
  const float kerb = static_cast<float>(p.kerb_height);
  const float inner = std::isfinite(ev.inner_height) ? ev.inner_height : 0.0f;
  const float near_side = std::isfinite(ev.inner_height) ? ev.inner_height
                          : std::isfinite(ev.line_height) && std::fabs(ev.line_height) <= kerb
                              ? ev.line_height
                              : kNaN;
  float step_h = kNaN, raise_h = kNaN;
  if (!stepInMostRows(pair_step_, kerb, kMinHeights, kStepShare, step_h) && std::isfinite(ev.outer_height))
    step_h = ev.outer_height - near_side;
  if (!stepInMostRows(pair_raise_, kerb, kMinHeights, kStepShare, raise_h) && std::isfinite(ev.line_height))
    raise_h = ev.line_height - inner;
  ev.step_height = step_h;
  // (no kerb is higher than an object; a vehicle beside the line raises its outer side more,
  // and more so farther out: its body above its wheels)
  const bool vehicle_beside =
      static_cast<int>(far_step_.size()) >= kMinHeights && median(far_step_) > kObjectHeight;
  if (!vehicle_beside &&
      ((std::isfinite(step_h) && step_h >= kerb && step_h <= kObjectHeight) ||
       (std::isfinite(raise_h) && raise_h >= kerb))) {
    ev.boundary = true;
    ev.kind = BoundaryKind::kRoadEdge;
    ev.reason = "height step";
    ev.raised = true;
    const float h = std::isfinite(step_h) && step_h >= kerb ? step_h : raise_h;
    ev.margin = std::min(1.0f, h / (2.0f * kerb));
    return;
  }
  // 3. a bright band on a flat road: paint, unless its resolved width says a rail head (too
  // narrow) or a zebra stripe, an arrow (too wide); a painted band beside the traced line (a
  // rail head next to the paint outshone it) moves the line onto the paint
  const bool ridge = ev.ridge_rows >= kRidgeShare * ev.rows;
  const int resolved = paint_rows + narrow_rows + wide_rows;
  if (ridge || resolved > 0) {
    // (a narrow line that runs into a dash is paint: a worn dash's rim, a seam's glint on it)
    const bool dash = longest_run >= kDashLength && longest_rows >= kDashRows;
    const bool little_paint = paint_rows < kRidgeShare * resolved;
    if (resolved >= kMinRows && little_paint && !(narrow_rows >= wide_rows && dash)) {
      if (narrow_rows >= wide_rows) {
        // a rail head lies in the road: the depth puts the line on it (a narrow bright line
        // that no depth measures may be a vehicle's trim or a glint on its body; kind is
        // still road edge for the worn-paint check of narrow dashes)
        ev.kind = BoundaryKind::kRoadEdge;
        ev.margin = static_cast<float>(narrow_rows) / resolved;
        ev.boundary = std::isfinite(ev.line_height) && std::fabs(ev.line_height) <= kerb;
        ev.reason = ev.boundary ? "narrow band (rail)" : "narrow band, unmeasured";
      } else {
        ev.reason = "wider than paint";
      }
      return;
    }
    if (!ridge && resolved < kMinRows) {
      ev.reason = "no band, no step";
      return;
    }
    ev.boundary = true;
    ev.kind = BoundaryKind::kPaint;
    ev.reason = resolved < kMinRows ? "bright band (width unresolved)"
                : little_paint      ? "narrow line with a dash"
                                    : "bright band";
    ev.margin = resolved >= kMinRows ? static_cast<float>(paint_rows) / resolved
                                     : 0.7f * std::min(1.0f, static_cast<float>(ev.ridge_rows) / ev.rows);
    if (resolved >= kMinRows) {
      ev.shift = median(shift_);
      if (std::fabs(ev.shift) > kMinShift) {
        // move every point onto the painted band (the shift is metres across the road)
        for (auto& c : pixels) {
          const double shift_px = roadPixelsAcross(K, *in.plane, K.ray(c.x, c.y), ev.shift);
          if (shift_px != 0.0) c.x += static_cast<float>(shift_px);  // 0: not on the road
        }
      }
    }
    return;
  }
  // 4. a change of surface: the colour changes across the line, not only the brightness (which
  // a shadow's edge also changes)
  if (std::isfinite(ev.chroma_step) && ev.chroma_step >= p.edge_chroma) {
    ev.boundary = true;
    ev.kind = BoundaryKind::kRoadEdge;
    ev.reason = "surface change";
    ev.margin = std::min(1.0f, static_cast<float>(ev.chroma_step / (2.0 * p.edge_chroma)));
    return;
  }
  ev.reason = "no band, no step";
}

void BoundaryClassifier::measurePaint(const ClassifierInput& in,
                                      const std::vector<cv::Point2f>& pixels, bool left,
                                      const Params& p, float& coverage, float& yellowness) {
  coverage = yellowness = -1.0f;
  if (in.plane == nullptr || !in.plane->valid || !in.frame.valid() || pixels.size() < 2) return;
  const double cos_heading = in.cosHeading(pixels);
  // each point stands for the stretch of road half-way to its neighbours
  auto forward = [&](const cv::Point2f& c) {
    double f, ppm;
    return in.roadAt(c.x, c.y, f, ppm) ? f : NAN;
  };
  double covered = 0.0, total = 0.0;
  yellow_.clear();
  yellow_worn_.clear();
  RowMeasure m;
  // at most kMaxPaintRows points, spread along the boundary, each standing for the stretch
  // half-way to its measured neighbours
  const size_t n = pixels.size();
  const size_t stride = (n + kMaxPaintRows - 1) / kMaxPaintRows;
  for (size_t k = 0; k < n; k += stride) {
    const double fa = forward(pixels[k >= stride ? k - stride : k]);
    const double fb = forward(pixels[k + stride < n ? k + stride : k]);
    const double weight = std::isfinite(fa) && std::isfinite(fb) ? 0.5 * std::fabs(fb - fa) : 0.0;
    if (!(weight > 0.0) || !profile_.measureRow(in, pixels[k], left, p, cos_heading, m)) continue;
    // paint here: a band of paint width on the line, or, where the pixels cannot resolve its
    // width, a bright enough peak
    const Band* band = m.paint;
    if (band && std::fabs(0.5 * (band->lo + band->hi)) > kCoverageReach * m.ppm) band = nullptr;
    const bool paint = band || (m.ppm < kWidthPixelsPerMetre && m.peak - m.top >= m.contrast);
    // no paint on a row whose sides are a shadow's ratio apart (a shadow's edge across the line,
    // a vehicle's dark flank or its shade beside it) is no gap either: paint in the shade need
    // not stand above the sunlit side, which sets the contrast (a solid line under dappled shade
    // read as dashes); such a row is left out of the measured length
    if (paint || !sidesAShadowApart(m)) total += weight;
    if (paint) covered += weight;
    // the paint's colour: on its bands of paint width, else where it is worn narrower (a worn
    // line's core, counted only where fewer than 3 rows have paint width)
    const bool worn = band == nullptr;
    if (worn) band = m.narrow;
    if (!band || std::fabs(0.5 * (band->lo + band->hi)) > kCoverageReach * m.ppm) continue;
    // colour of the paint against the road beside it (the illumination cancels): yellow paint
    // reflects little blue; a pixel with its red or green clipped and its blue not does not count
    const ImageRow row(in, m.v);
    const auto yellowClipped = [](float R, float G, float B) {
      return std::max(R, G) >= kSaturated && B < kSaturated;
    };
    double pr = 0, pg = 0, pb = 0, ar = 0, ag = 0, ab = 0;
    int np = 0, na = 0;
    for (int k2 = static_cast<int>(std::ceil(band->lo)); k2 <= static_cast<int>(std::floor(band->hi)); ++k2) {
      float R, G, B;
      row.rgb(m.u0 + k2, R, G, B);
      if (yellowClipped(R, G, B)) continue;
      pr += R, pg += G, pb += B, ++np;
    }
    const int s0 = std::max(2, static_cast<int>(std::ceil(kSideNear * m.ppm)));
    const int s1 = std::max(s0 + 1, static_cast<int>(std::floor(kSideFar * m.ppm)));
    for (int dir : {-1, 1})
      for (int k2 = s0; k2 <= s1 && k2 <= m.W; ++k2) {
        float R, G, B;
        row.rgb(m.u0 + dir * k2, R, G, B);
        if (yellowClipped(R, G, B)) continue;
        ar += R, ag += G, ab += B, ++na;
      }
    if (np == 0 || na == 0 || ab <= 0.0 || ar <= 0.0 || ag <= 0.0) continue;
    if (worn && std::min({ar, ag, ab}) < kMinWornColourLevel * na) continue;
    const double r = (pr / np) / (ar / na), g = (pg / np) / (ag / na), b = (pb / np) / (ab / na);
    (worn ? yellow_worn_ : yellow_).push_back(static_cast<float>(1.0 - b / (0.5 * (r + g))));
  }
  if (total >= kMinCoverageLength) coverage = static_cast<float>(covered / total);
  if (yellow_.size() < 3) yellow_.insert(yellow_.end(), yellow_worn_.begin(), yellow_worn_.end());
  if (yellow_.size() >= 3) yellowness = std::max(0.0f, median(yellow_));
}

}  // namespace rgbd_lane_detector

