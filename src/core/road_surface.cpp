#include "rgbd_lane_detector/road_surface.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "rgbd_lane_detector/depth_points.h"
#include "rgbd_lane_detector/geometry.h"

namespace rgbd_lane_detector {
namespace {

constexpr float kCorridorWeight = 3.0f;
constexpr int kMinSamples = 30;             // fewer near samples: no fit
constexpr int kRansacIterations = 128;
constexpr double kEarlyExit = 0.8;          // RANSAC stops at this share of the total weight
constexpr int kRefineIterations = 4;
constexpr double kPreviousBand = 4.0;       // first refit band around the previous plane (x band)
constexpr double kRansacBand = 2.0;         // first refit band around a RANSAC plane (x band)
constexpr double kMountBand = 1.0;          // first refit band around the mount's plane (x band)
constexpr double kAboveBand = 0.5;          // with a mount: share of the refit band above the plane
constexpr double kMinInlierShare = 0.15;    // of the near samples' weight
constexpr double kBelowBand = 2.0;          // RANSAC: a sample this many bands below is under it
constexpr double kBelowWeight = 4.0;        // RANSAC: a sample under a plane outweighs an inlier
constexpr double kNoiseMinDepth = 5.0;      // m: the noise growth is measured beyond this
constexpr size_t kMaxSupport = 200;         // support points kept for the message
// Valid range: 5 m bins beyond fit_range, the mode of the corridor's residuals per bin.
constexpr double kBinLength = 5.0;
constexpr int kMaxRangeBins = 40;           // bins looked at (200 m beyond fit_range)
constexpr int kMinBinSamples = 12;
constexpr float kHistogramRange = 1.0f;     // residuals within +-1 m enter the histogram
constexpr int kHistogramBins = 50;          // 4 cm bins
constexpr int kModeHalfWidth = 2;           // the mode counts the bins within +-8 cm
constexpr double kSharpMode = 0.3;          // share of a bin's samples near its mode
constexpr double kLeavesPlane = 0.08;       // m: the road left the plane

// The first of the depth blocks b, b + 1, ... of a row (its block map, nb blocks) that holds
// depth, nb when none does: eight blocks at a time while they hold none (a sparse LiDAR's rows
// are mostly blocks without depth).
inline int nextBlockWithDepth(const uint8_t* blocks, int b, int nb) {
  for (uint64_t eight; b + 8 <= nb; b += 8) {
    std::memcpy(&eight, blocks + b, sizeof(eight));
    if (eight != 0) break;
  }
  while (b < nb && !blocks[b]) ++b;
  return b;
}

// f(x) for the grid's columns x = stride / 2 + k stride of a row, in order, but none in a depth
// block without depth (blocks: the row of the block map, or null): a sparse LiDAR's grid at a
// fine stride passes over its empty blocks at once, not column by column
template <typename F>
inline void forEachGridColumn(const uint8_t* blocks, int cols, int stride, F&& f) {
  int x = stride / 2;
  if (!blocks) {
    for (; x < cols; x += stride) f(x);
    return;
  }
  if (stride >= kDepthBlock) {  // a column or none per block
    for (; x < cols; x += stride)
      if (blocks[x / kDepthBlock]) f(x);
    return;
  }
  while (x < cols) {
    int b = x / kDepthBlock;
    if (blocks[b]) {
      for (const int end = std::min(cols, (b + 1) * kDepthBlock); x < end; x += stride) f(x);
      continue;
    }
    // the blocks without depth from here on passed over at once: x onto the grid's first column
    // in the next block with depth (or past the row)
    b = nextBlockWithDepth(blocks, b + 1, (cols + kDepthBlock - 1) / kDepthBlock);
    x += (b * kDepthBlock - x + stride - 1) / stride * stride;
  }
}

// collectGrid()'s sampling rules in one place: collectGrid() samples by them, and the counts
// that choose its grid (nearGridCount(), extendedGridCount()) predict its samples by them.
class GridRules {
 public:
  GridRules(const cv::Mat& points, const RoadSurfaceSettings& s)
      : fit_range_(static_cast<float>(s.fit_range)),
        max_range_(static_cast<float>(std::max(s.max_range, s.fit_range))),
        extended_(2.0f * fit_range_),
        centre_(points.cols / 2),
        far_cols_(s.far_columns.empty() ? cv::Range(0, points.cols)
                                        : cv::Range(std::max(0, s.far_columns.start),
                                                    std::min(points.cols, s.far_columns.end))),
        first_block_((far_cols_.start + kDepthBlock - 1) / kDepthBlock * kDepthBlock) {}

  // pixel q is a sample: a number within max_range
  bool valid(const float* q) const {
    return (q[2] > 0.0f) && (q[2] <= max_range_) && std::isfinite(q[0]) && std::isfinite(q[1]);
  }
  // a sample in the corridor ahead (it weighs more)
  static bool corridor(const float* q) {
    return std::fabs(q[0]) < RoadSurface::kCorridorHalfWidth;
  }
  // a sample at depth z within fit_range (near_), else beyond it (far_)
  bool near(float z) const { return z <= fit_range_; }
  // a sample beyond fit_range at depth z that joins the near ones where they are too few (the
  // fit over twice the range: depth only farther away, a LiDAR or stereo gap near the car)
  bool joinsFew(float z) const { return !(z > extended_); }
  // a row whose corridor is scanned pixel by pixel beyond fit_range: far, or no depth at the
  // centre (far away the corridor is a few pixels wide)
  bool farRow(const float* row) const { return !(row[3 * centre_ + 2] <= 0.9f * fit_range_); }

  // f(x) for the columns x of the corridor scan of a row (blocks: its block map, or null):
  // the far columns, a block without depth passed over from its first column on, the grid's
  // columns (stride) left out on a grid row (sampled on the grid)
  template <typename F>
  void forEachCorridorColumn(const uint8_t* blocks, int stride, bool grid_row, F&& f) const {
    int grid_x = nextGrid(far_cols_.start, stride);
    for (int x = far_cols_.start; x < far_cols_.end;) {
      if (x % kDepthBlock == 0 && !scanned(blocks, x)) {  // a block without depth
        x += kDepthBlock;
        grid_x = nextGrid(x, stride);
        continue;
      }
      // the columns to the block's end (a block is looked up once)
      for (const int end = std::min(far_cols_.end, (x / kDepthBlock + 1) * kDepthBlock); x < end;
           ++x) {
        if (grid_row && x == grid_x) {  // taken on the grid
          grid_x += stride;
          continue;
        }
        f(x);
      }
    }
  }
  // f(x) for the grid's columns that forEachCorridorColumn() leaves out on a grid row
  template <typename F>
  void forEachCorridorGridColumn(const uint8_t* blocks, int stride, F&& f) const {
    for (int x = nextGrid(far_cols_.start, stride); x < far_cols_.end; x += stride)
      if (scanned(blocks, x)) f(x);
  }

 private:
  // the corridor scan reads column x (not in a block without depth that it passes over)
  bool scanned(const uint8_t* blocks, int x) const {
    return !(blocks && x >= first_block_ && !blocks[x / kDepthBlock]);
  }
  // the grid's first column at or after x (counted, not found per pixel)
  static int nextGrid(int x, int stride) {
    return x > stride / 2 ? stride / 2 + (x - stride / 2 + stride - 1) / stride * stride
                          : stride / 2;
  }

  float fit_range_, max_range_, extended_;
  int centre_;
  cv::Range far_cols_;
  int first_block_;  // the corridor scan's first whole depth block
};

double tukeyWeight(double r, double c) {
  const double u = r / c;
  if (std::fabs(u) >= 1.0) return 0.0;
  const double t = 1.0 - u * u;
  return t * t;
}

// Orient n . p + d = 0 so that the camera (origin) is on the positive side.
bool orient(Eigen::Vector3d& n, double& d) {
  if (!n.allFinite() || !std::isfinite(d) || std::fabs(d) < 1e-6) return false;
  if (d < 0.0) {
    n = -n;
    d = -d;
  }
  return true;
}

}  // namespace

const uint8_t* RoadSurface::blockRow(const cv::Mat& points, int y) const {
  if (!blocks_ || blocks_->type() != CV_8UC1 || blocks_->rows != points.rows ||
      blocks_->cols != (points.cols + kDepthBlock - 1) / kDepthBlock)
    return nullptr;
  return blocks_->ptr<uint8_t>(y);
}

void RoadSurface::collect(const cv::Mat& points, const cv::Range& rows,
                          const RoadSurfaceSettings& s) {
  // a grid of about target_samples pixels; where the depth is sparse (a LiDAR, a gap near the
  // car) and the grid holds few samples, a finer one
  const int height = std::max(0, rows.end - rows.start);
  const double area = static_cast<double>(height) * points.cols;
  int stride =
      std::max(1, static_cast<int>(std::lround(std::sqrt(area / std::max(s.target_samples, 1)))));
  // the grid chosen by counting its samples (collectGrid() also scans the far corridor: only
  // once, on the chosen grid; where the near samples are few, the far ones within twice
  // fit_range join them, and the corridor's are counted once for every grid tried)
  int corridor = -1;
  for (;;) {
    if (stride == 1) {  // the finest grid: no count decides anything
      collectGrid(points, rows, s, stride);
      return;
    }
    int count = nearGridCount(points, rows, s, stride);
    if (count < kMinSamples) count = extendedGridCount(points, rows, s, stride, corridor);
    if (!(2 * count < s.target_samples)) {
      collectGrid(points, rows, s, stride);
      return;
    }
    stride = std::max(1, stride / 2);
  }
}

int RoadSurface::extendedGridCount(const cv::Mat& points, const cv::Range& rows,
                                   const RoadSurfaceSettings& s, int stride,
                                   int& corridor) const {
  // collectGrid()'s near_ after its extension: the grid's samples within fit_range or joining
  // them, and the far corridor's samples of the pixels off the grid that join them (every pixel
  // of the corridor scan, less the grid's)
  const GridRules rules(points, s);
  auto joins = [&rules](const float* q) {
    return rules.valid(q) && GridRules::corridor(q) && !rules.near(q[2]) && rules.joinsFew(q[2]);
  };
  if (corridor < 0) {
    corridor = 0;
    for (int y = rows.start; y < rows.end; ++y) {
      const float* row = points.ptr<float>(y);
      if (!rules.farRow(row)) continue;
      rules.forEachCorridorColumn(blockRow(points, y), stride, false,
                                  [&](int x) { corridor += joins(row + 3 * x); });
    }
  }
  int count = corridor;
  for (int y = rows.start + stride / 2; y < rows.end; y += stride) {
    const float* row = points.ptr<float>(y);
    const uint8_t* blocks = blockRow(points, y);
    forEachGridColumn(blocks, points.cols, stride, [&](int x) {
      const float* q = row + 3 * x;
      if (rules.valid(q) && (rules.near(q[2]) || rules.joinsFew(q[2]))) ++count;
    });
    if (!rules.farRow(row)) continue;
    // the grid's pixels of the corridor scan: collectGrid() samples them on the grid
    rules.forEachCorridorGridColumn(blocks, stride, [&](int x) { count -= joins(row + 3 * x); });
  }
  return count;
}

int RoadSurface::nearGridCount(const cv::Mat& points, const cv::Range& rows,
                               const RoadSurfaceSettings& s, int stride) const {
  const GridRules rules(points, s);
  int count = 0;
  for (int y = rows.start + stride / 2; y < rows.end; y += stride) {
    const float* row = points.ptr<float>(y);
    // (blocks without depth give no sample)
    forEachGridColumn(blockRow(points, y), points.cols, stride, [&](int x) {
      const float* q = row + 3 * x;
      count += rules.valid(q) && rules.near(q[2]);
    });
  }
  return count;
}

void RoadSurface::collectGrid(const cv::Mat& points, const cv::Range& rows,
                              const RoadSurfaceSettings& s, int stride) {
  near_.clear();
  far_.clear();
  near_end_ = 0.0;
  const GridRules rules(points, s);
  for (int y = rows.start; y < rows.end; ++y) {
    const float* row = points.ptr<float>(y);
    // every stride-th pixel of every stride-th row on a grid (the fit)
    const bool grid_row = (y - rows.start) % stride == stride / 2;
    const uint8_t* blocks = blockRow(points, y);  // (blocks without depth give no sample)
    if (grid_row) {
      forEachGridColumn(blocks, points.cols, stride, [&](int x) {
        const float* q = row + 3 * x;
        if (!rules.valid(q)) return;
        const Sample smp{Eigen::Vector3f(q[0], q[1], q[2]),
                         GridRules::corridor(q) ? kCorridorWeight : 1.0f};
        (rules.near(q[2]) ? near_ : far_).push_back(smp);
      });
    }
    // beyond fit_range the corridor's every pixel (the valid range check)
    if (!rules.farRow(row)) continue;
    rules.forEachCorridorColumn(blocks, stride, grid_row, [&](int x) {
      const float* q = row + 3 * x;
      if (!rules.valid(q) || !GridRules::corridor(q)) return;
      if (!rules.near(q[2]))
        far_.push_back(Sample{Eigen::Vector3f(q[0], q[1], q[2]), kCorridorWeight});
      else  // how far the depth reaches within the fit's range
        near_end_ = std::max(near_end_, static_cast<double>(q[2]));
    });
  }
  // Depth only farther away (a LiDAR or stereo gap near the car): fit over twice the range.
  if (static_cast<int>(near_.size()) < kMinSamples) {
    auto mid = std::partition(far_.begin(), far_.end(),
                              [&rules](const Sample& a) { return !rules.joinsFew(a.p.z()); });
    near_.insert(near_.end(), mid, far_.end());
    far_.erase(mid, far_.end());
  }
}

cv::Range RoadSurface::corridorColumns(double fx, double cx, double fit_range) {
  const double half = kCorridorHalfWidth * fx / std::max(fit_range, 1e-3);
  return cv::Range(static_cast<int>(std::floor(cx - half)) - 1,
                   static_cast<int>(std::ceil(cx + half)) + 2);
}

bool RoadSurface::plausible(const Eigen::Vector3d& n, double d,
                            const RoadSurfaceSettings& s) const {
  if (!(d >= s.height_min && d <= s.height_max)) return false;
  return n.dot(s.up) >= std::cos(s.max_tilt_deg * M_PI / 180.0);
}

double RoadSurface::score(const Eigen::Vector3d& n, double d, const RoadSurfaceSettings& s,
                          double* below) const {
  const Eigen::Vector3f nf = n.cast<float>();
  const float df = static_cast<float>(d);
  double total = 0.0, under = 0.0;
  for (const Sample& smp : near_) {
    const float z = smp.p.z();
    const float b = static_cast<float>(s.inlier_distance + growth_ * z * z);
    const float r = nf.dot(smp.p) + df;
    if (std::fabs(r) <= b)
      total += smp.weight;
    else if (r < -kBelowBand * b)
      under += smp.weight;
  }
  if (below) *below = under;
  return total;
}

void RoadSurface::estimateNoise(const RoadSurfaceSettings& s, const Eigen::Vector3d& n, double d) {
  // depth noise that grows as z^2 (stereo, structured light): three robust sigmas of the
  // residuals per z^2 beyond 5 m, at most the settings' growth
  ratios_.clear();
  for (const Sample& smp : near_) {
    const double z = smp.p.z();
    if (z < kNoiseMinDepth) continue;
    const double signed_r = n.dot(smp.p.cast<double>()) + d;
    // with the mount's plane, below it only: nothing but noise lies below the road, kerbs,
    // pavements and vehicles above it
    if (s.mount_height > 0.0 && signed_r > 0.0) continue;
    const double r = std::fabs(signed_r);
    if (r <= s.inlier_distance + s.noise_growth * z * z) ratios_.push_back(static_cast<float>(r / (z * z)));
  }
  if (ratios_.size() < static_cast<size_t>(kMinSamples)) return;  // keep the settings' growth
  auto mid = ratios_.begin() + ratios_.size() / 2;
  std::nth_element(ratios_.begin(), mid, ratios_.end());
  growth_ = std::min(s.noise_growth, 3.0 * 1.4826 * static_cast<double>(*mid));
}

bool RoadSurface::ransac(const RoadSurfaceSettings& s, Eigen::Vector3d& n, double& d) {
  const uint32_t count = static_cast<uint32_t>(near_.size());
  if (count < 3) return false;
  double total = 0.0;
  for (const Sample& smp : near_) total += smp.weight;
  // xorshift32 from a fixed seed: the same frame gives the same plane
  rng_ = 2463534242u;
  auto next = [this, count]() {
    rng_ ^= rng_ << 13;
    rng_ ^= rng_ >> 17;
    rng_ ^= rng_ << 5;
    return rng_ % count;
  };
  double best = 0.0;
  for (int it = 0; it < kRansacIterations; ++it) {
    const uint32_t i = next(), j = next(), k = next();
    if (i == j || j == k || i == k) continue;
    const Eigen::Vector3d a = near_[i].p.cast<double>();
    Eigen::Vector3d cand = (near_[j].p.cast<double>() - a).cross(near_[k].p.cast<double>() - a);
    const double len = cand.norm();
    if (!(len > 1e-9)) continue;
    cand /= len;
    double cd = -cand.dot(a);
    if (!orient(cand, cd) || !plausible(cand, cd, s)) continue;
    // the road is what everything stands on: depth well below a hypothesis (the road beside
    // the cars a plane through their bodies lies on) counts against it
    double below = 0.0;
    const double sc = score(cand, cd, s, &below) - kBelowWeight * below;
    if (sc > best) {
      best = sc;
      n = cand;
      d = cd;
      if (best >= kEarlyExit * total) break;
    }
  }
  return best > 0.0;
}

bool RoadSurface::refine(const RoadSurfaceSettings& s, double first_band, Eigen::Vector3d& n,
                         double& d) {
  double factor = first_band;
  for (int it = 0; it < kRefineIterations; ++it) {
    // weighted moments in one pass: the mean and the scatter about it (relative to the first
    // sample, so that the subtraction loses nothing at road distances)
    const Eigen::Vector3d origin = near_.front().p.cast<double>();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    double wsum = 0.0;
    for (const Sample& smp : near_) {
      const Eigen::Vector3d p = smp.p.cast<double>();
      // with the mount's plane to start from, the road is what everything else stands on:
      // kerbs, pavements, vehicles and verges lie above it, nothing but noise below; above it
      // the band is narrower
      const double r = n.dot(p) + d;
      const double above = s.mount_height > 0.0 ? kAboveBand : 1.0;
      const double w =
          smp.weight * tukeyWeight(r, (r > 0.0 ? above : 1.0) * factor * bandAt(s, p.z()));
      if (w <= 0.0) continue;
      const Eigen::Vector3d q = p - origin;
      sum += w * q;
      scatter.noalias() += w * q * q.transpose();
      wsum += w;
    }
    if (!(wsum > 0.0)) return false;
    const Eigen::Vector3d mean_q = sum / wsum;
    const Eigen::Matrix3d C = scatter - wsum * mean_q * mean_q.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
    const Eigen::Vector3d ev = es.eigenvalues();
    if (!(ev[1] > 1e-9 * std::max(ev[2], 1e-12))) return false;  // degenerate (one line)
    Eigen::Vector3d cand = es.eigenvectors().col(0);
    double cd = -cand.dot(origin + mean_q);
    if (!orient(cand, cd)) return false;
    const bool converged = (cand - n).norm() < 1e-7 && std::fabs(cd - d) < 1e-7;
    n = cand;
    d = cd;
    if (converged && factor <= 1.0) break;
    factor = std::max(1.0, 0.5 * factor);
  }
  return plausible(n, d, s);
}

void RoadSurface::measureValidRange(const RoadSurfaceSettings& s, const Eigen::Vector3d& n,
                                    double d) {
  // The road surface beyond fit_range: per 5 m bin, the most frequent residual of the corridor's
  // samples (a car's rear spreads over its height, the road concentrates at its own). The plane
  // holds up to the first bin whose road leaves it, or whose road cannot be told (no sharp mode:
  // depth too noisy there).
  double near_end = near_end_;
  for (const Sample& smp : near_) near_end = std::max(near_end, static_cast<double>(smp.p.z()));
  valid_range_ = near_end >= 0.8 * s.fit_range ? s.fit_range : near_end;
  const Eigen::Vector3f nf = n.cast<float>();
  const float df = static_cast<float>(d);
  // one pass over the far samples: each corridor sample into its bin's residual histogram
  const int num_bins = std::max(0, std::min(kMaxRangeBins, static_cast<int>(std::ceil(
                                                               (s.max_range - s.fit_range) / kBinLength))));
  const float bin = 2.0f * kHistogramRange / kHistogramBins;
  int hist[kMaxRangeBins][kHistogramBins] = {};
  int counts[kMaxRangeBins] = {};
  for (const Sample& smp : far_) {
    if (smp.weight < kCorridorWeight || !(smp.p.z() > s.fit_range)) continue;
    const int k = static_cast<int>(std::ceil((smp.p.z() - s.fit_range) / kBinLength)) - 1;
    if (k < 0 || k >= num_bins) continue;
    const float r = nf.dot(smp.p) + df;
    if (std::fabs(r) >= kHistogramRange) continue;
    const int b = static_cast<int>((r + kHistogramRange) / bin);
    ++hist[k][std::min(std::max(b, 0), kHistogramBins - 1)];
    ++counts[k];
  }
  for (int k = 0; k < num_bins; ++k) {
    const int count = counts[k];
    if (count < kMinBinSamples) continue;  // nothing seen there (occluded, no depth): unknown
    int peak = 0, peak_count = -1;
    for (int b = 0; b < kHistogramBins; ++b) {
      int c = 0;
      for (int j = std::max(0, b - kModeHalfWidth); j <= std::min(kHistogramBins - 1, b + kModeHalfWidth); ++j)
        c += hist[k][j];
      if (c > peak_count) {
        peak_count = c;
        peak = b;
      }
    }
    const double mode = (peak + 0.5) * bin - kHistogramRange;
    if (peak_count < kSharpMode * count) break;            // no clear road surface
    if (std::fabs(mode) > kLeavesPlane + bin) break;       // the road left the plane
    valid_range_ = s.fit_range + (k + 1) * kBinLength;
  }
}

bool RoadSurface::fit(const cv::Mat& points, const cv::Range& rows,
                      const RoadSurfaceSettings& s, const PlaneEstimate& previous,
                      PlaneEstimate& plane) {
  plane.valid = false;
  plane.support.clear();
  plane.rms = 0.0;
  valid_range_ = 0.0;
  inliers_ = 0;
  if (points.empty() || points.type() != CV_32FC3) return false;
  collect(points, rows, s);
  if (static_cast<int>(near_.size()) < kMinSamples) return false;

  Eigen::Vector3d n;
  double d = 0.0;
  bool ok = false;
  growth_ = s.noise_growth;  // the sensor's worst case until the data tell
  double total = 0.0;
  for (const Sample& smp : near_) total += smp.weight;
  // the vehicle knows where the road is: the plane of its mount, refitted within the band alone
  // (a road seen mostly as paint, beside kerbs, pavements and passing cars, has more depth off
  // it than on it: a wide band lets those pull the plane, and from frame to frame it drifts)
  if (s.mount_height > 0.0 && plausible(s.up, s.mount_height, s)) {
    n = s.up;
    d = s.mount_height;
    estimateNoise(s, n, d);  // the band from the depth below the mount's plane
    ok = refine(s, kMountBand, n, d) && score(n, d, s) >= kMinInlierShare * total;
    if (!ok) growth_ = s.noise_growth;
  }
  if (!ok && previous.valid && plausible(previous.normal, previous.distance, s)) {
    n = previous.normal;
    d = previous.distance;
    ok = refine(s, kPreviousBand, n, d) && score(n, d, s) >= kMinInlierShare * total;
  }
  if (!ok) ok = ransac(s, n, d) && refine(s, kRansacBand, n, d);
  if (!ok || score(n, d, s) < kMinInlierShare * total) return false;
  // the band from the depth's own noise, then a last refit with it
  estimateNoise(s, n, d);
  const Eigen::Vector3d n0 = n;
  const double d0 = d;
  if (!refine(s, 1.0, n, d) || score(n, d, s) < kMinInlierShare * total) {
    n = n0;
    d = d0;
  }

  // support: a spread subsample of the inliers; rms of all inliers
  double sq = 0.0;
  int count = 0;
  for (const Sample& smp : near_) {
    const double r = n.dot(smp.p.cast<double>()) + d;
    if (std::fabs(r) <= bandAt(s, smp.p.z())) {
      sq += r * r;
      ++count;
    }
  }
  const size_t step = std::max<size_t>(1, static_cast<size_t>(count) / kMaxSupport + 1);
  int k = 0;
  for (const Sample& smp : near_) {
    const double r = n.dot(smp.p.cast<double>()) + d;
    if (std::fabs(r) > bandAt(s, smp.p.z())) continue;
    if (k++ % step == 0) plane.support.push_back(smp.p);
  }
  inliers_ = count;
  if (count < kMinSamples) return false;
  plane.valid = true;
  plane.normal = n;
  plane.distance = d;
  plane.rms = std::sqrt(sq / count);
  plane.fit_method = 2;
  measureValidRange(s, n, d);
  plane.range = valid_range_;
  return true;
}

}  // namespace rgbd_lane_detector
