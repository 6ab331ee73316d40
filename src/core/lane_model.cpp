// The lane model's filter: the observations reduced to stations in the vehicle frame, their
// association with the model's boundaries, the Kalman prediction and updates, lane changes. What
// is remembered of each boundary and the published model: lane_model_evidence.cpp.
#include "rgbd_lane_detector/lane_model.h"

#include <algorithm>
#include <cmath>

namespace rgbd_lane_detector {
namespace {

constexpr double kNominalWidth = 3.5;   // m: width of a lane whose other side was never seen
constexpr double kMinForward = 0.5;     // m: nearer points are not used
constexpr double kQuadraticRange = 12.0;  // m of x-range before a side's curvature is fitted
constexpr int kN = 7;                   // state size
// Process noise per update (the lane moves relative to the vehicle): y0, slope, kappa, kappa',
// w, vy (a lane change accelerates sideways by up to ~0.02 m per frame per frame at 10 fps),
// omega (its heading rate changes by up to ~2 mrad per frame per frame).
constexpr double kQ[kN] = {0.01 * 0.01, 0.002 * 0.002, 1e-4 * 1e-4, 1e-5 * 1e-5,
                           0.02 * 0.02, 0.02 * 0.02,  0.002 * 0.002};
// Initial standard deviations of a fresh model.
constexpr double kP0[kN] = {0.2, 0.03, 2e-3, 1e-4, 0.3, 0.1, 0.01};
constexpr double kMaxSideways = 0.5;    // m per update: |vy| (a lane change at 10 fps: ~0.2)
constexpr double kMaxSlopeRate = 0.03;  // per update: |omega| (a lane change: ~0.01)
constexpr double kStationGate = 3.0;    // sigmas: a station further from the model is skipped
constexpr double kHuber = 1.5;          // sigmas: a station beyond weighs less (Huber)
constexpr int kDisagreeFrames = 3;      // frames the model takes none of the ego lane seen
constexpr double kSlopeRateMemory = 0.8;  // omega's persistence per update (a turn relative to
                                          // the lane ends: the vehicle follows its lane)
constexpr double kResidualToStd = 1.25; // standard deviation / mean absolute residual
constexpr double kNextMin = 1.5;        // m: an outer line at least this far beyond its ego side
constexpr double kNextMax = 6.0;        // m: ... and at most this far

// Least-squares y = a + b x (+ c x^2 when the range allows) through a track's samples.
bool fitSide(const Eigen::Vector2d* xy, int n, double range, double& a, double& b, double& c) {
  if (n < 2) return false;
  const bool quadratic = range >= kQuadraticRange && n >= 4;
  Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d phi(1.0, xy[i].x(), quadratic ? xy[i].x() * xy[i].x() : 0.0);
    N.noalias() += phi * phi.transpose();
    r += phi * xy[i].y();
  }
  if (!quadratic) N(2, 2) = 1.0;
  const Eigen::Vector3d s = N.ldlt().solve(r);
  if (!s.allFinite()) return false;
  a = s[0];
  b = s[1];
  c = quadratic ? s[2] : 0.0;
  return true;
}

}  // namespace

LaneModelFilter::LaneModelFilter() {
  scratch_.reserve(kMaxPoints);
  reset();
}

void LaneModelFilter::reset() {
  x_.setZero();
  x_[4] = kNominalWidth;
  P_.setZero();
  for (int i = 0; i < kN; ++i) P_(i, i) = kP0[i] * kP0[i];
  initialised_ = false;
  lost_ = 0;
  disagree_ = 0;
  lane_changes_ = 0;
  for (auto& m : memory_) m = Memory();
}

void LaneModelFilter::predict(const Eigen::Isometry3d& motion) {
  if (!initialised_) return;
  // the vehicle moved by (dx, dy) and turned by dpsi: the lane as seen from the new pose
  const double dx = motion.translation().x(), dy = motion.translation().y();
  const double dpsi = std::atan2(motion.linear()(1, 0), motion.linear()(0, 0));
  const double y0 = x_[0], t = x_[1], k = x_[2], kr = x_[3];
  Cov F = Cov::Identity();
  F(0, 1) = dx;
  F(0, 2) = 0.5 * dx * dx;
  F(0, 3) = dx * dx * dx / 6.0;
  F(1, 2) = dx;
  F(1, 3) = 0.5 * dx * dx;
  F(2, 3) = dx;
  x_[0] = y0 + t * dx + 0.5 * k * dx * dx + kr * dx * dx * dx / 6.0 - dy;
  x_[1] = t + k * dx + 0.5 * kr * dx * dx - dpsi;
  x_[2] = k + kr * dx;
  P_ = F * P_ * F.transpose();
  for (Memory& m : memory_)
    for (int i = 0; i < m.num_extents; ++i) {
      Eigen::Vector2d& e = m.extents[i];
      e[0] = std::max(0.0, e[0] - dx);
      e[1] = std::max(e[0], e[1] - dx);
    }
}

double LaneModelFilter::predicted(int p, double x) const {
  const double centre = x_[0] + x * (x_[1] + x * (0.5 * x_[2] + x * x_[3] / 6.0));
  const double half = 0.5 * x_[4];
  const double side = isLeft(p) ? 1.0 : -1.0;
  if (isEgo(p)) return centre + side * half;
  const double beyond = known(p) ? memory_[p].beyond : x_[4];
  return centre + side * (half + beyond);
}

double LaneModelFilter::lateralVariance(int p, double x) const {
  const Row H = measurementRow(isEgo(p) ? p : egoOf(p), x);
  double var = (H * P_ * H.transpose())(0, 0);
  if (!isEgo(p)) var += memory_[p].beyond_var;
  return std::max(0.0, var);
}

LaneModelFilter::Row LaneModelFilter::measurementRow(int p, double x) const {
  Row H;
  H << 1.0, x, 0.5 * x * x, x * x * x / 6.0, isLeft(p) ? 0.5 : -0.5, 0.0, 0.0;
  return H;
}

double LaneModelFilter::boundaryScatter(int p) const {
  // a line found in a different place from frame to frame (a kerb's face or its top, one line
  // of a double line or the other) weighs less: its recent mean residual, as a standard
  // deviation (|r| averages 0.8 sigma)
  if (!known(p)) return 0.0;
  const double s = kResidualToStd * memory_[p].residual;
  return s * s;
}

double LaneModelFilter::measurementVariance(double x) const {
  // a pixel's lateral extent on the road grows with x: linear in x, measurement_std at 10 m
  const double s = settings_.measurement_std * (x + 2.0) / 12.0;
  return s * s;
}

bool LaneModelFilter::project(const Eigen::Isometry3d& T, const BoundaryObservation& o,
                              Track& t) {
  t.n = 0;
  t.obs = &o;
  t.assigned = -1;
  if (o.points == nullptr) return false;
  // the usable points in the vehicle frame (x >= kMinForward > 0), sorted by x (evenly thinned
  // beyond kMaxPoints)
  const std::vector<Eigen::Vector3f>& pts = *o.points;
  const size_t stride = pts.size() / kMaxPoints + 1;
  scratch_.clear();
  for (size_t i = 0; i < pts.size(); i += stride) {
    if (!pts[i].allFinite()) continue;
    const Eigen::Vector3d q = T * pts[i].cast<double>();
    if (q.x() < kMinForward || q.x() > settings_.x_max) continue;
    scratch_.emplace_back(q.x(), q.y());
  }
  if (scratch_.size() < 2) return false;
  std::sort(scratch_.begin(), scratch_.end(),
            [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() < b.x(); });
  t.x_min = scratch_.front().x();
  t.x_max = scratch_.back().x();
  // one station per stretch of log x (as the camera sees the road: a pixel's lateral extent
  // grows with x): its point of median y (a point of the line itself, near the middle of the
  // stretch where the line is monotonic over it; a few stray points do not move it)
  const double ratio = std::pow(t.x_max / t.x_min, 1.0 / kStations);
  auto first = scratch_.begin();
  double end = t.x_min;
  for (int s = 0; s < kStations && first != scratch_.end(); ++s) {
    end *= ratio;
    auto last = s + 1 == kStations ? scratch_.end()
                                   : std::find_if(first, scratch_.end(),
                                                  [end](const Eigen::Vector2d& q) { return q.x() >= end; });
    if (last == first) continue;
    const auto mid = first + (last - first) / 2;
    std::nth_element(first, mid, last, [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
      return a.y() < b.y();
    });
    t.xy[t.n++] = *mid;
    first = last;
  }
  trimStations(t);
  return t.n >= 2;
}

void LaneModelFilter::trimStations(Track& t) const {
  // A station off the curve through the others (a cluster of stray points the trace picked up)
  // is dropped: of the lines (quadratics over a long range) through every two (three) stations,
  // the one with the most stations within kStationGate sigmas, then the least spread, keeps
  // those.
  if (t.n < 3) return;
  const bool quadratic = t.xy[t.n - 1].x() - t.xy[0].x() >= kQuadraticRange && t.n >= 4;
  double sigma[kStations];
  for (int i = 0; i < t.n; ++i) sigma[i] = std::sqrt(measurementVariance(t.xy[i].x()));
  int best_count = 0;
  double best_cost = 0.0;
  Eigen::Vector3d best(0.0, 0.0, 0.0);
  auto consider = [&](const Eigen::Vector3d& c) {
    int count = 0;
    double cost = 0.0;
    for (int i = 0; i < t.n; ++i) {
      const double x = t.xy[i].x();
      const double r = std::fabs(t.xy[i].y() - (c[0] + x * (c[1] + x * c[2]))) / sigma[i];
      count += r <= kStationGate;
      cost += std::min(r, kStationGate) * std::min(r, kStationGate);
    }
    if (count > best_count || (count == best_count && cost < best_cost)) {
      best_count = count;
      best_cost = cost;
      best = c;
    }
  };
  for (int i = 0; i < t.n; ++i)
    for (int j = i + 1; j < t.n; ++j) {
      const Eigen::Vector2d& a = t.xy[i];
      const Eigen::Vector2d& b = t.xy[j];
      if (!quadratic) {
        const double slope = (b.y() - a.y()) / (b.x() - a.x());
        consider(Eigen::Vector3d(a.y() - slope * a.x(), slope, 0.0));
        continue;
      }
      for (int k = j + 1; k < t.n; ++k) {
        const Eigen::Vector2d& q = t.xy[k];
        Eigen::Matrix3d V;
        V << 1.0, a.x(), a.x() * a.x(), 1.0, b.x(), b.x() * b.x(), 1.0, q.x(), q.x() * q.x();
        const Eigen::Vector3d c = V.partialPivLu().solve(Eigen::Vector3d(a.y(), b.y(), q.y()));
        if (c.allFinite()) consider(c);
      }
    }
  if (best_count < 2 || best_count == t.n) return;
  const double x_first = t.xy[0].x(), x_last = t.xy[t.n - 1].x();
  int kept = 0;
  for (int i = 0; i < t.n; ++i) {
    const double x = t.xy[i].x();
    if (std::fabs(t.xy[i].y() - (best[0] + x * (best[1] + x * best[2]))) <= kStationGate * sigma[i])
      t.xy[kept++] = t.xy[i];
  }
  t.n = kept;
  // the range shrinks to the stations when an end station went
  if (t.xy[0].x() != x_first) t.x_min = t.xy[0].x();
  if (t.xy[t.n - 1].x() != x_last) t.x_max = t.xy[t.n - 1].x();
}

void LaneModelFilter::initialiseFromEgo(int count) {
  const Track *left = nullptr, *right = nullptr;
  for (int k = 0; k < count; ++k) {
    const Track& t = tracks_[k];
    if (t.n < 2 || !t.obs->ego) continue;
    (t.obs->left ? left : right) = &t;
  }
  if (left || right) initialise(left, right);
}

void LaneModelFilter::initialise(const Track* left, const Track* right) {
  reset();
  double a[2] = {0, 0}, b[2] = {0, 0}, c[2] = {0, 0};
  bool have[2] = {false, false};
  const Track* sides[2] = {left, right};
  for (int i = 0; i < 2; ++i)
    if (sides[i]) have[i] = fitSide(sides[i]->xy.data(), sides[i]->n,
                                    sides[i]->x_max - sides[i]->x_min, a[i], b[i], c[i]);
  if (have[0] && have[1]) {
    const double w = a[0] - a[1];
    if (w >= settings_.width_min && w <= settings_.width_max) {
      x_ << 0.5 * (a[0] + a[1]), 0.5 * (b[0] + b[1]), c[0] + c[1], 0.0, w, 0.0, 0.0;
      P_(4, 4) = 0.1 * 0.1;
      initialised_ = true;
      return;
    }
    // not one lane: keep the more trusted side
    const int keep = left->obs->confidence >= right->obs->confidence ? 0 : 1;
    have[1 - keep] = false;
  }
  for (int i = 0; i < 2; ++i) {
    if (!have[i]) continue;
    const double half = 0.5 * kNominalWidth;
    x_ << a[i] + (i == 0 ? -half : half), b[i], 2.0 * c[i], 0.0, kNominalWidth, 0.0, 0.0;
    P_(4, 4) = 1.0;
    initialised_ = true;
    return;
  }
}

void LaneModelFilter::associate(int count) {
  // Every (observation, position) pair within the gate, nearest first; each observation and
  // each position at most once.
  struct Pair {
    double d;
    int track, position;
  };
  std::array<Pair, 8 * kNumBoundaryPositions> pairs;
  int n = 0;
  for (int k = 0; k < count; ++k) {
    const Track& t = tracks_[k];
    if (t.n < 2) continue;
    const bool edge = t.obs->kind == BoundaryKind::kRoadEdge;
    for (int p = 0; p < kNumBoundaryPositions; ++p) {
      if (p >= 4 && !edge) continue;          // road edges are not paint
      if (p == 2 || p == 3) {
        if (edge) continue;                   // next lanes' lines are paint
      }
      if (!isEgo(p) && endsRoad(egoOf(p))) continue;  // nothing beyond the road's edge
      double sum = 0.0;
      for (int i = 0; i < t.n; ++i) sum += std::fabs(t.xy[i].y() - predicted(p, t.xy[i].x()));
      const double d = sum / t.n;
      const double xm = 0.5 * (t.x_min + t.x_max);
      const Row H = measurementRow(isEgo(p) ? p : egoOf(p), xm);
      double var = (H * P_ * H.transpose())(0, 0);
      if (!isEgo(p)) var += known(p) ? memory_[p].beyond_var : 1.0;
      double gate = settings_.gate + 2.0 * std::sqrt(var);
      if (!isEgo(p) && !known(p)) {
        // a first sighting of an outer line: anywhere a lane beyond its ego side
        const double beyond = (isLeft(p) ? 1.0 : -1.0) * (t.xy[0].y() - predicted(egoOf(p), t.xy[0].x()));
        if (beyond < kNextMin || beyond > kNextMax) continue;
        gate = 1e9;
      }
      if (d <= gate && n < static_cast<int>(pairs.size())) pairs[n++] = Pair{d, k, p};
    }
  }
  std::sort(pairs.begin(), pairs.begin() + n, [](const Pair& a, const Pair& b) { return a.d < b.d; });
  bool used[kNumBoundaryPositions] = {false, false, false, false, false, false};
  for (int i = 0; i < n; ++i) {
    Track& t = tracks_[pairs[i].track];
    if (t.assigned >= 0 || used[pairs[i].position]) continue;
    t.assigned = pairs[i].position;
    used[pairs[i].position] = true;
  }
}

int LaneModelFilter::updateEgo(const Track& t, int p) {
  int used = 0;
  const double scatter = boundaryScatter(p);
  for (int i = 0; i < t.n; ++i) {
    const double x = t.xy[i].x();
    const Row H = measurementRow(p, x);
    double S = (H * P_ * H.transpose())(0, 0) + measurementVariance(x) + scatter;
    const double innovation = t.xy[i].y() - (H * x_)(0, 0);
    const double r = std::fabs(innovation) / std::sqrt(S);
    if (r > kStationGate) continue;
    if (r > kHuber) S *= r / kHuber;  // a station far out pulls no harder than one at kHuber
    const State K = P_ * H.transpose() / S;
    x_ += K * innovation;
    P_ -= K * S * K.transpose();
    ++used;
  }
  P_ = 0.5 * (P_ + P_.transpose());
  x_[4] = std::min(std::max(x_[4], settings_.width_min), settings_.width_max);
  x_[5] = std::min(std::max(x_[5], -kMaxSideways), kMaxSideways);
  x_[6] = std::min(std::max(x_[6], -kMaxSlopeRate), kMaxSlopeRate);
  return used;
}

void LaneModelFilter::updateOuter(const Track& t, int p) {
  // distance beyond the ego side, averaged over the stations, into a 1D filter
  double sum = 0.0;
  const double side = isLeft(p) ? 1.0 : -1.0;
  for (int i = 0; i < t.n; ++i) sum += side * (t.xy[i].y() - predicted(egoOf(p), t.xy[i].x()));
  const double z = sum / t.n;
  Memory& m = memory_[p];
  const double r = measurementVariance(0.5 * (t.x_min + t.x_max)) + boundaryScatter(p);
  if (!known(p)) {
    m.beyond = z;
    m.beyond_var = r + 0.05;
  } else {
    const double g = m.beyond_var / (m.beyond_var + r);
    m.beyond += g * (z - m.beyond);
    m.beyond_var = (1.0 - g) * m.beyond_var;
  }
}

void LaneModelFilter::relabel(int direction) {
  // direction +1: the vehicle is now in the lane left of the old ego lane. The old left line is
  // the new right one; the old next-left line (if seen) the new left one.
  const int L = direction > 0 ? 0 : 1;     // the ego side the vehicle crossed
  const int R = 1 - L;                     // the other ego side
  const int next = direction > 0 ? 2 : 3;  // the next line on the crossed side
  const int far = 1 - L + 2;               // the next line on the other side
  const int edge_near = direction > 0 ? 4 : 5, edge_far = direction > 0 ? 5 : 4;
  const double side = direction > 0 ? 1.0 : -1.0;
  const double old_w = x_[4];
  const bool know_next = known(next);
  const double new_w = know_next ? std::min(std::max(memory_[next].beyond, settings_.width_min),
                                            settings_.width_max)
                                 : old_w;
  x_[0] += side * 0.5 * (old_w + new_w);
  x_[4] = new_w;
  if (know_next) P_(4, 4) = memory_[next].beyond_var + 0.01;
  Memory crossed = memory_[L], other = memory_[R], next_m = memory_[next];
  memory_[R] = crossed;  // the crossed line is now the ego line on the other side
  memory_[L] = know_next ? next_m : Memory();
  memory_[far] = other;  // the old far ego line is one lane beyond the new ego line
  memory_[far].beyond = old_w;
  memory_[far].beyond_var = P_(4, 4);
  memory_[next] = Memory();
  memory_[edge_near].beyond -= new_w;
  if (memory_[edge_near].beyond < kNextMin * 0.5) memory_[edge_near] = Memory();
  memory_[edge_far].beyond += old_w;
  lane_changes_ += direction;
}

void LaneModelFilter::update(const Eigen::Isometry3d& vehicle_from_camera,
                             const BoundaryObservation* observations, int count, LaneModelEstimate& model) {
  count = std::min(count, static_cast<int>(tracks_.size()));
  for (int k = 0; k < count; ++k) project(vehicle_from_camera, observations[k], tracks_[k]);
  for (Memory& m : memory_) m.age = std::min(m.age + 1, 1000);

  if (!initialised_) {
    initialiseFromEgo(count);
  } else {
    // the lane keeps moving sideways at vy and turning at omega (which fades)
    Cov F = Cov::Identity();
    F(0, 5) = 1.0;
    F(1, 6) = 1.0;
    F(6, 6) = kSlopeRateMemory;
    x_[0] += x_[5];
    x_[1] += x_[6];
    x_[6] *= kSlopeRateMemory;
    P_ = F * P_ * F.transpose();
    for (int i = 0; i < kN; ++i) P_(i, i) += kQ[i];
  }
  if (initialised_) {
    // the vehicle left the ego lane (the model says so): relabel before associating
    if (x_[0] - 0.5 * x_[4] > 0.0) relabel(-1);
    else if (x_[0] + 0.5 * x_[4] < 0.0) relabel(+1);
    associate(count);
    bool ego_seen = false, ego_used = false;
    for (int p = 0; p < 2; ++p)
      for (int k = 0; k < count; ++k)
        if (tracks_[k].assigned == p) {
          ego_used = updateEgo(tracks_[k], p) > 0 || ego_used;
          ego_seen = true;
        }
    // The detector sees its ego lane, and for kDisagreeFrames frames in a row the model took
    // none of it (a wrong start, a jump the model could not follow): start over from this frame.
    bool ego_observed = false;
    for (int k = 0; k < count; ++k) ego_observed = ego_observed || (tracks_[k].n >= 2 && tracks_[k].obs->ego);
    disagree_ = ego_observed && !ego_used ? disagree_ + 1 : 0;
    if (disagree_ >= kDisagreeFrames) {
      const int changes = lane_changes_;
      initialiseFromEgo(count);
      lane_changes_ = changes;
      fill(model);
      return;
    }
    for (int k = 0; k < count; ++k) {
      const Track& t = tracks_[k];
      if (t.assigned < 0) continue;
      if (!isEgo(t.assigned)) updateOuter(t, t.assigned);
      double sum = 0.0;
      for (int i = 0; i < t.n; ++i) sum += std::fabs(t.xy[i].y() - predicted(t.assigned, t.xy[i].x()));
      remember(t, t.assigned, sum / t.n);
    }
    lost_ = ego_seen ? 0 : lost_ + 1;
    if (lost_ > settings_.lost_frames) reset();
  }
  fill(model);
}

}  // namespace rgbd_lane_detector
