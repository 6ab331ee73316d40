#include "rgbd_lane_detector/lane_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>
#include <Eigen/Geometry>

namespace rgbd_lane_detector {
namespace {

constexpr double kForwardScale = 20.0;  // m; keeps the normal equations well conditioned
// Ridge on each side's curvature term: a short, straight stretch of evidence must not yield a
// strongly curved model when extrapolated.
constexpr double kCurvatureRidge = 0.25;
// Weight of the prior that both sides have the same heading and curvature (in the normal
// equations' scaled units, against the sums of a side's weighted evidence): a side whose own
// points span a few metres takes its shape from the other side; two sides seen over tens of
// metres keep their own, shrunk toward each other by a few per cent.
constexpr double kParallelPrior = 1.0;
// A side whose evidence is this many frames old may be replaced at once by measurements that
// disagree with it (lane change, or a track that was wrong).
constexpr int kStaleAge = 3;
// Measurements nearer than this (m) get full weight; farther ones 1/f^2 (a pixel's lateral
// extent grows with the distance).
constexpr double kNearRange = 10.0;
// Bounds of the reported points per side.
constexpr int kMinSamples = 10;
constexpr int kMaxSamples = 40;
// A side's reported range is at least this long (m): shorter evidence is no lane boundary.
constexpr double kMinLength = 2.0;
// Sideways speed of the lane: gain of each frame's measured shift, decay without one.
constexpr double kDriftGain = 0.5;
constexpr double kDriftDecay = 0.9;
// Turning of the lane relative to the camera (the vehicle's yaw: a lane change, a swerve): a
// side's residuals measure it as their slope over the forward distance when its points span at
// least kTurnSpan metres (a solid line, or two dashes of a 12 m dash period: a slope over a few
// metres is noise); a turn above kMaxTurn per frame (2.9 deg) is no vehicle's. Both sides must
// measure it and agree within kTurnAgree: the vehicle's yaw turns both alike, while one side's
// slope alone can be its own shape (a kerb leaving the lane, a trace pulled off the line). Like
// the drift, the turn rate has a gain and a decay.
constexpr double kTurnSpan = 12.0;
constexpr double kMaxTurn = 0.05;
constexpr double kTurnAgree = 0.01;
constexpr double kTurnGain = 0.5;
constexpr double kTurnDecay = 0.9;

}  // namespace

bool fitRobustLine(const std::vector<Eigen::Vector2d>& points, double gate, double& a, double& b) {
  // in scaled forward units: the normal equations stay well conditioned
  Eigen::Vector2d line(0.0, 0.0);
  bool have = false;
  for (int it = 0; it < 3; ++it) {
    Eigen::Matrix2d N = Eigen::Matrix2d::Zero();
    Eigen::Vector2d r = Eigen::Vector2d::Zero();
    for (const auto& q : points) {
      const double s = q.x() / kForwardScale;
      if (have && std::fabs(q.y() - (line[0] + line[1] * s)) > gate) continue;
      const Eigen::Vector2d phi(1.0, s);
      N.noalias() += phi * phi.transpose();
      r += phi * q.y();
    }
    if (N.determinant() < 1e-9) break;
    line = N.ldlt().solve(r);
    have = true;
  }
  a = line[0];
  b = line[1] / kForwardScale;
  return have;
}

double LaneTracker::Side::nearest() const {
  double v = std::numeric_limits<double>::infinity();
  for (int i = 0; i < num_extents; ++i) v = std::min(v, extents[i].x());
  return v;
}

double LaneTracker::Side::farthest() const {
  double v = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < num_extents; ++i) v = std::max(v, extents[i].y());
  return v;
}

void LaneTracker::reset() {
  drift_ = 0.0;
  turn_ = 0.0;
  for (int i = 0; i < 2; ++i) {
    A_[i].setZero();
    b_[i].setZero();
  }
  coef_.setZero();
  for (auto& s : sides_) s = Side();
}

void LaneTracker::handOver(int from) {
  // The sums live in (a_l, a_r, b_l, b_r, c_l, c_r): side `from`'s evidence moves to the other
  // side's terms.
  const int to = 1 - from;
  Eigen::PermutationMatrix<6> P;
  P.setIdentity();
  P.applyTranspositionOnTheRight(0, 1);
  P.applyTranspositionOnTheRight(2, 3);
  P.applyTranspositionOnTheRight(4, 5);
  A_[to] = P * A_[from] * P.transpose();
  b_[to] = P * b_[from];
  sides_[to] = sides_[from];
  A_[from].setZero();
  b_[from].setZero();
  sides_[from] = Side();
  solve();
}

void LaneTracker::resetSide(int i) {
  A_[i].setZero();
  b_[i].setZero();
  sides_[i] = Side();
  coef_[i] = 0.0;
  if (sides_[1 - i].valid) solve();
  else coef_.setZero();
}

LaneTracker::Vec6 LaneTracker::basis(int side, double f) {
  const double s = f / kForwardScale;
  Vec6 v = Vec6::Zero();
  v[side] = 1.0;
  v[2 + side] = s;
  v[4 + side] = s * s;
  return v;
}

double LaneTracker::lateral(int i, double f) const { return coef_.dot(basis(i, f)); }

void LaneTracker::shift(double delta) {
  // the data moved sideways by delta: b = sum w phi l -> b + delta sum w phi, and for side i
  // sum w phi = A_i e_i (the intercept entries of phi are the side indicators)
  for (int i = 0; i < 2; ++i) b_[i] += delta * A_[i].col(i);
  coef_[0] += delta;
  coef_[1] += delta;
}

void LaneTracker::rotate(double angle) {
  // the data turned by angle about the camera: y -> y + angle f (f = kForwardScale s), so
  // b = sum w phi y -> b + angle kForwardScale sum w phi s, and for side i sum w phi s = A_i e_(2+i)
  for (int i = 0; i < 2; ++i) b_[i] += angle * kForwardScale * A_[i].col(2 + i);
  coef_[2] += angle * kForwardScale;
  coef_[3] += angle * kForwardScale;
}

bool LaneTracker::measureTurn(int i, double gate, double& turn) {
  // the slope of the side's residuals over the forward distance, from points that span enough
  residual_points_.clear();
  double near = std::numeric_limits<double>::infinity(), far = -near;
  for (const auto& q : measurements_[i]) {
    const double r = q.y() - lateral(i, q.x());
    if (std::fabs(r) > gate) continue;
    residual_points_.emplace_back(q.x(), r);
    near = std::min(near, q.x());
    far = std::max(far, q.x());
  }
  if (!(far - near >= kTurnSpan)) return false;
  double a = 0.0;
  if (!fitRobustLine(residual_points_, 0.5 * gate, a, turn)) return false;
  return std::fabs(turn) <= kMaxTurn;
}

void LaneTracker::solve() {
  Mat6 M = A_[0] + A_[1];
  for (int k = 0; k < 4; ++k) M(k, k) += 1e-9;
  M(4, 4) += kCurvatureRidge;
  M(5, 5) += kCurvatureRidge;
  // the soft parallel prior: kParallelPrior (b_l - b_r)^2 + kParallelPrior (c_l - c_r)^2
  for (int k : {2, 4}) {
    M(k, k) += kParallelPrior;
    M(k + 1, k + 1) += kParallelPrior;
    M(k, k + 1) -= kParallelPrior;
    M(k + 1, k) -= kParallelPrior;
  }
  coef_ = M.ldlt().solve(b_[0] + b_[1]);
  if (!coef_.allFinite()) reset();
}

void LaneTracker::update(const RoadFrame& frame, const std::vector<Eigen::Vector3f>& left,
                         const std::vector<Eigen::Vector3f>& right, const TrackerParams& params) {
  const std::vector<Eigen::Vector3f>* points[2] = {&left, &right};
  for (int i = 0; i < 2; ++i) {
    measurements_[i].clear();
    if (!frame.valid()) continue;
    for (const auto& p : *points[i])
      if (p.allFinite()) measurements_[i].push_back(frame.toRoad(p.cast<double>()));
  }
  auto enough = [&](int i) { return static_cast<int>(measurements_[i].size()) >= params.min_points; };

  // the lane keeps moving sideways as it did (a lane change, a drift): predict that first, so
  // that a side without evidence follows it and the gate below looks at the right place
  if (valid(0) || valid(1)) {
    shift(drift_);
    rotate(turn_);
  }

  // Gate per side; a stale side whose new evidence disagrees starts its model over.
  bool gate[2] = {false, false};
  for (int i = 0; i < 2; ++i) {
    if (!enough(i) || !established(i)) continue;
    int inliers = 0;
    for (const auto& q : measurements_[i]) inliers += std::fabs(q.y() - lateral(i, q.x())) <= params.gate;
    gate[i] = true;
    if (2 * inliers < static_cast<int>(measurements_[i].size()) && sides_[i].age >= kStaleAge) {
      resetSide(i);
      gate[i] = false;
    }
  }

  // A side without an established model is checked against itself: points off the robust line
  // through its own points (a trace that left the marker) are dropped.
  for (int i = 0; i < 2; ++i)
    if (enough(i) && !gate[i]) trimToLine(measurements_[i], params.gate);

  // Common turning of the lane relative to the camera since the last frame (the vehicle's yaw:
  // evidence of older frames lies at the old heading): the slope of the sides' disagreement with
  // the model, taken when both sides measure a plausible one and they agree.
  double side_turn[2];
  bool have_turn[2] = {false, false};
  for (int i = 0; i < 2; ++i)
    if (gate[i]) have_turn[i] = measureTurn(i, params.gate, side_turn[i]);
  if (have_turn[0] && have_turn[1] && std::fabs(side_turn[0] - side_turn[1]) <= kTurnAgree) {
    const double turned = 0.5 * (side_turn[0] + side_turn[1]);
    rotate(turned);
    turn_ += kTurnGain * turned;
  } else {
    turn_ *= kTurnDecay;
  }

  // Common sideways motion of the lane relative to the camera since the last frame: the median
  // disagreement of each observed side with the model, taken when it is a plausible motion (at
  // most the gate) and, with both sides observed, when they agree.
  double side_shift[2];
  bool have_shift[2] = {false, false};
  for (int i = 0; i < 2; ++i) {
    if (!gate[i]) continue;
    residuals_.clear();
    for (const auto& q : measurements_[i]) residuals_.push_back(q.y() - lateral(i, q.x()));
    // (the median; of an even count the lower one, the one nearer the right, as when the lateral
    // axis pointed right)
    const size_t mid = (residuals_.size() - 1) / 2;
    std::nth_element(residuals_.begin(), residuals_.begin() + mid, residuals_.end());
    side_shift[i] = residuals_[mid];
    have_shift[i] = std::fabs(side_shift[i]) <= params.gate;
  }
  double measured = 0.0;
  bool moved = false;
  if (have_shift[0] && have_shift[1]) {
    if (std::fabs(side_shift[0] - side_shift[1]) <= 0.5 * params.gate) {
      measured = 0.5 * (side_shift[0] + side_shift[1]);
      moved = true;
    }
  } else if (have_shift[0] || have_shift[1]) {
    measured = have_shift[0] ? side_shift[0] : side_shift[1];
    moved = true;
  }
  if (moved) {
    shift(measured);
    drift_ += kDriftGain * measured;  // the sideways speed, per frame (alpha-beta filter)
  } else {
    drift_ *= kDriftDecay;
  }

  for (int i = 0; i < 2; ++i) {
    A_[i] *= params.memory;
    b_[i] *= params.memory;
  }
  bool changed = false;
  for (int i = 0; i < 2; ++i) {
    Side& side = sides_[i];
    int accepted = 0;
    double near = std::numeric_limits<double>::infinity(), far = -near;
    if (enough(i)) {
      for (const auto& q : measurements_[i]) {
        if (gate[i] && std::fabs(q.y() - lateral(i, q.x())) > params.gate) continue;
        const double r = std::max(q.x(), kNearRange) / kNearRange;
        const double w = 1.0 / (r * r);
        const Vec6 phi = basis(i, q.x());
        A_[i].noalias() += w * phi * phi.transpose();
        b_[i].noalias() += w * phi * q.y();
        near = std::min(near, q.x());
        far = std::max(far, q.x());
        ++accepted;
      }
    }
    if (accepted >= params.min_points) {
      side.extents[side.next_extent] = Eigen::Vector2d(near, far);
      side.next_extent = (side.next_extent + 1) % static_cast<int>(side.extents.size());
      side.num_extents = std::min(side.num_extents + 1, static_cast<int>(side.extents.size()));
      side.age = 0;
      ++side.frames;
      side.valid = true;
      changed = true;
    } else if (side.valid && ++side.age > params.max_age) {
      resetSide(i);
    }
  }
  if (changed) solve();
}

void LaneTracker::trimToLine(std::vector<Eigen::Vector2d>& m, double gate) {
  double a = 0.0, b = 0.0;
  if (!fitRobustLine(m, gate, a, b)) return;
  m.erase(std::remove_if(m.begin(), m.end(),
                         [&](const Eigen::Vector2d& q) { return std::fabs(q.y() - (a + b * q.x())) > gate; }),
          m.end());
}

void LaneTracker::sample(int i, const RoadFrame& frame, double step,
                         std::vector<Eigen::Vector3f>& out, double beyond) const {
  out.clear();
  const Side& s = sides_[i];
  if (!s.valid || !frame.valid() || !(step > 0.0)) return;
  double near = s.nearest(), far = s.farthest();
  const Side& other = sides_[1 - i];
  if (other.valid) {
    // extend over the other side's range, but report a side only so far beyond its own evidence
    near = std::min(near, std::max(other.nearest(), near - beyond));
    far = std::max(far, std::min(other.farthest(), far + beyond));
  }
  near = std::max(near, 0.5);
  if (!(far >= near + kMinLength)) return;
  // Uniform in 1/f, i.e. about uniform in image rows like the traced centroids: the far range,
  // where a pixel spans decimetres, does not dominate the reported points.
  const int count = std::max(kMinSamples, static_cast<int>(std::ceil((far - near) / step)));
  const int n = std::min(count, kMaxSamples);
  const double a = 1.0 / near, b = 1.0 / far;
  for (int k = 0; k < n; ++k) {
    const double f = 1.0 / (a + (b - a) * k / (n - 1));
    out.push_back(frame.toCamera(f, lateral(i, f)).cast<float>());
  }
}

}  // namespace rgbd_lane_detector
