#include "rgbd_lane_detector/band_profile.h"

#include <algorithm>
#include <cmath>

#include "rgbd_lane_detector/geometry.h"
#include "row_statistics.h"

namespace rgbd_lane_detector {
namespace {

constexpr double kProfileHalfWidth = 0.6;  // m each side of the line
constexpr double kPeakSearch = 0.1;        // m: the band's peak is sought this close to the trace
constexpr double kBandReach = 0.3;         // m: bands this close to the trace belong to it
constexpr double kEdgeBeyond = 0.3;        // m: an edge is sought up to this far beyond the line
constexpr double kEdgeRun = 0.12;          // m of mostly not-road in a row that make the edge
constexpr double kEdgeFill = 0.75;         // share of kEdgeRun that is not road
constexpr float kMadToSigma = 1.4826f;     // median absolute deviation to a Gaussian's sigma
constexpr float kNoiseSigmas = 3.0f;       // a band stands this many noise sigmas above the road
constexpr size_t kMinNoiseSamples = 5;     // side pixels a row's noise is estimated from
// m of road across which the profile is averaged where the pixels are finer: near the camera a
// pixel spans a few millimetres, and a painted line's texture (worn paint, the aggregate showing
// through, raised markers) dips between its bright grains deeper than half their contrast,
// splitting one line into bands narrower than paint (a rail head stays one, 4-7 cm wide)
constexpr double kTextureScale = 0.015;

}  // namespace

BandProfile::BandProfile() {
  side_.reserve(2 * kMaxProfileHalf + 1);
  run_max_.resize(2 * kMaxProfileHalf + 1);
  // (a row's grey over the profile and its averaging boxes, which reach a few pixels beyond it)
  grey_row_.reserve(4 * kMaxProfileHalf);
  prefix_.reserve(4 * kMaxProfileHalf);
  dev_.reserve(2 * kMaxProfileHalf + 1);
}

void BandProfile::addBand(int a, int b, float base, bool open, int W) {
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

void BandProfile::findBands(int W, float base, float low, double reach) {
  // Runs of the profile above `low`, split at dips deeper than half the contrast of the lower
  // of the peaks either side (a rail head next to a painted line), each band measured at half
  // its own peak.
  bands_.clear();
  const float* P = profile_.data() + W;  // P[k], k in [-W, W]
  // only the runs that reach into (-reach - 1, reach + 1): from the one through its left end on
  // (a band's centre lies within one pixel of its run)
  reach = std::min(reach, W + 1.0);  // (an infinite reach: the whole profile)
  int k = std::max(-W, static_cast<int>(std::floor(-reach)) - 1);
  if (P[k] >= low)
    while (k - 1 >= -W && P[k - 1] >= low) --k;
  const int k_stop = std::min(W, static_cast<int>(std::ceil(reach)) + 1);
  while (k <= k_stop) {
    if (P[k] < low) {
      ++k;
      continue;
    }
    int end = k;
    while (end + 1 <= W && P[end + 1] >= low) ++end;
    if (end + 1 <= -reach || k - 1 >= reach) {  // its bands' centres lie in (k - 1, end + 1)
      k = end + 1;
      continue;
    }
    // the highest value from each offset to the run's end, and from the band's start to each
    // offset, kept as it goes (one pass each, not one per local minimum)
    float* after_max = run_max_.data() + W;  // after_max[j]: max of P[j..end]
    after_max[end] = P[end];
    for (int j = end - 1; j > k; --j) after_max[j] = std::max(after_max[j + 1], P[j]);
    int seg = k;
    float before = P[k];  // max of P[seg..j]
    for (int j = k + 1; j < end; ++j) {
      before = std::max(before, P[j]);
      if (!(P[j] <= P[j - 1] && P[j] < P[j + 1])) continue;  // local minima only
      const float m = std::min(before, after_max[j]);
      if (m - P[j] > 0.5f * (m - base)) {
        addBand(seg, j - 1, base, seg == -W, W);
        seg = j + 1;
        before = P[seg];
      }
    }
    addBand(seg, end, base, seg == -W || end == W, W);
    k = end + 1;
  }
}

bool BandProfile::measureRow(const ClassifierInput& in, const cv::Point2f& c, bool left,
                             const Params& p, double cos_heading, RowMeasure& m) {
  const cv::Mat& colour = *in.colour;
  const Intrinsics& K = in.K;
  m = RowMeasure();
  m.v = static_cast<int>(std::lround(c.y));
  if (m.v < 0 || m.v >= colour.rows) return false;
  // the road's depth at this pixel (ray z = 1)
  if (!rayPlaneDepth(*in.plane, K.ray(c.x, m.v), m.depth)) return false;
  m.ppm = K.fx / m.depth;  // pixels per metre across the road at this row
  if (m.ppm < kMinPixelsPerMetre) return false;
  m.u0 = roundColumn(c.x, colour.cols);
  m.W = std::min(kMaxProfileHalf,
                 std::max(5, static_cast<int>(std::lround(kProfileHalfWidth * m.ppm))));
  if (m.u0 - m.W < 0 || m.u0 + m.W >= colour.cols) return false;
  const ImageRow row(in, m.v);
  if (!row.valid()) return false;
  profile_.resize(2 * m.W + 1);
  // each profile pixel the mean grey over kTextureScale of road (a box of 2 h + 1 pixels, cut at
  // the image border), where that spans more than a pixel either side
  const int h = static_cast<int>(0.5 * kTextureScale * m.ppm);
  if (h >= 1) {
    // the row's grey over the boxes' reach, read once (without a grey image it is computed from
    // the colour, and every pixel enters a box and leaves it)
    const int last = colour.cols - 1;
    const int x0 = std::max(0, m.u0 - m.W - h), x1 = std::min(last, m.u0 + m.W + h);
    const int n = x1 - x0 + 1;
    grey_row_.resize(static_cast<size_t>(n));
    row.greyRun(x0, n, grey_row_.data());
    // the box sums from the running sum of the row's grey (integers: exact in any order)
    prefix_.resize(static_cast<size_t>(n) + 1);
    prefix_[0] = 0;
    {
      // (a running sum in a register: the bytes may alias the vector's ints, which the compiler
      // would read back from memory on every column)
      const uint8_t* g = grey_row_.data();
      int* sums = prefix_.data();
      int sum = 0;
      for (int i = 0; i < n; ++i) sums[i + 1] = sum += g[i];
    }
    const int* S = prefix_.data() - x0;  // S[x]: the grey of the columns x0 .. x - 1
    float* out = profile_.data() + m.W;
    const auto box = [&](int k) {  // the box [u0 + k - h, u0 + k + h], cut at the image border
      const int lo = std::max(0, m.u0 + k - h), hi = std::min(last, m.u0 + k + h);
      out[k] = static_cast<float>(S[hi + 1] - S[lo]) / static_cast<float>(hi - lo + 1);
    };
    // (inside the image, k in [h - u0, last - h - u0], every box is whole: 2 h + 1 pixels)
    const int k_in = std::min(m.W + 1, std::max(-m.W, h - m.u0));
    const int k_out = std::max(k_in - 1, std::min(m.W, last - h - m.u0));
    const float whole = static_cast<float>(2 * h + 1);
    int k = -m.W;
    for (; k < k_in; ++k) box(k);
    for (; k <= k_out; ++k)
      out[k] = static_cast<float>(S[m.u0 + k + h + 1] - S[m.u0 + k - h]) / whole;
    for (; k <= m.W; ++k) box(k);
  } else {
    grey_row_.resize(static_cast<size_t>(2 * m.W + 1));
    row.greyRun(m.u0 - m.W, 2 * m.W + 1, grey_row_.data());
    for (int k = 0; k <= 2 * m.W; ++k) profile_[k] = grey_row_[k];
  }
  // backgrounds of both sides, outward from the trace
  m.outer_dir = left ? -1 : 1;  // image direction away from the vehicle
  const int s0 = std::max(2, static_cast<int>(std::ceil(kSideNear * m.ppm)));
  const int s1 = std::max(s0 + 1, static_cast<int>(std::floor(kSideFar * m.ppm)));
  m.noise = -1.0f;
  for (int s = 0; s < 2; ++s) {
    const int dir = s == 1 ? m.outer_dir : -m.outer_dir;
    // columns s0..min(s1, W) out (written in place: sized once, not pushed)
    const int n = std::min(s1, m.W) - s0 + 1;
    if (n <= 0) return false;
    side_.resize(n);
    for (int i = 0; i < n; ++i) side_[i] = profile_[m.W + dir * (s0 + i)];
    // (the colour sums in integers, over the side's columns left to right: exact, as doubles)
    int isr = 0, isg = 0, isb = 0;
    row.rgbSums(dir > 0 ? m.u0 + s0 : m.u0 - s0 - (n - 1), n, isr, isg, isb);
    const double sr = isr, sg = isg, sb = isb;
    // the chromaticity of the side's mean colour (dark pixels' colour is mostly noise: each
    // pixel counts by its brightness)
    const double sum = sr + sg + sb;
    m.chroma[s][0] = static_cast<float>(sum > 0.0 ? sr / sum : 1.0 / 3.0);
    m.chroma[s][1] = static_cast<float>(sum > 0.0 ? sg / sum : 1.0 / 3.0);
    m.bg[s] = greyMedian(side_);
    // the row's noise: the robust spread of the smoother side's grey about its median
    if (side_.size() >= kMinNoiseSamples) {
      dev_.resize(side_.size());
      const float bg = m.bg[s];
      std::transform(side_.begin(), side_.end(), dev_.begin(),
                     [bg](float x) { return std::fabs(x - bg); });
      const float sd = kMadToSigma * greyMedian(dev_);
      m.noise = m.noise < 0.0f ? sd : std::min(m.noise, sd);
    }
  }
  m.noise = std::max(m.noise, 0.0f);
  m.top = std::max(m.bg[0], m.bg[1]);
  // a band stands out by the paint contrast, and from the row's noise (a dark, noisy road at
  // night: a narrow run of noise is no rail head, a noisy step no kerb)
  m.contrast = std::max({kMinContrast,
                         static_cast<float>(p.paint_contrast) * std::max(m.top, 1.0f),
                         kNoiseSigmas * m.noise});
  // the brightest pixel near the trace
  const int search = std::max(2, static_cast<int>(std::lround(kPeakSearch * m.ppm)));
  m.peak = profile_[m.W];
  for (int k = -search; k <= search; ++k) m.peak = std::max(m.peak, profile_[k + m.W]);
  // bright bands near the trace, by width where the pixels resolve them: the painted one
  // nearest the trace, else a narrow one (a rail head), else a wide one
  if (m.ppm >= kWidthPixelsPerMetre) {
    const double reach = kBandReach * m.ppm;
    findBands(m.W, m.top, m.top + m.contrast, reach);
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

bool BandProfile::bandCentre(const ClassifierInput& in, int v, double u, int half, double max_px,
                             const Params& p, double& centre, int* width) {
  const int margin = std::max(3, half);
  const int u0 = roundColumn(u, in.colour->cols);
  const int W = half + margin;
  if (u0 - W < 0 || u0 + W >= in.colour->cols) return false;
  const ImageRow row(in, v);
  if (!row.valid()) return false;
  grey_row_.resize(static_cast<size_t>(2 * W + 1));
  row.greyRun(u0 - W, 2 * W + 1, grey_row_.data());
  const uint8_t* P = grey_row_.data() + W;  // P[k], k in [-W, W]
  // the road beside the window (the columns beyond half either side), and the brightest pixel
  // in it
  const float bg = greyMedian(P - W, W - half, P + half + 1, W - half);
  int kp = -half;
  for (int k = -half; k <= half; ++k)
    if (P[k] > P[kp]) kp = k;
  const float peak = P[kp];
  if (peak - bg < std::max(kMinContrast, static_cast<float>(p.paint_contrast) * std::max(bg, 1.0f)))
    return false;
  const float level = bg + 0.5f * (peak - bg);
  int l = kp, r = kp;
  while (l - 1 >= -W && P[l - 1] >= level) --l;
  while (r + 1 <= W && P[r + 1] >= level) ++r;
  if (r - l + 1 > max_px || l == -W || r == W) return false;
  if (width != nullptr) *width = r - l + 1;
  double sw = 0.0, sx = 0.0;
  for (int k = l; k <= r; ++k) {
    const double w = static_cast<float>(P[k]) - level + 1e-3;
    sw += w;
    sx += w * k;
  }
  centre = u0 + sx / sw;
  return true;
}

bool BandProfile::edgeInRow(const ClassifierInput& in, int v, double u, double ppm, bool left,
                            const Params& p, double inside, double& edge) {
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
  side_.resize(std::max(0, ref1 - ref0 + 1));
  double sr = 0.0, sg = 0.0;
  for (int k = ref0; k <= ref1; ++k) {
    float r, g;
    row.chroma(u0 - out_dir * k, r, g);
    side_[k - ref0] = row.grey(u0 - out_dir * k);
    sr += r;
    sg += g;
  }
  const float road = greyMedian(side_);
  const float road_r = static_cast<float>(sr / side_.size()),
              road_g = static_cast<float>(sg / side_.size());
  const float brighter =
      std::max(kMinContrast, static_cast<float>(p.paint_contrast) * std::max(road, 1.0f));
  // outward from well inside the line: the first window of kEdgeRun that is mostly not road
  // (a kerb face, a pavement, grass; a gutter's scattered leaves are not enough)
  const float chroma2 = static_cast<float>(p.edge_chroma * p.edge_chroma);
  other_.resize(std::max(0, beyond + run + start + 1));
  for (int k = -start; k <= beyond + run; ++k) {
    const int x = u0 + out_dir * k;
    bool other = row.grey(x) - road >= brighter;
    if (!other) {
      float r, g;
      row.chroma(x, r, g);
      other = (r - road_r) * (r - road_r) + (g - road_g) * (g - road_g) >= chroma2;
    }
    other_[k + start] = other;
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

}  // namespace rgbd_lane_detector
