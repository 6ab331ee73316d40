// The 16-column units FalsNormals solves with a mask (computeGeometric() with a mask): the
// units of a mask row with any pixel, their neighbours, runs of consecutive units, and G zeroed
// outside the mask.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace rgbd_lane_detector {
namespace fals {

/// With a mask, columns are chosen in units of 16 (a whole number of vectors on every target):
/// bit u of a row's unit set stands for the columns [16 u, 16 u + 16).
constexpr int kUnit = 16;

// Call fn(x0, x1) for each run of consecutive units in the set (nullptr: one run of every
// column), as the columns [x0, x1) clipped to the width W. Bits of units beyond W must be 0.
template <typename F>
void forEachRun(const uint64_t* units, int W, F&& fn) {
  if (!units) {
    fn(0, W);
    return;
  }
  const int n = (W + kUnit - 1) / kUnit;
  int u = 0;
  while (u < n) {
    const uint64_t rest = units[u / 64] >> (u % 64);
    if (rest == 0) {
      u = (u / 64 + 1) * 64;
      continue;
    }
    u += __builtin_ctzll(rest);
    int e = u;  // the first unit after the run
    while (e < n) {
      const int s = e % 64;
      const uint64_t word = units[e / 64] >> s;  // zeros shifted in at the top end the run there
      const int ones = word == ~uint64_t{0} ? 64 : __builtin_ctzll(~word);
      e += ones;
      if (ones < 64 - s) break;
    }
    e = std::min(e, n);
    fn(u * kUnit, std::min(W, e * kUnit));
    u = e;
  }
}

// The units of a mask row with any nonzero pixel.
inline void unitsOfRow(const uint8_t* m, int W, uint64_t* units) {
  const int n = (W + kUnit - 1) / kUnit;
  std::fill(units, units + (n + 63) / 64, uint64_t{0});
  for (int u = 0; u < n; ++u) {
    const int x0 = u * kUnit;
    bool any = false;
    if (x0 + kUnit <= W) {
      uint64_t a, b;
      std::memcpy(&a, m + x0, 8);
      std::memcpy(&b, m + x0 + 8, 8);
      any = (a | b) != 0;
    } else {
      for (int x = x0; x < W; ++x) any = any || m[x] != 0;
    }
    if (any) units[u / 64] |= uint64_t{1} << (u % 64);
  }
}

// dst = src with each unit's neighbours (one unit each side), within n units.
inline void dilateUnits(const uint64_t* src, int n, uint64_t* dst) {
  const int words = (n + 63) / 64;
  for (int j = 0; j < words; ++j) {
    const uint64_t left = (src[j] << 1) | (j > 0 ? src[j - 1] >> 63 : 0);
    const uint64_t right = (src[j] >> 1) | (j + 1 < words ? src[j + 1] << 63 : 0);
    dst[j] = src[j] | left | right;
  }
  if (n % 64) dst[words - 1] &= (uint64_t{1} << (n % 64)) - 1;
}

// G is 0 outside the mask: between the solved units, and at their pixels outside it.
inline void zeroOutsideMask(const uint8_t* m, const uint64_t* solved, int W, float* g) {
  int end = 0;
  forEachRun(solved, W, [&](int x0, int x1) {
    std::fill(g + end, g + x0, 0.f);
    for (int x = x0; x < x1; ++x)
      if (!m[x]) g[x] = 0.f;
    end = x1;
  });
  std::fill(g + end, g + W, 0.f);
}


}  // namespace fals
}  // namespace rgbd_lane_detector
