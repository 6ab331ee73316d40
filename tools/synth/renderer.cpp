#include "rgbd_lane_detector_tools/synth/renderer.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "frame_context.h"
#include "vehicle_view.h"
#include "rgbd_lane_detector_tools/synth/noise.h"
#include "scene_objects.h"

namespace rgbd_lane_detector {
namespace synth {
namespace {

constexpr double kDeg = M_PI / 180.0;

double smoothstep(double a, double b, double x) {
  const double t = std::min(1.0, std::max(0.0, (x - a) / (b - a)));
  return t * t * (3.0 - 2.0 * t);
}

// How far the camera is inside an overpass's shadow zone (0..1): drives the auto-exposure.
double underOverpass(const SceneObjects& objects, const SceneSettings& s, double cam_s) {
  std::vector<double> starts;
  objects.overpassesNear(cam_s, 30.0, 30.0, starts);
  double u = 0.0;
  for (double s0 : starts) {
    const double s1 = s0 + s.overpass_length;
    double v = 0.0;
    if (cam_s >= s0 && cam_s <= s1)
      v = 1.0;
    else if (cam_s < s0)
      v = smoothstep(s0 - 25.0, s0, cam_s);
    else
      v = 1.0 - smoothstep(s1, s1 + 10.0, cam_s);
    u = std::max(u, v);
  }
  return u;
}

// Quintic smoothstep (zero velocity and acceleration at both ends) and its derivative.
double quinticStep(double x) {
  x = std::min(1.0, std::max(0.0, x));
  return x * x * x * (10.0 + x * (-15.0 + 6.0 * x));
}
double quinticRate(double x) {
  if (x <= 0.0 || x >= 1.0) return 0.0;
  return 30.0 * x * x * (1.0 - x) * (1.0 - x);
}

// Lateral shift of the vehicle by lane changes at road position s and its derivative d/ds.
void laneChangeShift(const SceneSettings& s, double pos, double& shift, double& rate) {
  const double L = s.lane_change_length, D = s.lane_change_lanes * s.lane_width;
  const double out = (pos - s.lane_change_start) / L;
  shift = D * quinticStep(out);
  rate = D * quinticRate(out) / L;
  if (s.lane_change_return > 0) {
    const double back = (pos - s.lane_change_return) / L;
    shift -= D * quinticStep(back);
    rate -= D * quinticRate(back) / L;
  }
}

// Optical frame -> world rotation of a camera with yaw (positive right), pitch (positive down)
// and roll, on top of the y-down -> y-up flip of the optical frame.
Eigen::Matrix3d cameraRotation(double yaw, double pitch, double roll) {
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  const double cr = std::cos(roll), sr = std::sin(roll);
  Eigen::Matrix3d Ry, Rp, Rr;
  Ry << cy, 0, sy, 0, 1, 0, -sy, 0, cy;
  Rp << 1, 0, 0, 0, cp, -sp, 0, sp, cp;  // forward tilts down for positive pitch
  Rr << cr, -sr, 0, sr, cr, 0, 0, 0, 1;
  const Eigen::Matrix3d optical = Eigen::Vector3d(1, -1, 1).asDiagonal();  // y down -> y up
  return Ry * Rp * Rr * optical;
}

// Total-least-squares plane n . p + d = 0 of points, n oriented toward the origin (d > 0).
void fitPlane(const std::vector<Eigen::Vector3d>& pts, Eigen::Vector3d& n, double& d, double& rms) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : pts) c += p;
  c /= static_cast<double>(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) cov += (p - c) * (p - c).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  n = eig.eigenvectors().col(0).normalized();  // smallest eigenvalue first
  d = -n.dot(c);
  if (d < 0) {
    n = -n;
    d = -d;
  }
  double sum = 0.0;
  for (const auto& p : pts) sum += std::pow(n.dot(p) + d, 2);
  rms = std::sqrt(sum / pts.size());
}

constexpr double kLampHeight = 0.7;  // m, headlights above the road
constexpr double kLampAhead = 1.8;   // m, headlights ahead of the camera
}  // namespace

Eigen::Matrix3d baseFromWorld(double yaw, double pitch) {
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  Eigen::Matrix3d R;
  R.row(0) << sy * cp, sp, cy * cp;    // forward
  R.row(1) << -cy, 0.0, sy;            // left
  R.row(2) << -sy * sp, cp, -cy * sp;  // up
  return R;
}

Eigen::Isometry3d nominalMount(const SceneSettings& s) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = baseFromWorld(0.0, 0.0) * cameraRotation(0.0, s.pitch_deg * kDeg, s.roll_deg * kDeg);
  T.translation() = Eigen::Vector3d(0.0, 0.0, s.camera_height);
  return T;
}

Renderer::Renderer(const SceneSettings& settings)
    : settings_(settings), road_(settings_), objects_(new SceneObjects(settings_, road_)) {}

Renderer::~Renderer() = default;

Intrinsics Renderer::intrinsics() const {
  Intrinsics K;
  K.fx = K.fy = settings_.focal_1280 * settings_.width / 1280.0;
  K.cx = 0.5 * settings_.width;
  K.cy = 0.5 * settings_.height;
  return K;
}

CameraPose Renderer::pose(int index) const {
  const SceneSettings& s = settings_;
  CameraPose p;
  p.s = s.start_s + s.speed * index / s.fps;
  const double w = 2.0 * M_PI / s.drift_period;
  p.t = s.drift_amplitude * std::sin(w * p.s);
  double dtds = s.drift_amplitude * w * std::cos(w * p.s);
  if (s.lane_change_length > 0) {
    double shift, rate;
    laneChangeShift(s, p.s, shift, rate);
    p.t += shift;
    dtds += rate;
  }
  p.yaw = road_.heading(p.s) + std::atan(dtds / (1.0 - p.t * road_.curvature()));
  const double ww = 2.0 * M_PI / s.wobble_period;
  p.pitch = (s.pitch_deg + s.pitch_wobble_deg * std::sin(ww * p.s)) * kDeg;
  p.roll = (s.roll_deg + s.roll_wobble_deg * std::sin(ww * p.s / 1.37 + 1.0)) * kDeg;
  p.height = s.camera_height + 0.02 * std::sin(ww * p.s / 0.61);
  const Eigen::Vector2d g = road_.point(p.s, p.t);
  if (road_.profile().flat()) {
    p.position = Eigen::Vector3d(g.x(), p.height, g.y());
    p.base = Eigen::Vector3d(g.x(), 0.0, g.y());
    p.R_wc = cameraRotation(p.yaw, p.pitch, p.roll);
  } else {
    // the vehicle stands on the grade: pitched nose-up by it, the camera along its up axis
    p.vehicle_pitch = std::atan(road_.profile().grade(p.s));
    p.base = Eigen::Vector3d(g.x(), road_.profile().height(p.s), g.y());
    p.position = p.base + p.height * baseFromWorld(p.yaw, p.vehicle_pitch).row(2).transpose();
    p.R_wc = cameraRotation(p.yaw, p.pitch - p.vehicle_pitch, p.roll);
  }
  return p;
}

tools::FrameTruth Renderer::truth(int index) const {
  using tools::BoundaryLabel;
  const SceneSettings& s = settings_;
  const CameraPose p = pose(index);
  const Eigen::Matrix3d Rt = p.R_wc.transpose();
  const Eigen::Matrix3d Rb = baseFromWorld(p.yaw, p.vehicle_pitch);
  tools::FrameTruth f;
  f.index = index;
  // labels follow the lane under the camera
  const int lane = road_.laneAt(p.t);
  const LaneDef& ego = road_.lane(lane);
  const auto& defs = road_.boundaries();
  if (road_.profile().flat()) {
    f.normal = (Rt * Eigen::Vector3d::UnitY()).normalized();
    f.distance = p.position.y();
  } else {
    std::vector<Eigen::Vector3d> surface;
    const double left = defs[ego.left].offset, right = defs[ego.right].offset;
    for (double a = s.gt_plane_min; a <= s.gt_plane_max + 1e-9; a += s.gt_step)
      for (int j = 0; j <= 4; ++j)
        surface.push_back(
            Rt * (road_.surfacePoint(p.s + a, left + 0.25 * j * (right - left)) - p.position));
    fitPlane(surface, f.normal, f.distance, f.plane_rms);
  }
  // boundary index per label
  int index_of[tools::kNumBoundaryLabels] = {ego.left, ego.right, -1, -1, road_.roadEdgeLeft(),
                                             road_.roadEdgeRight()};
  if (lane > -road_.lanesLeft() && road_.lane(lane - 1).right == ego.left)
    index_of[2] = road_.lane(lane - 1).left;
  if (lane < road_.lanesRight() && road_.lane(lane + 1).left == ego.right)
    index_of[3] = road_.lane(lane + 1).right;
  const int n = static_cast<int>(std::floor((s.gt_max_distance - s.gt_min_distance) / s.gt_step +
                                            1e-9));
  for (int label = 0; label < tools::kNumBoundaryLabels; ++label) {
    const int b = index_of[label];
    bool taken = b < 0 || !defs[b].present;
    for (int other = 0; other < label && !taken; ++other) taken = index_of[other] == b;
    if (taken) continue;  // absent, or already labelled (ego, next, road edge in this order)
    const BoundaryDef& def = defs[b];
    tools::TrueBoundary tb;
    tb.label = static_cast<BoundaryLabel>(label);
    tb.kind = def.kind;
    tb.style = def.style;
    tb.colour = def.colour;
    tb.edge = def.edge;
    for (int k = 0; k <= n; ++k) {
      const double sk = p.s + s.gt_min_distance + k * s.gt_step;
      // intersections interrupt the lines (stop line to resumption) and the shoulders' edges
      if (road_.intersections() && (def.kind == BoundaryKind::kPaint ? road_.inLineGap(sk)
                                                                     : road_.inCrossing(sk)))
        continue;
      const Eigen::Vector3d w = road_.surfacePoint(sk, def.offset);
      tb.points.push_back(Rt * (w - p.position));
      tb.points_base.push_back(Rb * (w - p.base));
    }
    if (!tb.points.empty()) f.boundaries.push_back(std::move(tb));
  }
  f.syncEgoLines();
  f.lane_optional = road_.distanceToLineGap(p.s) <= s.gt_required_range;
  // vehicle frame and lane model
  f.has_vehicle_frame = true;
  f.base_to_camera.linear() = Rb * p.R_wc;
  f.base_to_camera.translation() = Rb * (p.position - p.base);
  const double left = defs[ego.left].offset, right = defs[ego.right].offset;
  const double centre = 0.5 * (left + right);
  f.lane.valid = f.has_lane;
  f.lane.width = right - left;
  f.lane.offset = centre - p.t;
  f.lane.heading = road_.heading(p.s) - p.yaw;
  const double k = road_.curvature();
  f.lane.curvature = k == 0.0 ? 0.0 : -k / (1.0 - centre * k);
  return f;
}

void Renderer::render(int index, RenderedFrame& out) const {
  const SceneSettings& s = settings_;
  const Intrinsics K = intrinsics();
  FrameContext ctx;
  ctx.settings = &settings_;
  ctx.road = &road_;
  ctx.index = index;
  ctx.seed = hashKeys(static_cast<uint32_t>(s.seed), 0x5eedU);
  ctx.pose = pose(index);
  ctx.fx = K.fx;
  ctx.fy = K.fy;
  ctx.cx = K.cx;
  ctx.cy = K.cy;
  const double el = s.sun_elevation_deg * kDeg, az = s.sun_azimuth_deg * kDeg;
  ctx.sun = Eigen::Vector3d(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
  ctx.ambient_light = cv::Vec3d(0.95, 0.98, 1.05) * s.ambient;
  ctx.sun_light = cv::Vec3d(1.05, 1.0, 0.92) * s.direct;
  ctx.gain = s.exposure *
             (1.0 + s.exposure_flicker * std::sin(2.0 * M_PI * index / s.flicker_period)) *
             (1.0 + s.exposure_adapt * underOverpass(*objects_, s, ctx.pose.s));
  if (s.headlights > 0.0) {
    const Eigen::Matrix3d Rb = baseFromWorld(ctx.pose.yaw, ctx.pose.vehicle_pitch);
    ctx.ahead = Rb.row(0).transpose();
    ctx.up = Rb.row(2).transpose();
    ctx.lamp = ctx.pose.base + kLampHeight * ctx.up + kLampAhead * ctx.ahead;
    ctx.headlight_light = cv::Vec3d(1.0, 0.98, 0.94) * s.headlights;  // LED low beams
  }
  ctx.flat_ground = road_.profile().flat() && road_.sideZoneHeight() == 0.0;
  ctx.urban = s.right_boundary != BoundaryType::kPaint || road_.hasTram() ||
              road_.intersections();
  ctx.rail_left = road_.leftEdge() - s.shoulder_width;
  ctx.rail_right = road_.rightEdge() + s.shoulder_width;
  objects_->boxesAt(index, ctx.pose.s, ctx.boxes);
  ctx.prepare(s.width, s.height);

  out.bgr.create(s.height, s.width, CV_8UC3);
  out.depth_true.create(s.height, s.width, CV_32FC1);
  out.labels.create(s.height, s.width, CV_8UC1);
  const int ss = s.supersample;
  const uint32_t noise_seed = hashKeys(static_cast<uint32_t>(s.seed), 0xc0105U);
  // footprint (m) of a sample spanning 1/n pixel: across the ray, widened at grazing angles
  const auto footprint = [&ctx](const Hit& hit, const Eigen::Vector3d& d, int n) {
    const double norm = d.norm();
    const double grazing = std::max(0.02, std::fabs(d.y()) / norm);
    return hit.lambda * norm / (ctx.fx * n) / std::sqrt(grazing);
  };
  // exposure, sensor noise, RGB -> BGR
  const auto writeColour = [&](const cv::Vec3d& sum, int x, int y, cv::Vec3b* bgr) {
    const double scale = 255.0 * ctx.gain / (ss * ss);
    const uint32_t pix = static_cast<uint32_t>(y * s.width + x);
    for (int c = 0; c < 3; ++c) {
      double v = sum[c] * scale;
      if (s.colour_noise > 0)
        v += s.colour_noise * hashGaussian(noise_seed, static_cast<uint32_t>(index), pix, c);
      bgr[x][2 - c] = cv::saturate_cast<uint8_t>(v);
    }
  };
  const Bonnet bonnet(s, K);
  cv::parallel_for_(cv::Range(0, s.height), [&](const cv::Range& rows) {
    Hit centre;
    std::vector<Hit> hits(ss * ss);
    for (int y = rows.start; y < rows.end; ++y) {
      cv::Vec3b* bgr = out.bgr.ptr<cv::Vec3b>(y);
      float* depth = out.depth_true.ptr<float>(y);
      uint8_t* label = out.labels.ptr<uint8_t>(y);
      for (int x = 0; x < s.width; ++x) {
        if (bonnet.hides(x, y)) {
          depth[x] = static_cast<float>(bonnet.depth(y));
          label[x] = kLabelCar;
        } else {
          ctx.trace(x, y, centre);
          depth[x] = centre.kind == Hit::kNone ? 0.f : static_cast<float>(centre.lambda);
          label[x] = ctx.label(centre);
        }
        if (bonnet.touches(x, y)) {  // the bonnet in front of (part of) this pixel
          cv::Vec3d sum(0, 0, 0);
          Hit h;
          for (int j = 0; j < ss; ++j) {
            for (int i = 0; i < ss; ++i) {
              const double u = x + (i + 0.5) / ss - 0.5, v = y + (j + 0.5) / ss - 0.5;
              if (bonnet.hides(u, v)) {
                sum += bonnet.colour(v, ctx);
              } else {
                ctx.trace(u, v, h);
                const Eigen::Vector3d d = ctx.rayDirection(u, v);
                sum += ctx.shade(h, d, footprint(h, d, ss));
              }
            }
          }
          writeColour(sum, x, y, bgr);
          continue;
        }
        // adaptive supersampling: shade once when every sample sees the same thing
        const uint32_t key = ss > 1 ? ctx.sampleKey(centre) : 0;
        bool uniform = true;
        for (int j = 0; j < ss && ss > 1; ++j) {
          for (int i = 0; i < ss; ++i) {
            Hit& h = hits[j * ss + i];
            ctx.trace(x + (i + 0.5) / ss - 0.5, y + (j + 0.5) / ss - 0.5, h);
            uniform = uniform && ctx.sampleKey(h) == key;
          }
        }
        cv::Vec3d sum(0, 0, 0);
        if (uniform) {
          const Eigen::Vector3d d = ctx.rayDirection(x, y);
          sum = ctx.shade(centre, d, footprint(centre, d, 1)) * static_cast<double>(ss * ss);
        } else {
          for (int j = 0; j < ss; ++j) {
            for (int i = 0; i < ss; ++i) {
              const Eigen::Vector3d d =
                  ctx.rayDirection(x + (i + 0.5) / ss - 0.5, y + (j + 0.5) / ss - 0.5);
              const Hit& h = hits[j * ss + i];
              sum += ctx.shade(h, d, footprint(h, d, ss));
            }
          }
        }
        writeColour(sum, x, y, bgr);
      }
    }
  });

  // depth sensor model on the exact depth
  out.depth_true.copyTo(out.depth);
  const LidarRings lidar(s, K);
  const uint32_t dseed =
      hashKeys(static_cast<uint32_t>(s.seed), 0xde97U, static_cast<uint32_t>(index));
  double hole_threshold = 2.0;
  cv::Mat holes;
  if (s.depth_holes > 0) {
    holes.create(s.height, s.width, CV_32FC1);
    const double ox = 1000.0 * hashUniform(dseed, 1), oy = 1000.0 * hashUniform(dseed, 2);
    for (int y = 0; y < s.height; ++y) {
      float* h = holes.ptr<float>(y);
      for (int x = 0; x < s.width; ++x)
        h[x] = static_cast<float>(fbm((x + ox) / 1.6, y + oy, 40.0, 3, 1.0, dseed));
    }
    // threshold at the quantile that gives the requested coverage
    std::vector<float> sample;
    for (int y = 0; y < s.height; y += 3)
      for (int x = 0; x < s.width; x += 3) sample.push_back(holes.at<float>(y, x));
    const size_t k =
        std::min(sample.size() - 1, static_cast<size_t>((1.0 - s.depth_holes) * sample.size()));
    std::nth_element(sample.begin(), sample.begin() + k, sample.end());
    hole_threshold = sample[k];
  }
  for (int y = 0; y < s.height; ++y) {
    float* d = out.depth.ptr<float>(y);
    const float* h = holes.empty() ? nullptr : holes.ptr<float>(y);
    for (int x = 0; x < s.width; ++x) {
      if (d[x] <= 0.f) continue;
      const uint32_t pix = static_cast<uint32_t>(y * s.width + x);
      if (s.lidar_beams > 0) {  // a roof LiDAR: returns on its rings only, none from the bonnet
        if (bonnet.hides(x, y) || !lidar.hits(ctx.rayDirection(x, y))) {
          d[x] = 0.f;
          continue;
        }
        if (s.lidar_range_noise > 0.0)
          d[x] = static_cast<float>(std::max(
              0.01, d[x] + s.lidar_range_noise * hashGaussian(dseed, pix, 5) *
                               ctx.rayDirection(x, y).normalized().dot(
                                   ctx.pose.R_wc.col(2))));  // range noise along the ray, as z
      }
      if (d[x] > s.depth_range || (h && h[x] >= hole_threshold) ||
          (s.depth_dropout > 0 && hashUniform(dseed, pix, 3) < s.depth_dropout)) {
        d[x] = 0.f;
        continue;
      }
      if (s.depth_noise_k > 0) {
        const double z = d[x];
        d[x] = static_cast<float>(
            std::max(0.01, z + s.depth_noise_k * z * z * hashGaussian(dseed, pix, 4)));
      }
    }
  }
}

}  // namespace synth
}  // namespace rgbd_lane_detector
