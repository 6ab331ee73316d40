// Ray tracing and materials of the synthetic road scene.
#include <algorithm>
#include <cmath>

#include "frame_context.h"
#include "rgbd_lane_detector_tools/synth/noise.h"

namespace rgbd_lane_detector {
namespace synth {
namespace {

inline double clamp01(double v) {
  return std::min(1.0, std::max(0.0, v));
}
inline double smoothstep(double a, double b, double x) {
  const double t = clamp01((x - a) / (b - a));
  return t * t * (3.0 - 2.0 * t);
}
inline cv::Vec3d mix(const cv::Vec3d& a, const cv::Vec3d& b, double w) {
  return a * (1.0 - w) + b * w;
}
inline cv::Vec3d mul(const cv::Vec3d& a, const cv::Vec3d& b) {
  return cv::Vec3d(a[0] * b[0], a[1] * b[1], a[2] * b[2]);
}

constexpr double kRailBeamHeight = 0.32;  // m, the beam spans [rail_height - this, rail_height]
constexpr double kPostSpacing = 2.0;
constexpr double kPostWidth = 0.12;

}  // namespace

void FrameContext::prepare(int width, int height) {
  const Eigen::Matrix3d Rt = pose.R_wc.transpose();
  const cv::Rect2d image(0, 0, width, height);
  const double floor = std::min(road->profile().minHeight(), std::min(0.0, road->sideZoneHeight()));
  for (Box& b : boxes) {
    double umin = 1e18, umax = -1e18, vmin = 1e18, vmax = -1e18;
    int behind = 0;
    Eigen::Vector4d fp(1e18, -1e18, 1e18, -1e18);
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d corner_local((k & 1 ? 1 : -1) * b.half.x(),
                                         (k & 2 ? 1 : -1) * b.half.y(),
                                         (k & 4 ? 1 : -1) * b.half.z());
      const Eigen::Vector3d c = b.centre + b.R * corner_local;
      const Eigen::Vector3d pc = Rt * (c - pose.position);
      if (pc.z() < 0.05) {
        ++behind;
      } else {
        const double u = fx * pc.x() / pc.z() + cx, v = fy * pc.y() / pc.z() + cy;
        umin = std::min(umin, u);
        umax = std::max(umax, u);
        vmin = std::min(vmin, v);
        vmax = std::max(vmax, v);
      }
      // ground footprint of the shadow: the corner and its projection along the sun down to
      // the lowest ground (y = 0 on a flat road)
      const Eigen::Vector3d g = c - ((c.y() - floor) / std::max(sun.y(), 0.05)) * sun;
      for (const Eigen::Vector3d& q : {c, g}) {
        fp[0] = std::min(fp[0], q.x());
        fp[1] = std::max(fp[1], q.x());
        fp[2] = std::min(fp[2], q.z());
        fp[3] = std::max(fp[3], q.z());
      }
    }
    if (behind == 8) {
      b.screen = cv::Rect2d();
    } else if (behind > 0) {
      b.screen = image;  // straddles the camera plane: no bound
    } else {
      b.screen = cv::Rect2d(umin - 1, vmin - 1, umax - umin + 2, vmax - vmin + 2) & image;
    }
    b.shadow_aabb = fp;
  }
}

Eigen::Vector3d FrameContext::rayDirection(double u, double v) const {
  return pose.R_wc * Eigen::Vector3d((u - cx) / fx, (v - cy) / fy, 1.0);
}

void FrameContext::trace(double u, double v, Hit& hit) const {
  const Eigen::Vector3d d = rayDirection(u, v);
  const Eigen::Vector3d& o = pose.position;
  hit = Hit();
  double best = settings->max_range;
  if (!flat_ground) {
    traceGround(o, d, best, hit);
  } else if (d.y() < -1e-9) {
    const double l = -o.y() / d.y();
    if (l < best) {
      best = l;
      hit.kind = Hit::kGround;
      hit.lambda = l;
    }
  }
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Box& b = boxes[i];
    if (!b.screen.contains(cv::Point2d(u, v))) continue;
    BoxHit bh;
    if (intersectBox(b, o, d, 1e-6, best, bh)) {
      best = bh.lambda;
      hit.kind = Hit::kBox;
      hit.lambda = bh.lambda;
      hit.box = static_cast<int>(i);
      hit.box_hit = bh;
    }
  }
  if (settings->guard_rails) {
    for (int side : {-1, 1}) {
      const double t_rail = side < 0 ? rail_left : rail_right;
      double l;
      if (!road->rayToLateral(o.x(), o.z(), d.x(), d.z(), t_rail, 1e-6, best, l)) continue;
      const Eigen::Vector3d p = o + l * d;
      double s, t;
      road->coordinates(p.x(), p.z(), pose.s, s, t);
      const double y = p.y() - road->profile().height(s);  // above the road
      if (y < 0.0 || y > settings->rail_height) continue;
      Hit::Kind kind = Hit::kRail;
      if (y < settings->rail_height - kRailBeamHeight) {
        double m = std::fmod(s, kPostSpacing);
        if (m < 0) m += kPostSpacing;
        if (m > kPostWidth) continue;  // between posts
        kind = Hit::kRailPost;
      }
      best = l;
      hit.kind = kind;
      hit.lambda = l;
      hit.rail_side = side;
      hit.s = s;
      hit.t = t;
    }
  }
  if (hit.kind == Hit::kNone) return;
  if (flat_ground || hit.kind != Hit::kGround) hit.point = o + hit.lambda * d;
  if (hit.kind == Hit::kGround && flat_ground) {
    hit.point.y() = 0.0;
    road->coordinates(hit.point.x(), hit.point.z(), pose.s, hit.s, hit.t);
  }
}

bool FrameContext::surfaceHit(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double offset,
                              double max_l, double& l, double& s, double& t) const {
  const VerticalProfile& profile = road->profile();
  if (profile.flat()) {
    if (d.y() > -1e-9) return false;
    l = (offset - o.y()) / d.y();
    if (!(l > 0.0 && l < max_l)) return false;
    const Eigen::Vector3d p = o + l * d;
    road->coordinates(p.x(), p.z(), pose.s, s, t);
    return true;
  }
  if (road->curvature() == 0.0) {  // s = z along the ray: exact piecewise-quadratic solution
    if (!profile.crossing(o.z(), d.z(), o.y(), d.y(), offset, max_l, l)) return false;
    const Eigen::Vector3d p = o + l * d;
    road->coordinates(p.x(), p.z(), pose.s, s, t);
    return true;
  }
  // f(l) = height of the ray above the surface. Lipschitz steps (|f'| <= lip) never pass the
  // first crossing; Newton steps on a numerical derivative finish it, bisection when one
  // overshoots.
  const auto f = [&](double lambda, double& ss, double& tt) {
    const Eigen::Vector3d p = o + lambda * d;
    road->coordinates(p.x(), p.z(), pose.s, ss, tt);
    return p.y() - profile.height(ss) - offset;
  };
  const auto bisect = [&](double lo, double hi) {  // f(lo) > 0 > f(hi)
    for (int k = 0; k < 60 && hi - lo > 1e-9; ++k) {
      const double mid = 0.5 * (lo + hi);
      (f(mid, s, t) > 0.0 ? lo : hi) = mid;
    }
    l = hi;
    f(l, s, t);
    return l < max_l;
  };
  const double arc = road->curvature() == 0.0 ? 1.0 : 1.5;  // ds / d(arc length) bound
  const double lip = std::fabs(d.y()) + 1.05 * arc * profile.maxGrade() * std::hypot(d.x(), d.z());
  double lambda = 0.0, value = f(0.0, s, t);
  if (value <= 0.0) return false;
  for (int it = 0; it < 600; ++it) {
    if (value < 1e-3) {
      for (int k = 0; k < 8; ++k) {
        double s2, t2;
        const double slope = (f(lambda + 1e-3, s2, t2) - value) / 1e-3;
        if (slope >= 0.0) break;  // grazing: no crossing here
        const double next = lambda - value / slope;
        const double next_value = f(next, s2, t2);
        if (next_value < 0.0) return bisect(lambda, next);
        lambda = next;
        value = next_value;
        s = s2;
        t = t2;
        if (value < 1e-9) {
          l = lambda;
          return l < max_l;
        }
      }
    }
    const double previous = lambda;
    lambda += std::max(value / lip, 1e-4);
    if (lambda >= max_l) return false;
    value = f(lambda, s, t);
    if (value < 0.0) return bisect(previous, lambda);  // the bound is loose on arcs
  }
  return false;
}

void FrameContext::traceGround(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double& best,
                               Hit& hit) const {
  // The camera is above the ego lane. A raised zone (kerb) beyond side_start is met first on its
  // top, else the ray meets the road, or the kerb's face between road and top. A lowered zone
  // (asphalt edge) is met after the ray passed road level beyond its start.
  const double zone = road->sideZoneHeight(), start = road->sideZoneStart();
  double l, s, t;
  const auto set = [&](Hit::Kind kind, double lambda, double ss, double tt) {
    best = lambda;
    hit.kind = kind;
    hit.lambda = lambda;
    hit.s = ss;
    hit.t = tt;
    hit.point = o + lambda * d;
  };
  if (zone > 0.0 && surfaceHit(o, d, zone, best, l, s, t) && t >= start) {
    set(Hit::kGround, l, s, t);
    return;
  }
  if (!surfaceHit(o, d, 0.0, best, l, s, t)) return;
  if (zone == 0.0 || t <= start) {
    set(Hit::kGround, l, s, t);
  } else if (zone < 0.0) {
    if (surfaceHit(o, d, zone, best, l, s, t)) set(Hit::kGround, l, s, t);
  } else if (road->rayToLateral(o.x(), o.z(), d.x(), d.z(), start, 1e-6, best, l)) {
    const Eigen::Vector3d p = o + l * d;
    road->coordinates(p.x(), p.z(), pose.s, s, t);
    const double y = p.y() - road->profile().height(s);
    if (y >= -1e-6 && y <= zone + 1e-6) set(Hit::kKerbFace, l, s, start);
  }
}

Eigen::Vector3d FrameContext::groundNormal(double s) const {
  const double g = road->profile().grade(s), yaw = road->heading(s);
  return Eigen::Vector3d(-g * std::sin(yaw), 1.0, -g * std::cos(yaw)).normalized();
}

uint8_t FrameContext::label(const Hit& hit) const {
  switch (hit.kind) {
    case Hit::kNone:
      return kLabelSky;
    case Hit::kBox:
      return boxes[hit.box].label;
    case Hit::kRail:
    case Hit::kRailPost:
      return kLabelFence;
    case Hit::kKerbFace:
      return kLabelKerb;
    case Hit::kGround: {
      if (road->markerAt(hit.s, hit.t) >= 0) return kLabelLaneMarking;
      if (urban) {
        const SceneSettings& s = *settings;
        if (road->intersections() && road->roadMarkingAt(hit.s, hit.t) > 0)
          return kLabelLaneMarking;
        const double beyond = hit.t - road->sideZoneStart();
        if (s.right_boundary == BoundaryType::kKerb && beyond > 0.0)
          return beyond <= s.kerb_width                     ? kLabelKerb
                 : beyond <= s.kerb_width + s.sidewalk_width ? kLabelSidewalk
                                                             : kLabelVegetation;
        if (s.right_boundary == BoundaryType::kAsphaltEdge && beyond > 0.0)
          return beyond <= s.gravel_width ? kLabelTerrain : kLabelVegetation;
        const int part = road->tramPartAt(hit.t);
        if (part == 1 || part == 2) return kLabelRail;
        if (road->intersections() && road->inCrossing(hit.s)) return kLabelRoad;
      }
      const double l = road->leftEdge(), r = road->rightEdge();
      if (hit.t >= l && hit.t <= r) return kLabelRoad;
      const double sh = settings->shoulder_width;
      if (hit.t >= l - sh && hit.t <= r + sh) return kLabelSidewalk;
      return kLabelVegetation;
    }
  }
  return kLabelVoid;
}

uint32_t FrameContext::sampleKey(const Hit& hit) const {
  uint32_t key = label(hit) | (static_cast<uint32_t>(hit.kind) << 8) |
                 (static_cast<uint32_t>(hit.box + 1) << 12);
  if (hit.kind == Hit::kGround) {
    key |= static_cast<uint32_t>(road->markerAt(hit.s, hit.t) + 1) << 20;
    if (settings->shadows && sunVisibility(hit.point, -1) < 0.5) key |= 1u << 28;
    if (urban) key |= urbanKey(hit) << 12;  // box bits are free on the ground
  }
  return key;
}

uint32_t FrameContext::urbanKey(const Hit& hit) const {
  uint32_t key = static_cast<uint32_t>(road->tramPartAt(hit.t));  // 2 bits
  if (road->intersections()) {
    key |= static_cast<uint32_t>(road->roadMarkingAt(hit.s, hit.t)) << 2;  // 2 bits
    key |= static_cast<uint32_t>(road->inCrossing(hit.s)) << 4;
  }
  if (kerbShadow(hit) > 0.5) key |= 1u << 5;
  return key;
}

cv::Vec3d FrameContext::sky(const Eigen::Vector3d& dir) const {
  const Eigen::Vector3d n = dir.normalized();
  const SceneSettings& s = *settings;
  cv::Vec3d c = mix(s.sky_horizon, s.sky_zenith, smoothstep(0.0, 0.45, n.y()));
  if (n.y() > 0.01 && s.cloud_cover > 0) {
    const double k = 1.0 / n.y();
    const double cl = fbm(n.x() * k * 40.0 + 0.3 * index, n.z() * k * 40.0, 60.0, 4, 1.0, seed + 9);
    const double cover = smoothstep(1.0 - s.cloud_cover - 0.15, 1.0 - s.cloud_cover + 0.15, cl);
    c = mix(c, cv::Vec3d(0.92, 0.92, 0.93) * (0.8 + 0.2 * s.ambient), cover);
  }
  return c;
}

double FrameContext::canopyShadow(double x, double z, double t) const {
  const double c = settings->canopy_shadows;
  if (c <= 0) return 0.0;
  const double inside = std::min(t - road->leftEdge(), road->rightEdge() - t);  // from the edge
  const double reach = 1.0 - smoothstep(-2.0, 5.0, inside);
  if (reach <= 0) return 0.0;
  const double n = fbm(x, z, 6.0, 4, 0.05, seed + 31);
  return smoothstep(0.56, 0.60, n + 0.25 * c * reach) * reach;
}

double FrameContext::sunVisibility(const Eigen::Vector3d& p, int self_box) const {
  if (!settings->shadows) return 1.0;
  const Eigen::Vector3d o = p + 1e-4 * sun;
  for (size_t i = 0; i < boxes.size(); ++i) {
    if (static_cast<int>(i) == self_box) continue;
    const Box& b = boxes[i];
    const Eigen::Vector4d& f = b.shadow_aabb;
    if (p.x() < f[0] || p.x() > f[1] || p.z() < f[2] || p.z() > f[3]) continue;
    BoxHit bh;
    if (intersectBox(b, o, sun, 0.0, 1e4, bh)) return 0.0;
  }
  return 1.0;
}

cv::Vec3d FrameContext::groundAlbedo(const Hit& hit, double footprint) const {
  const SceneSettings& s = *settings;
  const double x = hit.point.x(), z = hit.point.z(), t = hit.t, sr = hit.s;
  const double l = road->leftEdge(), r = road->rightEdge(), sh = s.shoulder_width;
  const bool crossing = urban && road->intersections() && road->inCrossing(sr);
  if (urban && s.right_boundary != BoundaryType::kPaint && t > road->sideZoneStart())
    return sideZoneAlbedo(hit, footprint);
  if (!crossing && (t < l - sh - 0.05 || t > r + sh + 0.05)) return grassAlbedo(x, z, footprint);
  // asphalt: fine grain + large blotches, repaired patches, cracks, tyre tracks
  const double grain = fbm(x, z, 2.0, 6, footprint, seed + 5);
  const double blotch = fbm(x, z, 30.0, 3, footprint, seed + 6);
  const double speck = fbm(x, z, 0.08, 2, footprint, seed + 13);  // aggregate, 2-8 cm
  double a = s.asphalt_albedo *
             (1.0 + s.asphalt_contrast *
                        (1.4 * (grain - 0.5) + 1.2 * (blotch - 0.5) + 1.6 * (speck - 0.5)));
  const double cell_s = std::floor(sr / 8.0), cell_t = std::floor((t - l) / s.lane_width);
  const uint32_t ch = hashKeys(seed + 7, static_cast<uint32_t>(static_cast<int64_t>(cell_s)),
                               static_cast<uint32_t>(static_cast<int64_t>(cell_t)));
  if (unitFromHash(ch) < s.patch_density) {
    const double s0 = cell_s * 8.0 + 3.0 * hashUniform(ch, 1),
                 s1 = s0 + 1.5 + 3.0 * hashUniform(ch, 2);
    const double t0 = l + cell_t * s.lane_width + 1.6 * hashUniform(ch, 3);
    const double t1 = t0 + 0.6 + 1.4 * hashUniform(ch, 4);
    if (sr >= s0 && sr <= s1 && t >= t0 && t <= t1) a *= hashUniform(ch, 5) < 0.6 ? 0.86 : 1.1;
  }
  if (s.crack_density > 0) {
    const double region = fbm(x, z, 25.0, 2, footprint, seed + 8);
    if (region > 1.0 - 0.45 * s.crack_density) {
      // thin, jagged crack lines: iso-line of a fractal field, fading with the footprint
      const double rn = std::fabs(fbm(x, z, 1.5, 3, 0.01, seed + 10) - 0.5);
      const double cover = clamp01(1.0 - rn / 0.008) * std::min(1.0, 0.025 / footprint);
      a *= 1.0 - 0.5 * cover;
    }
  }
  for (int lane = -s.lanes_left; lane <= s.lanes_right; ++lane) {
    for (double side : {-0.85, 0.85}) {
      const double d = std::fabs(t - road->laneCentre(lane) - side);
      if (d < 0.35) a *= 1.0 - 0.07 * std::cos(d / 0.35 * M_PI_2);
    }
  }
  if (!crossing && (t < l || t > r)) a *= 1.12;  // shoulder: older, lighter surface
  const int tram = urban ? road->tramPartAt(t) : 0;
  if (tram == 1) return cv::Vec3d(0.30, 0.30, 0.32);  // rail head steel (specular in shade())
  if (tram == 2) return cv::Vec3d(0.05, 0.05, 0.05);  // flangeway: a dark groove
  if (tram == 3) {  // granite setts between the rails: 0.2 x 0.1 m, staggered rows, 1 cm joints
    const double v = t / 0.1, row = std::floor(v);
    const double u = sr / 0.2 + 0.5 * std::fmod(std::fabs(row), 2.0), col = std::floor(u);
    const double joint = std::min(std::min(v - row, row + 1.0 - v) * 0.1,
                                  std::min(u - col, col + 1.0 - u) * 0.2);
    const double sett = 0.85 + 0.3 * hashUniform(seed + 41, static_cast<uint32_t>(row + 1e6),
                                                  static_cast<uint32_t>(col + 1e6));
    const double detail = std::min(1.0, 0.03 / footprint);  // the pattern fades with distance
    const double pattern = (joint < 0.005 ? 0.6 : sett) * (0.9 + 0.2 * grain);
    a = s.asphalt_albedo * 1.15 * (detail * pattern + (1.0 - detail) * 0.95);
  }
  if (urban && s.right_boundary == BoundaryType::kAsphaltEdge) {
    // gravel spilled onto the last 15 cm of asphalt
    const double inside = road->sideZoneStart() - t;
    if (inside < 0.15 && fbm(x, z, 0.3, 3, footprint, seed + 51) > 0.42 + inside / 0.15 * 0.4)
      return gravelAlbedo(x, z, footprint);
  }
  cv::Vec3d c = cv::Vec3d(0.96, 0.99, 1.05) * a;
  const int m = road->markerAt(sr, t);
  const int marking = m < 0 && urban && road->intersections() ? road->roadMarkingAt(sr, t) : 0;
  if (m >= 0 || marking > 0) {
    const double wear = fbm(sr * 1.5, t * 5.0, 1.0, 4, footprint, seed + 12);
    const double cover = 1.0 - s.paint_wear * smoothstep(0.35, 0.75, wear) * 1.6;
    const bool yellow = m >= 0 && road->markers()[m].colour == PaintColour::kYellow;
    c = mix(c, yellow ? s.yellow_paint : cv::Vec3d(1.0, 1.0, 0.97) * s.paint_albedo,
            clamp01(cover));
  }
  return c;
}

cv::Vec3d FrameContext::grassAlbedo(double x, double z, double footprint) const {
  const double g = fbm(x, z, 3.0, 6, footprint, seed + 3);
  const double patchy = fbm(x, z, 25.0, 2, footprint, seed + 4);
  return cv::Vec3d(0.16, 0.28, 0.09) * (0.6 + 0.6 * g) + cv::Vec3d(0.08, 0.04, 0.02) * patchy;
}

cv::Vec3d FrameContext::gravelAlbedo(double x, double z, double footprint) const {
  const double stones = fbm(x, z, 0.06, 3, footprint, seed + 52);  // 1-6 cm stones
  const double dirt = fbm(x, z, 2.0, 3, footprint, seed + 53);
  return cv::Vec3d(1.06, 0.98, 0.86) * settings->gravel_albedo *
         (0.7 + 0.6 * stones - 0.2 * (dirt - 0.5));
}

cv::Vec3d FrameContext::kerbAlbedo(double s, double footprint) const {
  // granite kerb stones of 1 m with 1 cm joints, each a little different
  const double stone = std::floor(s);
  const double joint = std::min(s - stone, stone + 1.0 - s);
  const double detail = std::min(1.0, 0.02 / footprint);
  const double base = 0.92 + 0.16 * hashUniform(seed + 43, static_cast<uint32_t>(stone + 1e6));
  const double grain = fbm(s * 3.0, 0.0, 0.2, 3, footprint, seed + 44);
  const double v = (joint < 0.005 ? 0.6 * detail + (1.0 - detail) : 1.0) * base *
                   (0.9 + 0.2 * grain);
  return cv::Vec3d(0.97, 0.99, 1.02) * settings->kerb_albedo * v;
}

cv::Vec3d FrameContext::sideZoneAlbedo(const Hit& hit, double footprint) const {
  const SceneSettings& s = *settings;
  const double x = hit.point.x(), z = hit.point.z();
  const double beyond = hit.t - road->sideZoneStart();
  if (s.right_boundary == BoundaryType::kKerb) {
    if (beyond <= s.kerb_width) return kerbAlbedo(hit.s, footprint);
    if (beyond > s.kerb_width + s.sidewalk_width) return grassAlbedo(x, z, footprint);
    // concrete sidewalk tiles of 0.3 m with dark joints, stains
    const double u = hit.s / 0.3, v = (beyond - s.kerb_width) / 0.3;
    const double joint = std::min({u - std::floor(u), std::ceil(u) - u, v - std::floor(v),
                                   std::ceil(v) - v}) * 0.3;
    const double detail = std::min(1.0, 0.03 / footprint);
    const double stain = fbm(x, z, 4.0, 4, footprint, seed + 45);
    const double tile = 0.95 + 0.1 * hashUniform(seed + 46, static_cast<uint32_t>(u + 1e6),
                                                 static_cast<uint32_t>(v + 1e6));
    const double a = s.sidewalk_albedo * tile * (0.85 + 0.3 * stain) *
                     (joint < 0.006 ? 0.7 * detail + (1.0 - detail) : 1.0);
    return cv::Vec3d(1.0, 0.99, 0.96) * a;
  }
  return beyond <= s.gravel_width ? gravelAlbedo(x, z, footprint) : grassAlbedo(x, z, footprint);
}

double FrameContext::kerbShadow(const Hit& hit) const {
  if (settings->right_boundary != BoundaryType::kKerb || !settings->shadows) return 0.0;
  const double gap = road->sideZoneStart() - hit.t;  // road points before the face
  if (gap < 0.0 || gap > 1.0 || hit.kind != Hit::kGround) return 0.0;
  const double yaw = road->heading(hit.s);
  const double toward = sun.x() * std::cos(yaw) - sun.z() * std::sin(yaw);  // sun toward +t
  if (toward <= 1e-6) return 0.0;
  return sun.y() * gap / toward < settings->kerb_height ? 1.0 : 0.0;
}

cv::Vec3d FrameContext::boxAlbedo(const Box& box, const BoxHit& h) const {
  const Eigen::Vector3d& q = h.local;
  const Eigen::Vector3d& hf = box.half;
  const double y = q.y() + hf.y();  // height above the box bottom
  const double xr = (q.x() + hf.x()) / (2 * hf.x()), zr = (q.z() + hf.z()) / (2 * hf.z());
  const double yr = y / (2 * hf.y());
  const bool side = h.axis == 0, top = h.axis == 1 && h.sign > 0, end = h.axis == 2;
  const bool rear = end && h.sign < 0;  // the -z face looks back at traffic behind
  const cv::Vec3d dark(0.04, 0.04, 0.045), glass(0.06, 0.07, 0.09), white(0.86, 0.86, 0.84);
  switch (box.kind) {
    case BoxKind::kCar: {
      if (top) return box.albedo;
      if (yr < 0.2) return dark;
      if (yr > 0.62 && ((side && zr > 0.2 && zr < 0.85) || (end && xr > 0.08 && xr < 0.92)))
        return glass;
      if (end && yr > 0.45 && yr < 0.58 && (xr < 0.17 || xr > 0.83))
        return rear ? cv::Vec3d(0.75, 0.05, 0.04) : cv::Vec3d(0.9, 0.9, 0.85);
      if (end && yr > 0.28 && yr < 0.38 && xr > 0.38 && xr < 0.62) return white * 0.9;
      return box.albedo;
    }
    case BoxKind::kTruck: {
      if (top) return box.albedo * 0.9;
      if (y < 0.9) {  // wheels, chassis and a bumper bar
        if (end && y > 0.45 && y < 0.6) return box.stripes ? white : cv::Vec3d(0.3, 0.3, 0.3);
        return dark;
      }
      if (box.stripes) {
        if (side && ((y > 1.0 && y < 1.15) || (y > 2 * hf.y() - 0.3 && y < 2 * hf.y() - 0.15)))
          return white;
        if (end) {
          const double edge = std::min({q.x() + hf.x(), hf.x() - q.x(), y - 0.9, 2 * hf.y() - y});
          if (edge < 0.1) return white;  // contour tape
          if (y < 1.6) {                 // chevrons "/\" on the rear bumper panel
            const double v = std::fmod(std::fabs(q.x()) + y, 0.5);
            return v < 0.25 ? white : cv::Vec3d(0.7, 0.06, 0.05);
          }
        }
      }
      if (end && std::fabs(q.x()) < 0.03) return dark;  // door gap
      return box.albedo;
    }
    case BoxKind::kConcrete: {
      const double n = fbm(q.x() + q.z(), q.y(), 2.0, 4, 0.05, seed + 20);
      return box.albedo * (0.85 + 0.3 * n);
    }
    case BoxKind::kPole:
      return box.albedo;
  }
  return box.albedo;
}

double FrameContext::headlightFactor(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const {
  const SceneSettings& s = *settings;
  const Eigen::Vector3d out = p - lamp;  // from the lamps to the point
  const double d = out.norm();
  if (d < 0.1) return 0.0;
  const Eigen::Vector3d l = out / d;
  const double ndl = std::max(0.0, -n.dot(l));
  // low beam: cut off at the lamps' horizon (within 1 deg), about 34 deg wide (1/e)
  const double below = -l.dot(up);
  const double cut = smoothstep(0.0, 0.0175, below);
  const Eigen::Vector3d flat = (l - l.dot(up) * up).normalized();
  const double az = std::acos(std::max(-1.0, std::min(1.0, flat.dot(ahead))));
  const double spread = std::exp(-(az / 0.6) * (az / 0.6));
  // aimed at the road: the road (n = up, ndl = lamp height / d) is lit evenly to the range;
  // a surface facing the lamps gets at most 3x the road's irradiance
  const double height = std::max(0.1, (lamp - p).dot(up));
  const double aim = std::min(3.0, ndl * d / height);
  const double reach = d > s.headlight_range ? (s.headlight_range / d) * (s.headlight_range / d) : 1.0;
  return cut * spread * aim * reach;
}

cv::Vec3d FrameContext::shade(const Hit& hit, const Eigen::Vector3d& dir, double footprint) const {
  const SceneSettings& s = *settings;
  cv::Vec3d c;
  if (hit.kind == Hit::kNone) {
    c = sky(dir);
  } else {
    cv::Vec3d albedo;
    Eigen::Vector3d n(0, 1, 0);
    int self = -1;
    double vis = 1.0;
    double specular = 0.0;
    if (hit.kind == Hit::kGround) {
      albedo = groundAlbedo(hit, footprint);
      vis = 1.0 - canopyShadow(hit.point.x(), hit.point.z(), hit.t);
      if (!road->profile().flat()) n = groundNormal(hit.s);
      if (urban) {
        vis *= 1.0 - kerbShadow(hit);
        if (road->tramPartAt(hit.t) == 1) specular = 0.75;  // polished rail heads mirror the sky
      }
    } else if (hit.kind == Hit::kKerbFace) {
      albedo = kerbAlbedo(hit.s, footprint) * 0.9;
      const double yaw = road->heading(hit.s);
      n = -Eigen::Vector3d(std::cos(yaw), 0, -std::sin(yaw));  // faces the road
    } else if (hit.kind == Hit::kBox) {
      const Box& b = boxes[hit.box];
      albedo = boxAlbedo(b, hit.box_hit);
      Eigen::Vector3d nl = Eigen::Vector3d::Zero();
      nl[hit.box_hit.axis] = hit.box_hit.sign;
      n = b.R * nl;
      self = hit.box;
    } else {
      const bool beam = hit.kind == Hit::kRail;
      albedo = beam ? cv::Vec3d(0.85, 0.85, 0.83) : cv::Vec3d(0.35, 0.35, 0.36);
      const double yaw = road->heading(hit.s);
      const Eigen::Vector3d lateral(std::cos(yaw), 0, -std::sin(yaw));
      n = hit.rail_side < 0 ? lateral : Eigen::Vector3d(-lateral);
    }
    const double ndl = std::max(0.0, n.dot(sun));
    if (ndl > 0 && vis > 0) vis *= sunVisibility(hit.point, self);
    c = mul(albedo, ambient_light * (0.75 + 0.25 * n.y()) + sun_light * (ndl * vis));
    if (s.headlights > 0.0) c += mul(albedo, headlight_light * headlightFactor(hit.point, n));
    if (specular > 0.0) {  // a rough steel mirror: the reflected sky's brightness
      const cv::Vec3d sky_seen = mix(sky(dir - 2.0 * dir.dot(n) * n), s.sky_horizon, 0.6);
      const double lum = 0.3 * sky_seen[0] + 0.59 * sky_seen[1] + 0.11 * sky_seen[2];
      c = mix(c, cv::Vec3d(0.97, 0.99, 1.0) * (1.1 * lum), specular);
    }
    // aerial perspective in clear air, then fog
    c = mix(c, s.sky_horizon, 1.0 - std::exp(-hit.lambda / 1500.0));
  }
  if (s.fog_visibility > 0) {
    const double w = hit.kind == Hit::kNone ? 1.0 : 1.0 - std::exp(-hit.lambda / s.fog_visibility);
    c = mix(c, s.fog_colour, w);
  }
  return c;
}

}  // namespace synth
}  // namespace rgbd_lane_detector
