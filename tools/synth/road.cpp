#include "rgbd_lane_detector_tools/synth/road.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rgbd_lane_detector_tools/synth/noise.h"

namespace rgbd_lane_detector {
namespace synth {
namespace {

using tools::EdgeType;
using tools::LineColour;
using tools::LineStyle;

// Intersection layout along the road, relative to the crossing road's near edge (m).
constexpr double kStopLineFrom = -7.0;  // stop line (0.5 m) across the lanes of our direction
constexpr double kStopLineTo = -6.5;
constexpr double kZebraFrom = -5.5;  // zebra crossing: 4 m stripes parallel to the road
constexpr double kZebraTo = -1.5;
constexpr double kZebraStripe = 0.5;  // stripe and gap width across the road
constexpr double kArrowLength = 5.0;
constexpr double kArrowTips[] = {-15.0, -35.0};  // tips of the arrows before the stop line

LineStyle styleOf(MarkerKind kind) {
  switch (kind) {
    case MarkerKind::kSolid:
      return LineStyle::kSolid;
    case MarkerKind::kDashed:
      return LineStyle::kDashed;
    case MarkerKind::kDouble:
      return LineStyle::kDoubleSolid;
    case MarkerKind::kNone:
      break;
  }
  return LineStyle::kUnknown;
}

BoundaryDef roadEdge(double offset, EdgeType edge) {
  BoundaryDef b;
  b.offset = offset;
  b.present = true;
  b.kind = BoundaryKind::kRoadEdge;
  b.style = LineStyle::kRoadEdge;
  b.colour = LineColour::kNone;
  b.edge = edge;
  return b;
}

// Turn arrow in arrow coordinates: u along the road from the tail (0..kArrowLength), v lateral
// (positive right). variant 0 straight, 1 straight and right, 2 straight and left.
bool insideArrow(double u, double v, int variant) {
  if (u < 0.0 || u > kArrowLength) return false;
  if (u <= 3.5 && std::fabs(v) <= 0.09) return true;                        // shaft
  if (u >= 3.5 && std::fabs(v) <= 0.45 * (kArrowLength - u) / 1.5) return true;  // head
  if (variant == 0) return false;
  const double w = variant == 1 ? v : -v;  // toward the turn
  // branch: a bar from (2.0, 0) to (3.2, 0.5), 0.16 m wide, and a head pointing sideways
  const Eigen::Vector2d a(2.0, 0.0), b(3.2, 0.5), p(u, w);
  const double h = std::min(1.0, std::max(0.0, (p - a).dot(b - a) / (b - a).squaredNorm()));
  if ((p - (a + h * (b - a))).norm() <= 0.08) return true;
  return w >= 0.45 && w <= 1.0 && std::fabs(u - 3.25) <= 0.4 * (1.0 - w) / 0.55;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
VerticalProfile::VerticalProfile(const SceneSettings& s) {
  if (!(s.vertical_radius > 0.0)) return;
  const double R = s.vertical_radius, g = s.vertical_grade, L1 = s.vertical_tangent;
  const double k = 1.0 / R;
  // crest to grade -g, tangent, sag to +g, tangent, crest back to level, level
  double u = 0.0, h = 0.0, gr = 0.0;
  const auto add = [&](double length, double curvature) {
    cycle_.push_back({u, h, gr, curvature});
    h += gr * length + 0.5 * curvature * length * length;
    gr += curvature * length;
    u += length;
    min_height_ = std::min(min_height_, h);
  };
  add(g * R, -k);
  add(L1, 0.0);
  add(g * R, k);  // the sag's lowest point is the end of this piece
  add(g * R, k);
  add(L1, 0.0);
  add(g * R, -k);
  add(s.vertical_flat, 0.0);
  period_ = u;
  start_ = s.vertical_start;
  max_grade_ = g;
}

const VerticalProfile::Piece& VerticalProfile::piece(double s, double& u) const {
  u = std::fmod(s - start_, period_);
  if (u < 0) u += period_;
  size_t i = cycle_.size() - 1;
  while (i > 0 && cycle_[i].s0 > u) --i;
  u -= cycle_[i].s0;
  return cycle_[i];
}

double VerticalProfile::height(double s) const {
  if (cycle_.empty() || s < start_) return 0.0;
  double u;
  const Piece& p = piece(s, u);
  return p.h0 + p.g0 * u + 0.5 * p.k * u * u;
}

double VerticalProfile::grade(double s) const {
  if (cycle_.empty() || s < start_) return 0.0;
  double u;
  const Piece& p = piece(s, u);
  return p.g0 + p.k * u;
}

bool VerticalProfile::crossing(double s0, double ds, double y0, double dy, double offset,
                               double max_l, double& l) const {
  // walk the pieces the line passes, in its direction along s; in each, f(l) = y - surface is
  // a quadratic A l^2 + B l + C
  double lambda = 0.0;
  double s = s0;
  for (int guard = 0; guard < 10000 && lambda < max_l; ++guard) {
    // piece holding s (in the direction of travel) and its extent [a, b] in absolute s
    double a, b, ref = s0, h0 = 0.0, g0 = 0.0, k = 0.0;  // ref: the polynomial's origin
    if (flat() || s < start_) {
      a = -std::numeric_limits<double>::infinity();
      b = flat() ? std::numeric_limits<double>::infinity() : start_;
    } else {
      const double cycle = std::floor((s - start_) / period_);
      const double u = s - start_ - cycle * period_;
      size_t i = cycle_.size() - 1;
      while (i > 0 && cycle_[i].s0 > u) --i;
      // H = h0 + g0 (s - a) + k/2 (s - a)^2 on [a, b]
      a = start_ + cycle * period_ + cycle_[i].s0;
      b = start_ + cycle * period_ + (i + 1 < cycle_.size() ? cycle_[i + 1].s0 : period_);
      ref = a;
      h0 = cycle_[i].h0;
      g0 = cycle_[i].g0;
      k = cycle_[i].k;
    }
    // parameter range of the line inside [a, b]
    double l_end = max_l;
    if (ds > 1e-12) l_end = std::min(l_end, (b - s0) / ds);
    if (ds < -1e-12) l_end = std::min(l_end, (a - s0) / ds);
    const double u0 = s0 - ref;  // u(l) = u0 + l ds
    const double A = -0.5 * k * ds * ds;
    const double B = dy - g0 * ds - k * u0 * ds;
    const double C = y0 - offset - h0 - g0 * u0 - 0.5 * k * u0 * u0;
    // smallest root in (lambda, l_end]
    double roots[2];
    int n = 0;
    if (std::fabs(A) < 1e-15) {
      if (std::fabs(B) > 1e-15) roots[n++] = -C / B;
    } else {
      const double disc = B * B - 4.0 * A * C;
      if (disc >= 0.0) {
        const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
        roots[n++] = q / A;
        if (q != 0.0) roots[n++] = C / q;
        if (n == 2 && roots[1] < roots[0]) std::swap(roots[0], roots[1]);
      }
    }
    for (int i = 0; i < n; ++i) {
      if (roots[i] > lambda - 1e-9 && roots[i] > 0.0 && roots[i] <= l_end) {
        l = roots[i];
        return l < max_l;
      }
    }
    if (l_end >= max_l || std::fabs(ds) <= 1e-12) return false;
    lambda = l_end;
    // into the next piece (the quadratic of each piece is exact: s only selects the piece)
    s = (ds > 0 ? b : a) + std::copysign(1e-7, ds);
  }
  return false;
}

// ---------------------------------------------------------------------------------------------
RoadGeometry::RoadGeometry(const SceneSettings& s)
    : curvature_(s.curvature),
      radius_(std::fabs(s.curvature) > 1e-9 ? 1.0 / s.curvature : 0.0),
      lane_width_(s.lane_width),
      lanes_left_(s.lanes_left),
      lanes_right_(s.lanes_right),
      profile_(s) {
  if (radius_ == 0.0) curvature_ = 0.0;
  if (s.left_boundary == BoundaryType::kTramRails) {
    tram_gauge_ = s.tram_gauge;
    tram_head_ = s.tram_head_width;
    tram_groove_ = s.tram_groove_width;
    tram_spacing_ = s.tram_track_spacing;
    // two tracks, the nearest rail's centre on the lane boundary, 0.5 m clear beyond the last
    tram_zone_width_ = tram_spacing_ + tram_gauge_ + 1.5 * tram_head_ + 0.5;
  }
  if (s.intersection_period > 0) {
    intersection_period_ = s.intersection_period;
    intersection_start_ = s.intersection_start;
    crossing_width_ = s.crossing_width;
    turn_arrows_ = s.turn_arrows;
  }
  const double W = s.lane_width;
  left_edge_ = -0.5 * W - s.lanes_left * W - tram_zone_width_;
  right_edge_ = 0.5 * W + s.lanes_right * W;
  if (s.right_boundary == BoundaryType::kKerb) side_zone_height_ = s.kerb_height;
  if (s.right_boundary == BoundaryType::kAsphaltEdge) side_zone_height_ = -s.edge_drop;
  side_zone_start_ = right_edge_;
  buildCrossSection(s);
}

void RoadGeometry::buildCrossSection(const SceneSettings& s) {
  const double W = s.lane_width;
  const int L = s.lanes_left, n_lines = s.lanes_left + s.lanes_right + 2;
  lanes_.assign(L + s.lanes_right + 1, LaneDef());
  for (int j = -L; j <= s.lanes_right; ++j) lanes_[j + L].centre = laneCentre(j);
  const auto push = [this](const BoundaryDef& b) {
    boundaries_.push_back(b);
    return static_cast<int>(boundaries_.size()) - 1;
  };
  road_edge_left_ = push(roadEdge(left_edge_ - s.shoulder_width - 0.05, EdgeType::kShoulderEdge));
  // lines from left to right: k = 0 is the left road edge; line k is left of lane k - L
  for (int k = 0; k < n_lines; ++k) {
    const int lane_right = k - L;  // lane right of this line (== lanes_right + 1 past the last)
    const bool is_edge = k == 0 || k == n_lines - 1;
    const bool is_ego_left = k == s.lanes_left;
    const bool is_ego_right = k == s.lanes_left + 1;
    double offset = left_edge_ + k * W;
    if (k > L) offset += tram_zone_width_;
    int index = -1;
    if (is_ego_left && hasTram()) {
      // lane -1 ends at the far track's outer rail, the ego lane at the near rail
      const double near_rail = tramZoneRight();
      lanes_[lane_right - 1 + L].right = push(roadEdge(
          near_rail - tram_spacing_ - tram_gauge_ - tram_head_, EdgeType::kRails));
      lanes_[lane_right + L].left = push(roadEdge(near_rail, EdgeType::kRails));
      continue;
    }
    if (is_ego_right && s.right_boundary != BoundaryType::kPaint) {
      index = push(roadEdge(offset, s.right_boundary == BoundaryType::kKerb
                                        ? EdgeType::kKerb
                                        : EdgeType::kAsphaltEdge));
    } else {
      MarkerKind kind = is_edge ? s.edges : s.separators;
      PaintColour colour = PaintColour::kWhite;
      if (is_ego_left) {
        kind = s.ego_left;
        colour = s.ego_left_colour;
      }
      if (is_ego_right) {
        kind = s.ego_right;
        colour = s.ego_right_colour;
      }
      BoundaryDef b;
      b.offset = offset;
      b.present = kind != MarkerKind::kNone;
      b.style = styleOf(kind);
      b.colour = colour == PaintColour::kYellow ? LineColour::kYellow : LineColour::kWhite;
      index = push(b);
      if (b.present) {
        MarkerLine m;
        m.offset = offset;
        m.width =
            (is_edge && !is_ego_left && !is_ego_right) ? s.edge_marker_width : s.marker_width;
        m.dashed = kind == MarkerKind::kDashed;
        m.dash_length = s.dash_length;
        m.period = s.dash_length + s.dash_gap;
        m.phase = 1.7 * k;  // neighbouring lines are not in phase
        if (kind == MarkerKind::kDouble) m.double_gap = s.double_line_gap;
        m.colour = colour;
        markers_.push_back(m);
      }
    }
    if (lane_right <= s.lanes_right) lanes_[lane_right + L].left = index;
    if (lane_right - 1 >= -L) lanes_[lane_right - 1 + L].right = index;
  }
  road_edge_right_ =
      s.right_boundary == BoundaryType::kPaint
          ? push(roadEdge(right_edge_ + s.shoulder_width + 0.05, EdgeType::kShoulderEdge))
          : lanes_.back().right;
}

Eigen::Vector2d RoadGeometry::point(double s, double t) const {
  if (curvature_ == 0.0) return Eigen::Vector2d(t, s);
  const double phi = s * curvature_;
  const double rho = radius_ - t;
  return Eigen::Vector2d(radius_ - rho * std::cos(phi), rho * std::sin(phi));
}

Eigen::Vector3d RoadGeometry::surfacePoint(double s, double t) const {
  const Eigen::Vector2d g = point(s, t);
  return Eigen::Vector3d(g.x(), profile_.height(s), g.y());
}

void RoadGeometry::coordinates(double x, double z, double s_ref, double& s, double& t) const {
  if (curvature_ == 0.0) {
    s = z;
    t = x;
    return;
  }
  const double vx = x - radius_, vz = z;
  const double r = std::hypot(vx, vz);
  const double rho = radius_ > 0 ? r : -r;
  t = radius_ - rho;
  const double phi = rho != 0.0 ? std::atan2(vz / rho, -vx / rho) : 0.0;
  s = phi * radius_;
  const double turn = 2.0 * M_PI * std::fabs(radius_);
  s += std::round((s_ref - s) / turn) * turn;
}

bool RoadGeometry::rayToLateral(double ox, double oz, double dx, double dz, double t_line,
                                double min_l, double max_l, double& lambda) const {
  if (curvature_ == 0.0) {
    if (std::fabs(dx) < 1e-12) return false;
    lambda = (t_line - ox) / dx;
    return lambda > min_l && lambda < max_l;
  }
  // |o + l d - C|^2 = (R - t)^2 with C = (R, 0)
  const double px = ox - radius_, pz = oz;
  const double a = dx * dx + dz * dz;
  const double b = 2.0 * (px * dx + pz * dz);
  const double rr = radius_ - t_line;
  const double c = px * px + pz * pz - rr * rr;
  const double disc = b * b - 4.0 * a * c;
  if (a < 1e-18 || disc < 0.0) return false;
  const double sq = std::sqrt(disc);
  const double l1 = (-b - sq) / (2.0 * a), l2 = (-b + sq) / (2.0 * a);
  if (l1 > min_l && l1 < max_l) {
    lambda = l1;
    return true;
  }
  if (l2 > min_l && l2 < max_l) {
    lambda = l2;
    return true;
  }
  return false;
}

int RoadGeometry::markerAt(double s, double t) const {
  if (intersection_period_ > 0.0 && inLineGap(s)) return -1;
  for (size_t i = 0; i < markers_.size(); ++i) {
    const MarkerLine& m = markers_[i];
    if (m.double_gap > 0.0) {
      const double d = std::fabs(t - m.offset) - 0.5 * m.double_gap;
      if (d < 0.0 || d > m.width) continue;
    } else if (std::fabs(t - m.offset) > 0.5 * m.width) {
      continue;
    }
    if (m.dashed) {
      double u = std::fmod(s - m.phase, m.period);
      if (u < 0) u += m.period;
      if (u >= m.dash_length) continue;
    }
    return static_cast<int>(i);
  }
  return -1;
}

int RoadGeometry::laneAt(double t) const {
  int best = -lanes_left_;
  for (int j = -lanes_left_; j <= lanes_right_; ++j)
    if (std::fabs(t - laneCentre(j)) < std::fabs(t - laneCentre(best))) best = j;
  return best;
}

int RoadGeometry::tramPartAt(double t) const {
  const double z = tramZoneRight();
  const double h = 0.5 * tram_head_;
  if (!hasTram() || t < tramZoneLeft() || t > z + h) return 0;
  for (int track = 0; track < 2; ++track) {
    const double right_rail = z - track * tram_spacing_;
    const double left_rail = right_rail - tram_gauge_ - tram_head_;
    if (std::fabs(t - right_rail) <= h || std::fabs(t - left_rail) <= h) return 1;
    // flangeways on the gauge side (inside the track)
    if ((t < right_rail - h && t >= right_rail - h - tram_groove_) ||
        (t > left_rail + h && t <= left_rail + h + tram_groove_))
      return 2;
    if (t > left_rail && t < right_rail) return 3;
  }
  return 0;
}

int RoadGeometry::intersectionAt(double s, double& local) const {
  if (intersection_period_ <= 0.0) return -1;
  const double P = intersection_period_;
  const double k = std::floor((s - intersection_start_ + 0.5 * P) / P);
  if (k < 0) return -1;
  local = s - (intersection_start_ + k * P);
  return static_cast<int>(k);
}

bool RoadGeometry::inCrossing(double s) const {
  double local;
  return intersectionAt(s, local) >= 0 && local >= 0.0 && local <= crossing_width_;
}

bool RoadGeometry::inLineGap(double s) const {
  double local;
  return intersectionAt(s, local) >= 0 && local >= kStopLineFrom &&
         local <= crossing_width_ - kStopLineFrom;
}

double RoadGeometry::distanceToLineGap(double s) const {
  if (intersection_period_ <= 0.0) return std::numeric_limits<double>::infinity();
  if (inLineGap(s)) return 0.0;
  const double P = intersection_period_;
  // the next gap start after s
  double k = std::ceil((s - intersection_start_ - kStopLineFrom) / P);
  k = std::max(k, 0.0);
  return intersection_start_ + k * P + kStopLineFrom - s;
}

int RoadGeometry::roadMarkingAt(double s, double t) const {
  double local;
  const int k = intersectionAt(s, local);
  if (k < 0) return 0;
  const double W = lane_width_;
  const double ego_left = laneCentre(0) - 0.5 * W;
  const double far = local - crossing_width_;  // relative to the crossing road's far edge
  // stop lines: ours across our direction's lanes, the far one across the oncoming lanes
  if (local >= kStopLineFrom && local <= kStopLineTo && t >= ego_left && t <= right_edge_)
    return 1;
  if (far >= -kStopLineTo && far <= -kStopLineFrom && t >= left_edge_ && t <= ego_left) return 1;
  // zebra crossings on both sides, across the roadway
  if (((local >= kZebraFrom && local <= kZebraTo) || (far >= -kZebraTo && far <= -kZebraFrom)) &&
      t >= left_edge_ && t <= right_edge_) {
    double u = std::fmod(t - left_edge_, 2.0 * kZebraStripe);
    if (u < 0) u += 2.0 * kZebraStripe;
    return u < kZebraStripe ? 2 : 0;
  }
  if (turn_arrows_) {
    const int variant = static_cast<int>(hash32(static_cast<uint32_t>(k) + 0xa770U) % 3U);
    for (int lane = 0; lane <= lanes_right_; ++lane) {
      for (double tip : kArrowTips) {
        const double u = local - (tip - kArrowLength);
        if (insideArrow(u, t - laneCentre(lane), lane == lanes_right_ ? variant : 0)) return 3;
      }
    }
  }
  return 0;
}

}  // namespace synth
}  // namespace rgbd_lane_detector
