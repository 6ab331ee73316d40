#include "rgbd_lane_detector/boundary_classifier.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace rgbd_lane_detector {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
// Rows are measured where a pixel spans at most 1/kMinPixelsPerMetre m across the road, the
// band's width where it spans at most 1/kWidthPixelsPerMetre m.
constexpr double kMinPixelsPerMetre = 12.0;
constexpr double kWidthPixelsPerMetre = 25.0;
constexpr double kProfileHalfWidth = 0.6;    // m each side of the line
constexpr int kMaxProfileHalf = 160;         // px each side of the line at most (near rows)
constexpr double kPeakSearch = 0.1;          // m: the band's peak is sought this close to the trace
constexpr double kSideNear = 0.22;           // m: the sides' backgrounds start this far from the peak
constexpr double kSideFar = 0.5;             // ... and end here
constexpr double kHeightNear = 0.3;          // m: heights of the sides are read here
constexpr double kHeightFar = 0.5;
constexpr float kObjectHeight = 0.3f;        // a line higher than this above the road is an object
constexpr int kHeightSearch = 3;             // rows up and down a height is sought (sparse depth)
constexpr double kStepShare = 0.7;           // share of a line's rows that must show its step
constexpr double kDoublePitch = 0.27;        // m between the two lines of a double line, expected
constexpr double kDoubleReach = 0.1;         // m: the second line is sought this far around it
constexpr double kDoubleMin = 0.17;          // m: a second line this near ...
constexpr double kDoubleMax = 0.4;           // ... to this far makes a double line
constexpr double kDoubleShare = 0.6;         // share of the measured rows that must show it
constexpr float kRidgeShare = 0.5f;          // share of measured rows that must show a band
constexpr int kMinRows = 3;
constexpr size_t kMaxMeasuredRows = 48;      // rows a classification measures at most
constexpr size_t kMaxPaintRows = 24;         // rows a paint measurement measures at most
constexpr int kMinHeights = 3;
constexpr float kMinContrast = 10.0f;        // grey levels: below this a band is sensor noise
constexpr double kBandReach = 0.3;           // m: bands this close to the trace belong to it
constexpr double kMinShift = 0.02;           // m: smaller offsets of the paint are not applied
constexpr float kShadowRatio = 1.4f;         // a shadow's sunlit side is at least this much brighter
constexpr double kCoverageReach = 0.15;      // m: paint this close to the line covers it
constexpr double kMinCoverageLength = 3.0;   // m of measured road for a coverage
constexpr double kFollowReach = 0.15;        // m: a followed row's band is sought this close
constexpr double kFollowSpacing = 0.1;       // m of road between followed rows at least
constexpr double kFollowFit = 4.0;            // m of road behind the last row found that make the line ahead
constexpr double kEdgeReference[2] = {0.7, 1.0};  // m inside a road edge: the road's look
constexpr double kArrowReach = 2.5;           // m beyond a stroke's far end where an arrow's head is sought
constexpr double kArrowBack = 3.0;            // ... and from this far before it
constexpr double kArrowHalfWidth = 0.8;       // m either side of the stroke's extension looked at
constexpr double kArrowTaper = 0.5;           // an arrow's head narrows below this share of its base
constexpr double kArrowWidthShare = 1.0;      // a head is wider than paint_width_max (no lane line is)
constexpr double kEdgeBeyond = 0.3;          // m: an edge is sought up to this far beyond the line
constexpr double kEdgeRun = 0.12;            // m of mostly not-road in a row that make the edge
constexpr double kEdgeFill = 0.75;           // share of kEdgeRun that is not road

float median(std::vector<float>& v) {
  if (v.empty()) return kNaN;
  const size_t n = v.size(), k = n / 2;
  // up to kMaxMeasuredRows finite samples: the element whose rank range holds k, found by
  // counting (branch-free, vectorised; 2x faster than std::nth_element at 17-48 samples, which
  // partitions by unpredictable branches); the same element nth_element puts at k
  if (n > 16 && n <= 64 && std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); })) {
    const float* a = v.data();
    for (size_t i = 0; i < n; ++i) {
      size_t below = 0, up_to = 0;
      for (size_t j = 0; j < n; ++j) {
        below += a[j] < a[i];
        up_to += a[j] <= a[i];
      }
      if (below <= k && k < up_to) return a[i];
    }
  }
  auto mid = v.begin() + k;
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// median() of grey values (integers 0-255), the same element: above 16 samples (where
/// std::nth_element stops sorting by insertion) by counting, 4-8x faster at 30-120 samples.
float greyMedian(std::vector<float>& v) {
  if (v.size() <= 16) return median(v);
  std::array<uint16_t, 256> count{};
  for (float g : v) ++count[static_cast<uint8_t>(g)];
  const size_t rank = v.size() / 2 + 1;  // nth_element's v.size() / 2, counted from 1
  size_t seen = 0;
  int b = 0;
  while ((seen += count[b]) < rank) ++b;
  return static_cast<float>(b);
}

/// One row of the input image: its grey values and its colours, read in place.
class ImageRow {
 public:
  /// Row @p v of @p in; valid() is false outside the grey image's rows.
  ImageRow(const ClassifierInput& in, int v) {
    if (v < in.grey_rows.start || v >= in.grey_rows.end || v < 0 || v >= in.grey->rows) return;
    grey_ = in.grey->ptr<uint8_t>(v);
    colour_ = in.colour->ptr<uint8_t>(v);
    cn_ = in.colour->channels();
    switch (in.format) {
      case PixelFormat::kMono8:
        r_ = g_ = b_ = 0;
        break;
      case PixelFormat::kRgb8:
      case PixelFormat::kRgba8:
        r_ = 0, g_ = 1, b_ = 2;
        break;
      default:  // bgr8, bgra8
        b_ = 0, g_ = 1, r_ = 2;
        break;
    }
  }
  bool valid() const { return grey_ != nullptr; }
  /// Grey value (BT.601 luma) at column @p u.
  float grey(int u) const { return grey_[u]; }
  /// Colour at column @p u (0-255).
  void rgb(int u, float& R, float& G, float& B) const {
    const uint8_t* px = colour_ + static_cast<size_t>(u) * cn_;
    R = px[r_], G = px[g_], B = px[b_];
  }
  /// rg chromaticity at column @p u.
  void chroma(int u, float& r, float& g) const {
    float R, G, B;
    rgb(u, R, G, B);
    const float sum = R + G + B + 1e-3f;
    r = R / sum;
    g = G / sum;
  }

 private:
  const uint8_t* grey_ = nullptr;
  const uint8_t* colour_ = nullptr;
  int cn_ = 1, r_ = 0, g_ = 0, b_ = 0;
};

// The step of per-row height differences @p steps: their median, when at least kStepShare of them
// reach @p kerb (else NaN: no consistent step). False when fewer than kMinHeights are measured.
bool stepInMostRows(std::vector<float>& steps, float kerb, float& step) {
  step = kNaN;
  if (static_cast<int>(steps.size()) < kMinHeights) return false;
  const auto high = std::count_if(steps.begin(), steps.end(), [kerb](float h) { return h >= kerb; });
  if (high >= kStepShare * static_cast<double>(steps.size())) step = median(steps);
  return true;
}

// The road under input pixel (u, v): its forward distance in the plane frame and the pixels per
// metre across the road there; false where the pixel's ray does not meet the road.
bool roadAt(const ClassifierInput& in, double u, double v, double& f, double& ppm) {
  const Intrinsics& K = in.K;
  const Eigen::Vector3d ray((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
  const double den = in.plane->normal.dot(ray);
  if (!(den < -1e-9)) return false;
  const double t = -in.plane->distance / den;
  f = in.frame.toRoad(ray * t).x();
  ppm = K.fx / t;
  return true;
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
  followed_.reserve(kReservedPixels);
  followed_near_.reserve(kReservedPixels);
  follow_f_.reserve(kReservedPixels);
  side_.reserve(2 * kMaxProfileHalf + 1);
  for (auto* v : {&ridge_, &step_, &chroma_, &width_, &line_h_, &inner_h_, &outer_h_, &shift_,
                  &far_step_})
    v->reserve(kMaxMeasuredRows);
  pair_step_.reserve(2 * kMaxMeasuredRows);
  pair_raise_.reserve(2 * kMaxMeasuredRows);
}

float BoundaryClassifier::heightAt(const ClassifierInput& in, int u, int v) const {
  const cv::Mat& P = *in.points;
  const int x = static_cast<int>((u + 0.5) * in.scale_x);
  const int y = static_cast<int>((v + 0.5) * in.scale_y);
  if (x < 0 || y < 0 || x >= P.cols || y >= P.rows) return kNaN;
  // the pixel's own depth, else the nearest in its column within kHeightSearch rows (a LiDAR's
  // scan lines leave rows between them empty); filled road points are no measurement
  for (int k = 0; k <= kHeightSearch; ++k) {
    for (int yy : {y + k, y - k}) {
      if (yy < 0 || yy >= P.rows || (k == 0 && yy != y)) continue;
      if (in.filled != nullptr && in.filled->at<uint8_t>(yy, x) != 0) continue;
      const float* q = P.ptr<float>(yy) + 3 * x;
      if (!std::isfinite(q[2])) continue;
      const Eigen::Vector3d& n = in.plane->normal;
      return static_cast<float>(n.x() * q[0] + n.y() * q[1] + n.z() * q[2] + in.plane->distance);
    }
  }
  return kNaN;
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

double BoundaryClassifier::cosHeading(const ClassifierInput& in,
                                      const std::vector<cv::Point2f>& pixels) const {
  // the line's heading in the road plane (profiles are read along image rows, i.e. across the
  // road: a band's width is its extent there times cos(heading))
  const Eigen::Vector3d& n = in.plane->normal;
  const double d = in.plane->distance;
  Eigen::Vector2d a(0, 0), b(0, 0);
  bool have_a = false;
  for (const auto& c : pixels) {
    const Eigen::Vector3d ray((c.x - in.K.cx) / in.K.fx, (c.y - in.K.cy) / in.K.fy, 1.0);
    const double den = n.dot(ray);
    if (!(den < -1e-9)) continue;
    const Eigen::Vector2d q = in.frame.toRoad(ray * (-d / den));
    if (!have_a) {
      a = q;
      have_a = true;
    }
    b = q;
  }
  const Eigen::Vector2d t = b - a;
  return t.norm() > 0.5 ? std::max(0.5, std::fabs(t.x()) / t.norm()) : 1.0;
}

bool BoundaryClassifier::measureRow(const ClassifierInput& in, const cv::Point2f& c, bool left,
                                    const Params& p, double cos_heading, RowMeasure& m) {
  const cv::Mat& colour = *in.colour;
  const Intrinsics& K = in.K;
  m = RowMeasure();
  m.v = static_cast<int>(std::lround(c.y));
  if (m.v < 0 || m.v >= colour.rows) return false;
  const Eigen::Vector3d ray((c.x - K.cx) / K.fx, (m.v - K.cy) / K.fy, 1.0);
  const double den = in.plane->normal.dot(ray);
  if (!(den < -1e-9)) return false;
  m.depth = -in.plane->distance / den;  // of the road at this pixel (ray z = 1)
  m.ppm = K.fx / m.depth;               // pixels per metre across the road at this row
  if (m.ppm < kMinPixelsPerMetre) return false;
  m.u0 = static_cast<int>(std::lround(c.x));
  m.W = std::min(kMaxProfileHalf, std::max(5, static_cast<int>(std::lround(kProfileHalfWidth * m.ppm))));
  if (m.u0 - m.W < 0 || m.u0 + m.W >= colour.cols) return false;
  const ImageRow row(in, m.v);
  if (!row.valid()) return false;
  profile_.resize(2 * m.W + 1);
  for (int k = -m.W; k <= m.W; ++k) profile_[k + m.W] = row.grey(m.u0 + k);
  // backgrounds of both sides, outward from the trace
  m.outer_dir = left ? -1 : 1;  // image direction away from the vehicle
  const int s0 = std::max(2, static_cast<int>(std::ceil(kSideNear * m.ppm)));
  const int s1 = std::max(s0 + 1, static_cast<int>(std::floor(kSideFar * m.ppm)));
  for (int s = 0; s < 2; ++s) {
    const int dir = s == 1 ? m.outer_dir : -m.outer_dir;
    side_.clear();
    double sr = 0, sg = 0;
    for (int k = s0; k <= s1 && k <= m.W; ++k) {
      float r, g;
      row.chroma(m.u0 + dir * k, r, g);
      side_.push_back(profile_[m.W + dir * k]);
      sr += r;
      sg += g;
    }
    if (side_.empty()) return false;
    m.chroma[s][0] = static_cast<float>(sr / side_.size());
    m.chroma[s][1] = static_cast<float>(sg / side_.size());
    m.bg[s] = greyMedian(side_);
  }
  m.top = std::max(m.bg[0], m.bg[1]);
  m.contrast =
      std::max(kMinContrast, static_cast<float>(p.paint_contrast) * std::max(m.top, 1.0f));
  // the brightest pixel near the trace
  const int search = std::max(2, static_cast<int>(std::lround(kPeakSearch * m.ppm)));
  m.peak = profile_[m.W];
  for (int k = -search; k <= search; ++k) m.peak = std::max(m.peak, profile_[k + m.W]);
  // bright bands near the trace, by width where the pixels resolve them: the painted one
  // nearest the trace, else a narrow one (a rail head), else a wide one
  if (m.ppm >= kWidthPixelsPerMetre) {
    findBands(m.W, m.top, m.top + m.contrast);
    const double reach = kBandReach * m.ppm;
    for (const Band& b : bands_) {
      const double centre = 0.5 * (b.lo + b.hi);
      if (b.open || std::fabs(centre) > reach) continue;
      const double w = (b.hi - b.lo) / m.ppm * cos_heading;
      const Band** slot = w < p.paint_width_min   ? &m.narrow
                          : w > p.paint_width_max ? &m.wide
                                                  : &m.paint;
      if (*slot == nullptr || std::fabs(centre) < std::fabs(0.5 * ((*slot)->lo + (*slot)->hi)))
        *slot = &b;
    }
  }
  return true;
}

Eigen::Vector3f BoundaryClassifier::pointAt(const ClassifierInput& in, int u, int v) const {
  const cv::Mat& P = *in.points;
  const int x = static_cast<int>((u + 0.5) * in.scale_x);
  const int y = static_cast<int>((v + 0.5) * in.scale_y);
  if (x < 0 || y < 0 || x >= P.cols || y >= P.rows) return Eigen::Vector3f::Constant(kNaN);
  const float* q = P.ptr<float>(y) + 3 * x;
  return Eigen::Vector3f(q[0], q[1], q[2]);
}

bool BoundaryClassifier::bandCentre(const ClassifierInput& in, int v, double u, int half,
                                    double max_px, const Params& p, double& centre) {
  const int margin = std::max(3, half);
  const int u0 = static_cast<int>(std::lround(u));
  const int W = half + margin;
  if (u0 - W < 0 || u0 + W >= in.colour->cols) return false;
  const ImageRow row(in, v);
  if (!row.valid()) return false;
  profile_.resize(2 * W + 1);
  for (int k = -W; k <= W; ++k) profile_[k + W] = row.grey(u0 + k);
  // the road beside the window, and the brightest pixel in it
  side_.clear();
  for (int k = -W; k <= W; ++k)
    if (std::abs(k) > half) side_.push_back(profile_[k + W]);
  const float bg = greyMedian(side_);
  int kp = -half;
  for (int k = -half; k <= half; ++k)
    if (profile_[k + W] > profile_[kp + W]) kp = k;
  const float peak = profile_[kp + W];
  if (peak - bg < std::max(kMinContrast, static_cast<float>(p.paint_contrast) * std::max(bg, 1.0f)))
    return false;
  const float level = bg + 0.5f * (peak - bg);
  int l = kp, r = kp;
  while (l - 1 >= -W && profile_[l - 1 + W] >= level) --l;
  while (r + 1 <= W && profile_[r + 1 + W] >= level) ++r;
  if (r - l + 1 > max_px || l == -W || r == W) return false;
  double sw = 0.0, sx = 0.0;
  for (int k = l; k <= r; ++k) {
    const double w = profile_[k + W] - level + 1e-3;
    sw += w;
    sx += w * k;
  }
  centre = u0 + sx / sw;
  return true;
}

template <typename FindInRow>
int BoundaryClassifier::followRows(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                                   std::vector<Eigen::Vector3f>& points, double max_gap,
                                   double max_range, FindInRow&& find) {
  if (pixels.size() < 2 || in.plane == nullptr || !in.plane->valid || !in.frame.valid()) return 0;
  // the trace by row, near (bottom) to far (top)
  int v_near = 0, v_far = in.colour->rows;
  for (const auto& c : pixels) {
    v_near = std::max(v_near, static_cast<int>(std::lround(c.y)));
    v_far = std::min(v_far, static_cast<int>(std::lround(c.y)));
  }
  auto traceColumn = [&](double v) {  // the trace polyline's column at row v (rows decrease)
    for (size_t i = 1; i < pixels.size(); ++i) {
      const cv::Point2f& a = pixels[i - 1];
      const cv::Point2f& b = pixels[i];
      if ((v <= a.y && v >= b.y) || (v >= a.y && v <= b.y)) {
        const double t = std::fabs(b.y - a.y) > 1e-6 ? (v - a.y) / (b.y - a.y) : 0.0;
        return a.x + t * (b.x - a.x);
      }
    }
    return static_cast<double>(v >= pixels.front().y ? pixels.front().x : pixels.back().x);
  };
  // the straight line u(v) through the trace: where nothing has been found beyond it yet
  double ta = 0.0, tb = 0.0;
  {
    double s1 = 0, sv = 0, su = 0, svv = 0, suv = 0;
    for (const auto& c : pixels)
      s1 += 1, sv += c.y, su += c.x, svv += c.y * c.y, suv += c.x * c.y;
    const double den = s1 * svv - sv * sv;
    tb = std::fabs(den) > 1e-9 ? (s1 * suv - sv * su) / den : 0.0;
    ta = (su - tb * sv) / s1;
  }
  // forward distance of a road pixel, and pixels per metre across the road there
  auto road = [&](double u, int v, double& f, double& ppm) {
    return roadAt(in, u, v, f, ppm) && f > 0.0 && f <= max_range && ppm >= 1.5;
  };
  // One direction from the trace: rows v0, v0 + step, ...; inside the trace's rows the column
  // comes from the trace, outside it from a line through the last rows found.
  auto follow = [&](int v0, int step, std::vector<cv::Point2f>& out) {
    out.clear();
    follow_f_.clear();
    double last_f = -1.0, measured_f = -1.0;
    for (int v = v0; v >= 0 && v < in.colour->rows; v += step) {
      const bool inside = v <= v_near && v >= v_far;
      double u;
      if (inside) {
        u = traceColumn(v);
      } else if (out.size() < 2) {
        u = ta + tb * v;
      } else {  // least-squares line u(v) through the last rows found
        size_t first = out.size() - 2;  // the rows within kFollowFit of the last one found
        while (first > 0 && std::fabs(follow_f_[first - 1] - follow_f_.back()) <= kFollowFit) --first;
        double s1 = 0, sv = 0, su = 0, svv = 0, suv = 0;
        for (size_t i = first; i < out.size(); ++i) {
          s1 += 1, sv += out[i].y, su += out[i].x, svv += out[i].y * out[i].y,
              suv += out[i].x * out[i].y;
        }
        const double den = s1 * svv - sv * sv;
        const double b = std::fabs(den) > 1e-9 ? (s1 * suv - sv * su) / den : 0.0;
        u = (su - b * sv) / s1 + b * v;
      }
      double f = 0.0, ppm = 0.0;
      if (!road(u, v, f, ppm)) {
        if (!inside) break;
        continue;
      }
      if (!inside && last_f >= 0.0 && std::fabs(f - last_f) > max_gap) break;  // past the line
      // near the car rows are a few centimetres apart: one in kFollowSpacing of road is enough
      if (measured_f >= 0.0 && std::fabs(f - measured_f) < kFollowSpacing) continue;
      measured_f = f;
      double centre;
      if (find(v, u, ppm, inside || out.size() < 2, centre)) {
        out.emplace_back(static_cast<float>(centre), static_cast<float>(v));
        follow_f_.push_back(f);
        last_f = f;
      } else if (!inside && last_f < 0.0 && out.empty()) {
        last_f = f;  // a gap from the trace's end on
      }
    }
  };
  follow(v_near, -1, followed_);           // from the trace's nearest row to the far end
  follow(v_near + 1, 1, followed_near_);   // below it, toward the car
  const int found = static_cast<int>(followed_.size() + followed_near_.size());
  if (found < 3) return found;
  pixels.clear();
  points.clear();
  for (auto it = followed_near_.rbegin(); it != followed_near_.rend(); ++it) pixels.push_back(*it);
  pixels.insert(pixels.end(), followed_.begin(), followed_.end());
  for (const auto& c : pixels)
    points.push_back(pointAt(in, static_cast<int>(std::lround(c.x)), static_cast<int>(std::lround(c.y))));
  return found;
}

int BoundaryClassifier::followLine(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                                   std::vector<Eigen::Vector3f>& points, const Params& p,
                                   double max_gap, double max_range, double reach) {
  return followRows(in, pixels, points, max_gap, max_range,
                    [&](int v, double u, double ppm, bool from_trace, double& centre) {
                      // where the column comes from the trace (@p reach: wider for a predicted
                      // line), else from the rows found
                      const double r = from_trace ? reach : kFollowReach;
                      const int half = std::min(48, std::max(2, static_cast<int>(std::lround(r * ppm))));
                      return bandCentre(in, v, u, half, p.paint_width_max * ppm + 2.0, p, centre);
                    });
}

bool BoundaryClassifier::centreDoubleLine(const ClassifierInput& in,
                                          std::vector<cv::Point2f>& pixels,
                                          std::vector<Eigen::Vector3f>& points, const Params& p) {
  if (in.plane == nullptr || !in.plane->valid || pixels.size() < static_cast<size_t>(kMinRows))
    return false;
  const Intrinsics& K = in.K;
  // pixels per metre across the road at an input pixel (0: not on the road)
  auto ppmAt = [&](const cv::Point2f& c) {
    const Eigen::Vector3d ray((c.x - K.cx) / K.fx, (c.y - K.cy) / K.fy, 1.0);
    const double den = in.plane->normal.dot(ray);
    return den < -1e-9 ? K.fx * (-den) / in.plane->distance : 0.0;
  };
  twin_[0].clear();
  twin_[1].clear();
  int measured = 0;
  const size_t stride = (pixels.size() + kMaxMeasuredRows - 1) / kMaxMeasuredRows;
  for (size_t i = 0; i < pixels.size(); i += stride) {
    const cv::Point2f& c = pixels[i];
    const double ppm = ppmAt(c);
    if (ppm < kWidthPixelsPerMetre) continue;  // the gap is not resolved
    ++measured;
    const int half = std::max(2, static_cast<int>(std::lround(kDoubleReach * ppm)));
    const int v = static_cast<int>(std::lround(c.y));
    for (int s = 0; s < 2; ++s) {
      const double probe = c.x + (s == 0 ? -1.0 : 1.0) * kDoublePitch * ppm;
      double twin;
      if (!bandCentre(in, v, probe, half, p.paint_width_max * ppm + 2.0, p, twin)) continue;
      const double offset = (twin - c.x) / ppm;
      if (std::fabs(offset) >= kDoubleMin && std::fabs(offset) <= kDoubleMax)
        twin_[s].push_back(static_cast<float>(offset));
    }
  }
  if (measured < kMinRows) return false;
  const int s = twin_[0].size() >= twin_[1].size() ? 0 : 1;
  if (twin_[s].size() < kDoubleShare * measured || twin_[1 - s].size() > 0.2 * measured)
    return false;
  const float offset = median(twin_[s]);  // metres across the road to the second line
  for (size_t i = 0; i < pixels.size(); ++i) {
    pixels[i].x += static_cast<float>(0.5 * offset * ppmAt(pixels[i]));
    points[i] = pointAt(in, static_cast<int>(std::lround(pixels[i].x)),
                        static_cast<int>(std::lround(pixels[i].y)));
  }
  return true;
}

int BoundaryClassifier::followEdge(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                                   std::vector<Eigen::Vector3f>& points, bool left,
                                   const Params& p, double max_gap, double max_range,
                                   double reach) {
  return followRows(in, pixels, points, max_gap, max_range,
                    [&](int v, double u, double ppm, bool from_trace, double& edge) {
                      // the rows found predict the edge itself
                      return edgeInRow(in, v, u, ppm, left, p,
                                       from_trace ? std::min(reach, kEdgeReference[0]) : kFollowReach,
                                       edge);
                    });
}

bool BoundaryClassifier::edgeInRow(const ClassifierInput& in, int v, double u, double ppm,
                                   bool left, const Params& p, double inside, double& edge) {
  if (ppm < kMinPixelsPerMetre) return false;
  const int out_dir = left ? -1 : 1;
  const int u0 = static_cast<int>(std::lround(u));
  const int start = static_cast<int>(std::lround(inside * ppm));
  const int ref0 = static_cast<int>(std::lround(kEdgeReference[0] * ppm));
  const int ref1 = static_cast<int>(std::lround(kEdgeReference[1] * ppm));
  const int beyond = static_cast<int>(std::lround(kEdgeBeyond * ppm));
  const int run = std::max(3, static_cast<int>(std::lround(kEdgeRun * ppm)));
  const int far_end = beyond + run + 3;
  if (u0 - out_dir * ref1 < 0 || u0 - out_dir * ref1 >= in.colour->cols ||
      u0 + out_dir * far_end < 0 || u0 + out_dir * far_end >= in.colour->cols)
    return false;
  const ImageRow row(in, v);
  if (!row.valid()) return false;
  // the road well inside the line: its grey and colour
  side_.clear();
  double sr = 0.0, sg = 0.0;
  for (int k = ref0; k <= ref1; ++k) {
    float r, g;
    row.chroma(u0 - out_dir * k, r, g);
    side_.push_back(row.grey(u0 - out_dir * k));
    sr += r;
    sg += g;
  }
  const float road = greyMedian(side_);
  const float road_r = static_cast<float>(sr / side_.size()), road_g = static_cast<float>(sg / side_.size());
  const float brighter = std::max(kMinContrast, static_cast<float>(p.paint_contrast) * std::max(road, 1.0f));
  // outward from well inside the line: the first window of kEdgeRun that is mostly not road
  // (a kerb face, a pavement, grass; a gutter's scattered leaves are not enough)
  const float chroma2 = static_cast<float>(p.edge_chroma * p.edge_chroma);
  other_.clear();
  for (int k = -start; k <= beyond + run; ++k) {
    const int x = u0 + out_dir * k;
    bool other = row.grey(x) - road >= brighter;
    if (!other) {
      float r, g;
      row.chroma(x, r, g);
      other = (r - road_r) * (r - road_r) + (g - road_g) * (g - road_g) >= chroma2;
    }
    other_.push_back(other);
  }
  const int need = static_cast<int>(std::ceil(kEdgeFill * run));
  int count = 0;
  for (int j = 0; j < run; ++j) count += other_[j];
  for (int j = 0; j + run <= static_cast<int>(other_.size()) && j - start <= beyond; ++j) {
    if (j > 0) count += other_[j + run - 1] - other_[j - 1];
    if (count >= need && other_[j]) {
      edge = u0 + out_dir * (j - start - 0.5);
      return true;
    }
  }
  return false;
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
  if (!roadAt(in, b.x, b.y, f0, ppm0)) return false;
  // from kArrowBack before the far end (the follow may have run up the head's narrow tip)
  int v_start = static_cast<int>(std::lround(b.y)) - 1;
  for (size_t i = pixels.size(); i-- > 0;) {
    double f = 0.0, ppm = 0.0;
    if (!roadAt(in, pixels[i].x, pixels[i].y, f, ppm) || f0 - f > kArrowBack) break;
    v_start = static_cast<int>(std::lround(pixels[i].y));
  }
  int wide = 0, widest = 0;
  for (int v = v_start; v >= 0; --v) {
    const double u = v >= b.y ? columnAt(pixels, v) : b.x + du * (v - b.y);
    double f = 0.0, ppm = 0.0;
    if (!roadAt(in, u, v, f, ppm) || f - f0 > kArrowReach) break;
    if (ppm < kWidthPixelsPerMetre) break;
    const ImageRow row(in, v);
    if (!row.valid()) break;
    const int W = std::min(kMaxProfileHalf, static_cast<int>(std::lround(kArrowHalfWidth * ppm)));
    const int u0 = static_cast<int>(std::lround(u));
    if (u0 - W < 0 || u0 + W >= in.colour->cols) break;
    side_.clear();
    for (int x = u0 - W; x <= u0 + W; ++x) side_.push_back(row.grey(x));
    const float bg = greyMedian(side_);
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
    }
    if (bounded && width > kArrowWidthShare * p.paint_width_max * ppm) {
      ++wide;
      widest = std::max(widest, width);
    } else if (wide >= kMinRows && width > 0 && width < kArrowTaper * widest) {
      return true;  // the head narrows to its tip (a zebra stripe keeps its width, then ends)
    }
  }
  return false;
}

bool BoundaryClassifier::cutAtObject(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                                     bool left, const Params& p) {
  // the first pixel (near to far) from which the line or the road beside it on the vehicle's
  // side reads depth well above the road on two of three measured pixels; the line before it
  // must lie on the road (within the kerb height) on most of its measured pixels
  if (in.plane == nullptr || !in.plane->valid) return false;
  const Intrinsics& K = in.K;
  object_.clear();  // per pixel: 1 object, 0 road, 2 off the road but no object, -1 no depth
  for (const auto& c : pixels) {
    const int u = static_cast<int>(std::lround(c.x));
    const int v = static_cast<int>(std::lround(c.y));
    const Eigen::Vector3d ray((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
    const double den = in.plane->normal.dot(ray);
    if (!(den < -1e-9)) {
      object_.push_back(-1);
      continue;
    }
    const int inner = static_cast<int>(std::lround(kHeightNear * K.fx * (-den) / in.plane->distance));
    const float h = heightAt(in, u, v);
    const float hi = heightAt(in, left ? u + inner : u - inner, v);
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
      if (measured < kMinHeights || on_road < kStepShare * measured ||
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
                                  bool left, const Params& p, BoundaryEvidence& ev) {
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
  cutAtObject(in, pixels, left, p);
  const Intrinsics& K = in.K;
  const Eigen::Vector3d& n = in.plane->normal;
  const double d = in.plane->distance;
  const double cos_heading = cosHeading(in, pixels);

  int paint_rows = 0, narrow_rows = 0, wide_rows = 0;
  RowMeasure m;
  // at most kMaxMeasuredRows rows, spread evenly along the line (a followed line has a point on
  // every image row; its medians need no more)
  const size_t stride = (pixels.size() + kMaxMeasuredRows - 1) / kMaxMeasuredRows;
  for (size_t i = 0; i < pixels.size(); i += stride) {
    const cv::Point2f& c = pixels[i];
    if (!measureRow(in, c, left, p, cos_heading, m)) continue;
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
      const bool shadow = m.bg[1 - dark] >= kShadowRatio * std::max(m.bg[dark], 1.0f) &&
                          blue_dark - blue_light > 0.5f * dist;
      chroma_.push_back(shadow ? 0.0f : dist);
    }
    if (m.peak - m.top >= m.contrast) ++ev.ridge_rows;
    const Band* chosen = m.paint ? m.paint : m.narrow ? m.narrow : m.wide;
    if (chosen) {
      width_.push_back(static_cast<float>((chosen->hi - chosen->lo) / m.ppm * cos_heading));
      if (m.paint) {
        ++paint_rows;
        shift_.push_back(static_cast<float>(0.5 * (m.paint->lo + m.paint->hi) / m.ppm));
      } else if (m.narrow) {
        ++narrow_rows;
      } else {
        ++wide_rows;
      }
    }
    // heights of the line and of the surfaces beside it (where depth exists)
    const float hl = heightAt(in, m.u0, m.v);
    if (std::isfinite(hl)) line_h_.push_back(hl);
    for (double off : {kHeightNear, kHeightFar}) {
      const int k = static_cast<int>(std::lround(off * m.ppm));
      const float hi = heightAt(in, m.u0 - m.outer_dir * k, m.v);
      const float ho = heightAt(in, m.u0 + m.outer_dir * k, m.v);
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
  // pairs, the sides' medians against the plane
  const float kerb = static_cast<float>(p.kerb_height);
  const float inner = std::isfinite(ev.inner_height) ? ev.inner_height : 0.0f;
  float step_h = kNaN, raise_h = kNaN;
  if (!stepInMostRows(pair_step_, kerb, step_h) && std::isfinite(ev.outer_height))
    step_h = ev.outer_height - inner;
  if (!stepInMostRows(pair_raise_, kerb, raise_h) && std::isfinite(ev.line_height))
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

void BoundaryClassifier::measurePaint(const ClassifierInput& in,
                                      const std::vector<cv::Point2f>& pixels, bool left,
                                      const Params& p, float& coverage, float& yellowness) {
  coverage = yellowness = -1.0f;
  if (in.plane == nullptr || !in.plane->valid || !in.frame.valid() || pixels.size() < 2) return;
  const double cos_heading = cosHeading(in, pixels);
  // each point stands for the stretch of road half-way to its neighbours
  auto forward = [&](const cv::Point2f& c) {
    const Eigen::Vector3d ray((c.x - in.K.cx) / in.K.fx, (c.y - in.K.cy) / in.K.fy, 1.0);
    const double den = in.plane->normal.dot(ray);
    return den < -1e-9 ? in.frame.toRoad(ray * (-in.plane->distance / den)).x() : NAN;
  };
  double covered = 0.0, total = 0.0;
  yellow_.clear();
  RowMeasure m;
  // at most kMaxPaintRows points, spread along the boundary, each standing for the stretch
  // half-way to its measured neighbours
  const size_t n = pixels.size();
  const size_t stride = (n + kMaxPaintRows - 1) / kMaxPaintRows;
  for (size_t k = 0; k < n; k += stride) {
    const double fa = forward(pixels[k >= stride ? k - stride : k]);
    const double fb = forward(pixels[k + stride < n ? k + stride : k]);
    const double weight = std::isfinite(fa) && std::isfinite(fb) ? 0.5 * std::fabs(fb - fa) : 0.0;
    if (!(weight > 0.0) || !measureRow(in, pixels[k], left, p, cos_heading, m)) continue;
    total += weight;
    // paint here: a band of paint width on the line, or, where the pixels cannot resolve its
    // width, a bright enough peak
    const Band* band = m.paint;
    if (band && std::fabs(0.5 * (band->lo + band->hi)) > kCoverageReach * m.ppm) band = nullptr;
    const bool paint = band || (m.ppm < kWidthPixelsPerMetre && m.peak - m.top >= m.contrast);
    if (!paint) continue;
    covered += weight;
    if (!band) continue;
    // colour of the paint against the road beside it (the illumination cancels): yellow paint
    // reflects little blue
    const ImageRow row(in, m.v);
    double pr = 0, pg = 0, pb = 0, ar = 0, ag = 0, ab = 0;
    int np = 0, na = 0;
    for (int k2 = static_cast<int>(std::ceil(band->lo)); k2 <= static_cast<int>(std::floor(band->hi)); ++k2) {
      float R, G, B;
      row.rgb(m.u0 + k2, R, G, B);
      pr += R, pg += G, pb += B, ++np;
    }
    const int s0 = std::max(2, static_cast<int>(std::ceil(kSideNear * m.ppm)));
    const int s1 = std::max(s0 + 1, static_cast<int>(std::floor(kSideFar * m.ppm)));
    for (int dir : {-1, 1})
      for (int k2 = s0; k2 <= s1 && k2 <= m.W; ++k2) {
        float R, G, B;
        row.rgb(m.u0 + dir * k2, R, G, B);
        ar += R, ag += G, ab += B, ++na;
      }
    if (np == 0 || na == 0 || ab <= 0.0 || ar <= 0.0 || ag <= 0.0) continue;
    const double r = (pr / np) / (ar / na), g = (pg / np) / (ag / na), b = (pb / np) / (ab / na);
    yellow_.push_back(static_cast<float>(1.0 - b / (0.5 * (r + g))));
  }
  if (total >= kMinCoverageLength) coverage = static_cast<float>(covered / total);
  if (yellow_.size() >= 3) yellowness = std::max(0.0f, median(yellow_));
}

}  // namespace rgbd_lane_detector
