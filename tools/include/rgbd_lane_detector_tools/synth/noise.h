/**
 * @file noise.h
 * @brief Deterministic, order-independent noise for the synthetic renderer.
 *
 * Every value is a pure function of its integer keys (seed, lattice coordinates, pixel, frame),
 * so images do not depend on thread scheduling and a seed reproduces a sequence bit for bit.
 * Layout randomness (vehicles, patches) uses std::mt19937 seeded from the scenario seed.
 */
#pragma once

#include <cstdint>

namespace rgbd_lane_detector {
namespace synth {

/// 32-bit integer hash (lowbias32 by C. Wellons) of one value.
inline uint32_t hash32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

/// Hash of several keys (order matters).
inline uint32_t hashKeys(uint32_t a, uint32_t b, uint32_t c = 0, uint32_t d = 0) {
  uint32_t h = hash32(a ^ 0x9e3779b9U);
  h = hash32(h ^ b);
  h = hash32(h ^ (c + 0x632be5abU));
  return hash32(h ^ (d + 0x85ebca6bU));
}

/// Uniform in [0, 1) from a hash value.
inline double unitFromHash(uint32_t h) {
  return (h >> 8) * (1.0 / 16777216.0);
}

/// Uniform in [0, 1) from keys.
inline double hashUniform(uint32_t a, uint32_t b, uint32_t c = 0, uint32_t d = 0) {
  return unitFromHash(hashKeys(a, b, c, d));
}

/// Approximately standard normal sample (sum of 8 uniforms) from keys.
double hashGaussian(uint32_t a, uint32_t b, uint32_t c = 0, uint32_t d = 0);

/**
 * @brief Smooth 2D value noise in [0, 1]: hashed lattice values, quintic interpolation.
 * @param[in] x,y coordinates in lattice units.
 * @param[in] seed selects an independent noise field.
 */
double valueNoise(double x, double y, uint32_t seed);

/**
 * @brief Fractal sum of value noise with footprint filtering (a cheap mip-map).
 *
 * Octave k has wavelength @p base_wavelength / 2^k. Octaves whose wavelength is below twice
 * the sample footprint fade to their mean (0.5), so distant texture does not alias.
 * @param[in] x,y position (m).
 * @param[in] base_wavelength wavelength of the first octave (m).
 * @param[in] octaves number of octaves.
 * @param[in] footprint size of the area one sample stands for (m).
 * @param[in] seed noise field.
 * @return value in [0, 1], mean 0.5.
 */
double fbm(double x, double y, double base_wavelength, int octaves, double footprint,
           uint32_t seed);

}  // namespace synth
}  // namespace rgbd_lane_detector
