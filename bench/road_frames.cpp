#include "road_frames.h"

#include <cmath>
#include <cstdint>

namespace rgbd_lane_detector {
namespace bench {
namespace {

// Integer hash to [0, 1): texture anchored to road coordinates, stable across frames.
double hash01(int64_t a, int64_t b, int64_t c) {
  uint64_t h = static_cast<uint64_t>(a) * 0x9E3779B97F4A7C15ull ^
               static_cast<uint64_t>(b) * 0xC2B2AE3D27D4EB4Full ^
               static_cast<uint64_t>(c) * 0x165667B19E3779F9ull;
  h ^= h >> 29;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 32;
  return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

}  // namespace

Frame RoadFrame::frame() const {
  Frame f;
  f.colour = bgr;
  f.format = PixelFormat::kBgr8;
  f.depth = depth_mm;
  f.depth_scale = 0.001;
  f.intrinsics = K;
  return f;
}

void renderRoadFrame(int width, int height, int index, RoadFrame& out) {
  const double f = 266.37 * width / 640.0;
  out.K = Intrinsics{f, f, 0.5 * width, 0.5 * height};
  out.bgr.create(height, width, CV_8UC3);
  out.depth_mm.create(height, width, CV_16UC1);

  const double cam_h = 1.5, pitch = 0.08, lane = 3.6, marker = 0.15;
  const double travelled = 1.5 * index;
  const double sway = 0.3 * std::sin(0.21 * index);
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  // car: back face at 25 m ahead in the left lane, 1.8 m wide, 1.5 m high
  const double car_z = 25.0, car_x0 = -lane - 0.9 - sway, car_x1 = car_x0 + 1.8;

  // Depth holes as a sensor gives them: blobs (specular or dark patches, occlusion edges) of
  // 3 to 9 px radius at 640 x 380, about 0.3% of the road.
  struct Blob {
    double u, v, r2;
  };
  Blob blobs[12];
  const double s = width / 640.0;
  for (int i = 0; i < 12; ++i) {
    const double r = s * (3.0 + 6.0 * hash01(index, i, 11));
    blobs[i] = {width * hash01(index, i, 12), height * (0.45 + 0.55 * hash01(index, i, 13)), r * r};
  }
  auto inHole = [&](int u, int v) {
    for (const Blob& b : blobs)
      if ((u - b.u) * (u - b.u) + (v - b.v) * (v - b.v) <= b.r2) return true;
    return false;
  };

  for (int v = 0; v < height; ++v) {
    cv::Vec3b* c = out.bgr.ptr<cv::Vec3b>(v);
    uint16_t* d = out.depth_mm.ptr<uint16_t>(v);
    for (int u = 0; u < width; ++u) {
      // ray in the camera frame, then in the level frame (y down, z forward)
      const double rx = (u - out.K.cx) / f, ry = (v - out.K.cy) / f;
      const double ly = ry * cp + sp, lz = -ry * sp + cp;
      double grey = 180.0 + 40.0 * (1.0 - static_cast<double>(v) / height);  // sky
      double depth = 0.0;
      // road plane y = cam_h in the level frame
      if (ly > 1e-9) {
        const double t = cam_h / ly;  // along the ray (rx, ly, lz) in level coordinates
        const double X = rx * t, Z = lz * t;
        {
          // camera-frame z of the point is t (the ray has z = 1); no depth beyond 60 m
          if (Z <= 60.0) depth = t;
          const double F = Z + travelled, Xr = X + sway;
          const double cell = hash01(static_cast<int64_t>(std::floor(Xr * 8)),
                                     static_cast<int64_t>(std::floor(F * 8)), 7);
          grey = 72.0 + 34.0 * cell * cell + 6.0 * (hash01(u, v, index) - 0.5);
          const bool left = std::fabs(Xr + 0.5 * lane) <= 0.5 * marker;
          const bool right = std::fabs(Xr - 0.5 * lane) <= 0.5 * marker && std::fmod(F, 12.0) < 3.0;
          if (left || right) grey = 215.0 + 20.0 * (hash01(u, v, 3) - 0.5);
        }
      }
      // car back face: plane z = car_z in the level frame
      if (lz > 1e-9) {
        const double t = car_z / lz;
        const double X = rx * t, Y = ly * t;
        if (X >= car_x0 && X <= car_x1 && Y >= cam_h - 1.5 && Y <= cam_h &&
            (depth == 0.0 || t < depth)) {
          depth = t;
          grey = (Y < cam_h - 1.0) ? 60.0 : 140.0 + 30.0 * hash01(u / 4, v / 4, 9);
        }
      }
      const uint8_t g = cv::saturate_cast<uint8_t>(grey);
      c[u] = cv::Vec3b(g, g, g);
      if (depth > 0.0 && inHole(u, v)) depth = 0.0;
      if (depth > 0.0) depth += 0.001 * (hash01(u, v, 2000 + index) - 0.5);
      d[u] = static_cast<uint16_t>(std::lround(depth * 1000.0));
    }
  }
}

}  // namespace bench
}  // namespace rgbd_lane_detector
