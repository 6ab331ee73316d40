#include "rgbd_lane_detector/boundary_classifier.h"

#include <algorithm>
#include <cmath>

namespace rgbd_lane_detector {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
// Rows are measured where a pixel spans at most 1/kMinPixelsPerMetre m across the road, the
// band's width where it spans at most 1/kWidthPixelsPerMetre m.
constexpr double kMinPixelsPerMetre = 12.0;
constexpr double kWidthPixelsPerMetre = 25.0;
constexpr double kProfileHalfWidth = 0.6;    // m each side of the line
constexpr double kPeakSearch = 0.1;          // m: the band's peak is sought this close to the trace
constexpr double kSideNear = 0.22;           // m: the sides' backgrounds start this far from the peak
constexpr double kSideFar = 0.5;             // ... and end here
constexpr double kHeightNear = 0.3;          // m: heights of the sides are read here
constexpr double kHeightFar = 0.5;
constexpr float kObjectHeight = 0.3f;        // a line higher than this above the road is an object
constexpr float kRidgeShare = 0.5f;          // share of measured rows that must show a band
constexpr int kMinRows = 3;
constexpr int kMinHeights = 3;
constexpr float kMinContrast = 10.0f;        // grey levels: below this a band is sensor noise
constexpr double kBandReach = 0.3;           // m: bands this close to the trace belong to it
constexpr double kMinShift = 0.02;           // m: smaller offsets of the paint are not applied
constexpr float kShadowRatio = 1.4f;         // a shadow's sunlit side is at least this much brighter

float median(std::vector<float>& v) {
  if (v.empty()) return kNaN;
  auto mid = v.begin() + v.size() / 2;
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

void BoundaryClassifier::sample(const ClassifierInput& in, int u, int v, float& grey, float& r,
                                float& g) const {
  const cv::Mat& c = *in.colour;
  const uint8_t* px = c.ptr<uint8_t>(v) + static_cast<size_t>(u) * c.channels();
  float R, G, B;
  switch (in.format) {
    case PixelFormat::kMono8:
      R = G = B = px[0];
      break;
    case PixelFormat::kRgb8:
    case PixelFormat::kRgba8:
      R = px[0], G = px[1], B = px[2];
      break;
    default:  // bgr8, bgra8
      B = px[0], G = px[1], R = px[2];
      break;
  }
  grey = 0.299f * R + 0.587f * G + 0.114f * B;
  const float sum = R + G + B + 1e-3f;
  r = R / sum;
  g = G / sum;
}

float BoundaryClassifier::heightAt(const ClassifierInput& in, int u, int v) const {
  const cv::Mat& P = *in.points;
  const int x = static_cast<int>((u + 0.5) * in.scale_x);
  const int y = static_cast<int>((v + 0.5) * in.scale_y);
  if (x < 0 || y < 0 || x >= P.cols || y >= P.rows) return kNaN;
  const float* q = P.ptr<float>(y) + 3 * x;
  if (!std::isfinite(q[2])) return kNaN;
  const Eigen::Vector3d& n = in.plane->normal;
  return static_cast<float>(n.x() * q[0] + n.y() * q[1] + n.z() * q[2] + in.plane->distance);
}

void BoundaryClassifier::addBand(int a, int b, float base, bool open, int W) {
  const float* P = profile_.data() + W;
  int peak = a;
  for (int j = a; j <= b; ++j)
    if (P[j] > P[peak]) peak = j;
  Band band;
  band.peak = P[peak];
  band.open = open;
  const float half = base + 0.5f * (band.peak - base);
  int l = peak, r = peak;
  while (l - 1 >= a && P[l - 1] >= half) --l;
  while (r + 1 <= b && P[r + 1] >= half) ++r;
  band.lo = l - 1 >= -W && P[l - 1] < half ? l - (P[l] - half) / (P[l] - P[l - 1]) : l - 0.5;
  band.hi = r + 1 <= W && P[r + 1] < half ? r + (P[r] - half) / (P[r] - P[r + 1]) : r + 0.5;
  bands_.push_back(band);
}

void BoundaryClassifier::findBands(int W, float base, float low) {
  // Runs of the profile above `low`, split at dips deeper than half the contrast of the lower
  // of the peaks either side (a rail head next to a painted line), each band measured at half
  // its own peak.
  bands_.clear();
  const float* P = profile_.data() + W;  // P[k], k in [-W, W]
  int k = -W;
  while (k <= W) {
    if (P[k] < low) {
      ++k;
      continue;
    }
    int end = k;
    while (end + 1 <= W && P[end + 1] >= low) ++end;
    int seg = k;
    for (int j = k + 1; j < end; ++j) {
      if (!(P[j] <= P[j - 1] && P[j] < P[j + 1])) continue;  // local minima only
      float before = P[seg], after = P[j];
      for (int i = seg; i <= j; ++i) before = std::max(before, P[i]);
      for (int i = j; i <= end; ++i) after = std::max(after, P[i]);
      const float m = std::min(before, after);
      if (m - P[j] > 0.5f * (m - base)) {
        addBand(seg, j - 1, base, seg == -W, W);
        seg = j + 1;
      }
    }
    addBand(seg, end, base, seg == -W || end == W, W);
    k = end + 1;
  }
}

void BoundaryClassifier::classify(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                                  bool left, const Params& p, BoundaryEvidence& ev) {
  ev = BoundaryEvidence();
  for (auto* v : {&ridge_, &step_, &chroma_, &width_, &line_h_, &inner_h_, &outer_h_, &shift_})
    v->clear();
  if (in.plane == nullptr || !in.plane->valid || !in.frame.valid) {
    ev.reason = "no plane";
    return;
  }
  if (pixels.size() < 2) {
    ev.reason = "too short";
    return;
  }
  const cv::Mat& colour = *in.colour;
  const Intrinsics& K = in.K;
  const Eigen::Vector3d& n = in.plane->normal;
  const double d = in.plane->distance;

  // the line's heading in the road plane (its profile is read along image rows, i.e. across
  // the road: a band's width is its extent there times cos(heading))
  double cos_heading = 1.0;
  {
    Eigen::Vector2d a(0, 0), b(0, 0);
    bool have_a = false;
    for (const auto& c : pixels) {
      const Eigen::Vector3d ray((c.x - K.cx) / K.fx, (c.y - K.cy) / K.fy, 1.0);
      const double den = n.dot(ray);
      if (!(den < -1e-9)) continue;
      const Eigen::Vector2d q = in.frame.toPlane(ray * (-d / den));
      if (!have_a) {
        a = q;
        have_a = true;
      }
      b = q;
    }
    const Eigen::Vector2d t = b - a;
    if (t.norm() > 0.5) cos_heading = std::max(0.5, std::fabs(t.x()) / t.norm());
  }

  int paint_rows = 0, narrow_rows = 0, wide_rows = 0;
  const int outer_dir = left ? -1 : 1;  // image direction away from the vehicle
  for (const auto& c : pixels) {
    const int v = static_cast<int>(std::lround(c.y));
    if (v < 0 || v >= colour.rows) continue;
    const Eigen::Vector3d ray((c.x - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
    const double den = n.dot(ray);
    if (!(den < -1e-9)) continue;
    const double Z = -d / den;  // depth of the road at this pixel (ray z = 1)
    const double ppm = K.fx / Z;  // pixels per metre across the road at this row
    if (ppm < kMinPixelsPerMetre) continue;
    const int u0 = static_cast<int>(std::lround(c.x));
    const int W = std::min(160, std::max(5, static_cast<int>(std::lround(kProfileHalfWidth * ppm))));
    if (u0 - W < 0 || u0 + W >= colour.cols) continue;
    profile_.resize(2 * W + 1);
    for (int k = -W; k <= W; ++k) {
      float r, g;
      sample(in, u0 + k, v, profile_[k + W], r, g);
    }
    // backgrounds of both sides, outward from the trace
    const int s0 = std::max(2, static_cast<int>(std::ceil(kSideNear * ppm)));
    const int s1 = std::max(s0 + 1, static_cast<int>(std::floor(kSideFar * ppm)));
    float bg[2];  // 0: inner, 1: outer
    float chroma[2][2];
    bool ok = true;
    for (int s = 0; s < 2; ++s) {
      const int dir = s == 1 ? outer_dir : -outer_dir;
      side_.clear();
      double sr = 0, sg = 0;
      for (int k = s0; k <= s1 && k <= W; ++k) {
        float grey, r, g;
        sample(in, u0 + dir * k, v, grey, r, g);
        side_.push_back(grey);
        sr += r;
        sg += g;
      }
      if (side_.empty()) {
        ok = false;
        break;
      }
      chroma[s][0] = static_cast<float>(sr / side_.size());
      chroma[s][1] = static_cast<float>(sg / side_.size());
      bg[s] = median(side_);
    }
    if (!ok) continue;
    ++ev.rows;
    const float top = std::max(bg[0], bg[1]);
    const float contrast = std::max(kMinContrast, static_cast<float>(p.paint_contrast) * std::max(top, 1.0f));
    // the brightest pixel near the trace: its contrast to the brighter side
    const int search = std::max(2, static_cast<int>(std::lround(kPeakSearch * ppm)));
    float peak = profile_[W];
    for (int k = -search; k <= search; ++k) peak = std::max(peak, profile_[k + W]);
    ridge_.push_back(peak - top);
    step_.push_back(bg[1] - bg[0]);
    // colour change across the line, unless it is the blue cast of a shadow: the darker side
    // much darker and bluer (sky-lit) than the sunlit one
    {
      const int dark = bg[0] < bg[1] ? 0 : 1;
      const float dr = chroma[1][0] - chroma[0][0], dg = chroma[1][1] - chroma[0][1];
      const float blue_dark = 1.f - chroma[dark][0] - chroma[dark][1];
      const float blue_light = 1.f - chroma[1 - dark][0] - chroma[1 - dark][1];
      const float dist = std::hypot(dr, dg);
      const bool shadow = bg[1 - dark] >= kShadowRatio * std::max(bg[dark], 1.0f) &&
                          blue_dark - blue_light > 0.5f * dist;
      chroma_.push_back(shadow ? 0.0f : dist);
    }
    if (peak - top >= contrast) ++ev.ridge_rows;
    // bright bands near the trace, by width where the pixels resolve them: the painted one
    // nearest the trace, else a narrow one (a rail head), else a wide one
    if (ppm >= kWidthPixelsPerMetre) {
      findBands(W, top, top + contrast);
      const double reach = kBandReach * ppm;
      const Band* paint = nullptr;
      const Band* narrow = nullptr;
      const Band* wide = nullptr;
      for (const Band& b : bands_) {
        const double centre = 0.5 * (b.lo + b.hi);
        if (b.open || std::fabs(centre) > reach) continue;
        const double w = (b.hi - b.lo) / ppm * cos_heading;
        const Band** slot = w < p.paint_width_min ? &narrow : w > p.paint_width_max ? &wide : &paint;
        if (*slot == nullptr || std::fabs(centre) < std::fabs(0.5 * ((*slot)->lo + (*slot)->hi)))
          *slot = &b;
      }
      const Band* chosen = paint ? paint : narrow ? narrow : wide;
      if (chosen) {
        width_.push_back(static_cast<float>((chosen->hi - chosen->lo) / ppm * cos_heading));
        if (paint) {
          ++paint_rows;
          shift_.push_back(static_cast<float>(0.5 * (paint->lo + paint->hi) / ppm));
        } else if (narrow) {
          ++narrow_rows;
        } else {
          ++wide_rows;
        }
      }
    }
    // heights of the line and of the surfaces beside it (where depth exists)
    const float hl = heightAt(in, u0, v);
    if (std::isfinite(hl)) line_h_.push_back(hl);
    for (double off : {kHeightNear, kHeightFar}) {
      const int k = static_cast<int>(std::lround(off * ppm));
      const float hi = heightAt(in, u0 - outer_dir * k, v);
      const float ho = heightAt(in, u0 + outer_dir * k, v);
      if (std::isfinite(hi)) inner_h_.push_back(hi);
      if (std::isfinite(ho)) outer_h_.push_back(ho);
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
  // rail's beam, a cyclist)
  if ((std::isfinite(ev.line_height) && ev.line_height > kObjectHeight) ||
      (std::isfinite(ev.inner_height) && ev.inner_height > kObjectHeight)) {
    ev.reason = "above the road";
    return;
  }
  // 2. a height step: the surface beyond the line is raised (kerb), or the line itself is
  const float inner = std::isfinite(ev.inner_height) ? ev.inner_height : 0.0f;
  const float step_h =
      std::isfinite(ev.outer_height) ? ev.outer_height - inner : kNaN;
  const bool raised_line = std::isfinite(ev.line_height) && ev.line_height >= p.kerb_height;
  if ((std::isfinite(step_h) && step_h >= p.kerb_height && step_h <= kObjectHeight * 2) ||
      raised_line) {
    ev.boundary = true;
    ev.kind = BoundaryKind::kRoadEdge;
    ev.reason = "height step";
    const float h = std::isfinite(step_h) ? step_h : ev.line_height;
    ev.margin = std::min(1.0f, static_cast<float>(h / (2.0 * p.kerb_height)));
    return;
  }
  // 3. a bright band on a flat road: paint, unless its resolved width says a rail head (too
  // narrow) or a zebra stripe, an arrow (too wide); a painted band beside the traced line (a
  // rail head next to the paint outshone it) moves the line onto the paint
  const bool ridge = ev.ridge_rows >= kRidgeShare * ev.rows;
  const int resolved = paint_rows + narrow_rows + wide_rows;
  if (ridge || resolved > 0) {
    if (resolved >= kMinRows && paint_rows < kRidgeShare * resolved) {
      if (narrow_rows >= wide_rows) {
        ev.boundary = true;
        ev.kind = BoundaryKind::kRoadEdge;
        ev.reason = "narrow band (rail)";
        ev.margin = static_cast<float>(narrow_rows) / resolved;
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
    ev.reason = resolved >= kMinRows ? "bright band" : "bright band (width unresolved)";
    ev.margin = resolved >= kMinRows ? static_cast<float>(paint_rows) / resolved
                                     : 0.7f * std::min(1.0f, static_cast<float>(ev.ridge_rows) / ev.rows);
    if (resolved >= kMinRows) {
      ev.shift = median(shift_);
      if (std::fabs(ev.shift) > kMinShift) {
        // move every point onto the painted band (the shift is metres across the road)
        for (auto& c : pixels) {
          const Eigen::Vector3d ray((c.x - K.cx) / K.fx, (c.y - K.cy) / K.fy, 1.0);
          const double den = n.dot(ray);
          if (!(den < -1e-9)) continue;
          c.x += static_cast<float>(ev.shift * K.fx * (-den) / d);
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

}  // namespace rgbd_lane_detector
