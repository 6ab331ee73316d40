#include "scene_objects.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace rgbd_lane_detector {
namespace synth {
namespace {

constexpr double kWindowBehind = 15.0;  // vehicles wrap inside [-15, 105) m around the camera
constexpr double kWindowLength = 120.0;

Eigen::Matrix3d yawMatrix(double yaw) {
  Eigen::Matrix3d R;
  R << std::cos(yaw), 0, std::sin(yaw), 0, 1, 0, -std::sin(yaw), 0, std::cos(yaw);
  return R;
}

// Tilts the box's forward axis (+z) up by pitch (a box on a grade).
Eigen::Matrix3d pitchMatrix(double pitch) {
  Eigen::Matrix3d R;
  R << 1, 0, 0, 0, std::cos(pitch), std::sin(pitch), 0, -std::sin(pitch), std::cos(pitch);
  return R;
}

const cv::Vec3d kCarColours[] = {{0.85, 0.85, 0.86}, {0.55, 0.56, 0.58}, {0.05, 0.05, 0.06},
                                 {0.10, 0.16, 0.40}, {0.55, 0.07, 0.06}, {0.20, 0.20, 0.22},
                                 {0.30, 0.33, 0.25}};
const cv::Vec3d kTruckColours[] = {
    {0.12, 0.22, 0.50}, {0.45, 0.10, 0.08}, {0.15, 0.30, 0.15}, {0.30, 0.30, 0.32}};

}  // namespace

bool intersectBox(const Box& box, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double min_l,
                  double max_l, BoxHit& hit) {
  const Eigen::Vector3d ol = box.R.transpose() * (o - box.centre);
  const Eigen::Vector3d dl = box.R.transpose() * d;
  double t0 = min_l, t1 = max_l;
  int axis = -1;
  for (int a = 0; a < 3; ++a) {
    const double h = box.half[a];
    if (std::fabs(dl[a]) < 1e-12) {
      if (std::fabs(ol[a]) > h) return false;
      continue;
    }
    const double inv = 1.0 / dl[a];
    double ta = (-h - ol[a]) * inv, tb = (h - ol[a]) * inv;
    if (ta > tb) std::swap(ta, tb);
    if (ta > t0) {
      t0 = ta;
      axis = a;
    }
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  if (axis < 0) return false;  // origin inside the box or no entry face in the interval
  hit.lambda = t0;
  hit.axis = axis;
  hit.sign = dl[axis] > 0 ? -1.0 : 1.0;
  hit.local = ol + t0 * dl;
  return true;
}

SceneObjects::SceneObjects(const SceneSettings& s, const RoadGeometry& road) : s_(s), road_(road) {
  std::mt19937 rng(static_cast<uint32_t>(s.seed) * 2654435761u + 17u);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<int> lanes;
  // no traffic in the lanes the ego vehicle changes into (it would drive through it)
  const int change_lo = s.lane_change_length > 0 ? std::min(0, s.lane_change_lanes) : 0;
  const int change_hi = s.lane_change_length > 0 ? std::max(0, s.lane_change_lanes) : 0;
  for (int l = -s.lanes_left; l <= s.lanes_right; ++l)
    if (l < change_lo || l > change_hi) lanes.push_back(l);
  // one relative speed per lane: vehicles of a lane never overlap
  std::vector<double> lane_speed(lanes.size());
  for (auto& v : lane_speed) v = -4.0 + 8.0 * uni(rng);
  if (!lanes.empty()) {
    const int total = s.vehicles + s.trucks;
    for (int i = 0; i < total; ++i) {
      VehicleSpec v;
      v.truck = i >= s.vehicles;
      const size_t li = std::min(lanes.size() - 1, static_cast<size_t>(uni(rng) * lanes.size()));
      v.lane = lanes[li];
      v.rel_speed = lane_speed[li];
      v.lateral = (uni(rng) - 0.5) * 0.4;
      if (v.truck) {
        v.length = 10.0 + 3.0 * uni(rng);
        v.width = 2.5;
        v.height = 3.6 + 0.3 * uni(rng);
        v.colour = kTruckColours[static_cast<int>(uni(rng) * 4) % 4];
      } else {
        v.length = 4.2 + 0.6 * uni(rng);
        v.width = 1.75 + 0.1 * uni(rng);
        v.height = 1.42 + 0.2 * uni(rng);
        v.colour = kCarColours[static_cast<int>(uni(rng) * 7) % 7];
      }
      // spread positions over the window, away from vehicles already in the same lane
      for (int attempt = 0; attempt < 50; ++attempt) {
        v.s0 = -kWindowBehind + kWindowLength * uni(rng);
        bool clear = true;
        for (const auto& o : vehicles_) {
          if (o.lane != v.lane) continue;
          double gap = std::fabs(o.s0 - v.s0);
          gap = std::min(gap, kWindowLength - gap);
          if (gap < 0.5 * (o.length + v.length) + 6.0) clear = false;
        }
        if (clear) break;
      }
      if (s.oncoming_left && v.lane < 0) {
        v.oncoming = true;
        v.rel_speed -= 2.0 * s.speed;
      }
      vehicles_.push_back(v);
    }
  }
  if (s.lead_vehicle) {
    VehicleSpec v;
    v.lane = 0;
    v.lead = true;
    v.s0 = 38.0;
    v.colour = kCarColours[static_cast<int>(uni(rng) * 7) % 7];
    v.height = 1.5;
    vehicles_.push_back(v);
  }
}

void SceneObjects::addVehicle(const VehicleSpec& v, double s, std::vector<Box>& out) const {
  Box b;
  const double t = road_.laneCentre(v.lane) + v.lateral;
  const Eigen::Vector2d g = road_.point(s, t);
  b.R = yawMatrix(road_.heading(s) + (v.oncoming ? M_PI : 0.0));
  b.centre = Eigen::Vector3d(g.x(), 0.5 * v.height, g.y());
  if (!road_.profile().flat()) {  // standing on the grade
    b.R = yawMatrix(road_.heading(s)) * pitchMatrix(std::atan(road_.profile().grade(s))) *
          yawMatrix(v.oncoming ? M_PI : 0.0);
    b.centre = Eigen::Vector3d(g.x(), road_.profile().height(s), g.y()) +
               b.R * Eigen::Vector3d(0.0, 0.5 * v.height, 0.0);
  }
  b.half = Eigen::Vector3d(0.5 * v.width, 0.5 * v.height, 0.5 * v.length);
  b.kind = v.truck ? BoxKind::kTruck : BoxKind::kCar;
  b.albedo = v.colour;
  b.label = kLabelCar;
  b.stripes = v.truck && s_.truck_stripes;
  out.push_back(b);
}

void SceneObjects::boxesAt(int index, double cam_s, std::vector<Box>& out) const {
  out.clear();
  const double time = index / s_.fps;
  for (const auto& v : vehicles_) {
    double rel;
    if (v.lead) {
      rel = v.s0 + 12.0 * std::sin(2.0 * M_PI * time / 40.0);
    } else {
      rel = std::fmod(v.s0 + kWindowBehind + v.rel_speed * time, kWindowLength);
      if (rel < 0) rel += kWindowLength;
      rel -= kWindowBehind;
    }
    addVehicle(v, cam_s + rel, out);
  }
  const double far = cam_s + s_.max_range;
  if (s_.pole_period > 0) {
    const double off = s_.shoulder_width + 0.6;
    for (double k = std::ceil((cam_s - 40.0) / s_.pole_period); k * s_.pole_period < far; ++k) {
      const double s = k * s_.pole_period;
      for (double t : {road_.leftEdge() - off, road_.rightEdge() + off}) {
        Box b;
        const Eigen::Vector2d g = road_.point(s, t);
        b.R = yawMatrix(road_.heading(s));
        b.centre = Eigen::Vector3d(g.x(), 4.0 + road_.profile().height(s), g.y());
        b.half = Eigen::Vector3d(0.09, 4.0, 0.09);
        b.kind = BoxKind::kPole;
        b.albedo = cv::Vec3d(0.45, 0.45, 0.47);
        b.label = kLabelPole;
        out.push_back(b);
      }
    }
  }
  std::vector<double> starts;
  overpassesNear(cam_s, 60.0, s_.max_range, starts);
  for (double s0 : starts) {
    const double sm = s0 + 0.5 * s_.overpass_length;
    const double tm = 0.5 * (road_.leftEdge() + road_.rightEdge());
    const double half_w = 0.5 * (road_.rightEdge() - road_.leftEdge()) + s_.shoulder_width + 14.0;
    Box deck;
    const Eigen::Vector2d g = road_.point(sm, tm);
    deck.R = yawMatrix(road_.heading(sm));
    const double ground = road_.profile().height(sm);
    deck.centre = Eigen::Vector3d(g.x(), ground + s_.overpass_clearance + 0.7, g.y());
    deck.half = Eigen::Vector3d(half_w, 0.7, 0.5 * s_.overpass_length);
    deck.kind = BoxKind::kConcrete;
    deck.albedo = cv::Vec3d(0.55, 0.54, 0.52);
    deck.label = kLabelBuilding;
    out.push_back(deck);
    for (double t : {road_.leftEdge() - s_.shoulder_width - 1.5,
                     road_.rightEdge() + s_.shoulder_width + 1.5}) {
      Box p = deck;
      const Eigen::Vector2d q = road_.point(sm, t);
      p.centre = Eigen::Vector3d(q.x(), ground + 0.5 * s_.overpass_clearance, q.y());
      p.half = Eigen::Vector3d(0.6, 0.5 * s_.overpass_clearance, 0.35 * s_.overpass_length);
      out.push_back(p);
    }
  }
}

void SceneObjects::overpassesNear(double s, double before, double after,
                                  std::vector<double>& starts) const {
  starts.clear();
  if (s_.overpass_period <= 0) return;
  const double first = 60.0;  // the first deck starts 60 m into the road
  const double P = s_.overpass_period;
  for (double k = std::max(0.0, std::floor((s - before - first) / P)); first + k * P < s + after;
       ++k) {
    const double s0 = first + k * P;
    if (s0 + s_.overpass_length >= s - before) starts.push_back(s0);
  }
}

}  // namespace synth
}  // namespace rgbd_lane_detector
