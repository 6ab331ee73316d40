#include "rgbd_lane_detector_tools/synth/noise.h"

#include <algorithm>
#include <cmath>

namespace rgbd_lane_detector {
namespace synth {
namespace {

inline double quintic(double t) {
  return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// One hash round per lattice point: the noise dominates the renderer's cost.
inline double lattice(int64_t ix, int64_t iy, uint32_t seed) {
  return unitFromHash(hash32(static_cast<uint32_t>(ix) * 0x9e3779b1U ^
                             static_cast<uint32_t>(iy) * 0x85ebca77U ^ seed * 0xc2b2ae3dU));
}

}  // namespace

double hashGaussian(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
  // Irwin-Hall: the sum of 8 byte-uniforms, standardised (close to normal, no log/cos: the
  // colour noise runs for every pixel channel)
  const uint32_t h1 = hashKeys(a, b, c, d);
  const uint32_t h2 = hash32(h1 ^ 0x2545f491U);
  int sum = 0;
  for (int k = 0; k < 32; k += 8) sum += ((h1 >> k) & 0xff) + ((h2 >> k) & 0xff);
  // mean 8 * 127.5, variance 8 * (256^2 - 1) / 12
  return (sum - 1020.0) * (1.0 / 209.02);
}

double valueNoise(double x, double y, uint32_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const int64_t ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy);
  const double tx = quintic(x - fx), ty = quintic(y - fy);
  const double v00 = lattice(ix, iy, seed), v10 = lattice(ix + 1, iy, seed);
  const double v01 = lattice(ix, iy + 1, seed), v11 = lattice(ix + 1, iy + 1, seed);
  const double a = v00 + (v10 - v00) * tx;
  const double b = v01 + (v11 - v01) * tx;
  return a + (b - a) * ty;
}

double fbm(double x, double y, double base_wavelength, int octaves, double footprint,
           uint32_t seed) {
  double sum = 0.0, norm = 0.0, amp = 1.0, wavelength = base_wavelength;
  for (int k = 0; k < octaves; ++k) {
    // fade 1 -> 0 as the wavelength shrinks from 4 to 2 footprints
    const double ratio = wavelength / std::max(footprint, 1e-9);
    const double w = std::min(1.0, std::max(0.0, 0.5 * ratio - 1.0));
    if (w <= 0.0) {
      sum += amp * 0.5;
    } else {
      const double v = valueNoise(x / wavelength, y / wavelength, seed + 101u * k);
      sum += amp * (w * v + (1.0 - w) * 0.5);
    }
    norm += amp;
    amp *= 0.5;
    wavelength *= 0.5;
  }
  return norm > 0.0 ? sum / norm : 0.5;
}

}  // namespace synth
}  // namespace rgbd_lane_detector
