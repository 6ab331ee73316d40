// Helpers shared by the fuzz targets: interesting values drawn from the fuzzer's bytes.
#pragma once

#include <cstdint>
#include <limits>

#include <fuzzer/FuzzedDataProvider.h>

namespace rgbd_lane_detector {
namespace fuzz {

/// A double that is often a boundary value (0, NaN, inf, huge, tiny, negative), else any.
inline double interestingDouble(FuzzedDataProvider& fdp, double typical) {
  static const double kValues[] = {0.0,
                                   -0.0,
                                   1.0,
                                   -1.0,
                                   0.5,
                                   1e-12,
                                   1e12,
                                   1e300,
                                   -1e300,
                                   std::numeric_limits<double>::denorm_min(),
                                   std::numeric_limits<double>::max(),
                                   std::numeric_limits<double>::lowest(),
                                   std::numeric_limits<double>::quiet_NaN(),
                                   std::numeric_limits<double>::infinity(),
                                   -std::numeric_limits<double>::infinity(),
                                   2147483648.0,
                                   -2147483649.0};
  constexpr int kCount = sizeof(kValues) / sizeof(kValues[0]);
  const int pick = fdp.ConsumeIntegralInRange<int>(0, kCount + 2);
  if (pick < kCount) return kValues[pick];
  if (pick == kCount) return typical;
  if (pick == kCount + 1) return typical * fdp.ConsumeFloatingPointInRange<double>(0.0, 4.0);
  return fdp.ConsumeFloatingPoint<double>();
}

/// A float depth sample: often NaN, inf, negative, zero, huge or tiny, else a plausible range.
inline float interestingDepth(FuzzedDataProvider& fdp) {
  static const float kValues[] = {std::numeric_limits<float>::quiet_NaN(),
                                  std::numeric_limits<float>::infinity(),
                                  -std::numeric_limits<float>::infinity(),
                                  -1.0f,
                                  0.0f,
                                  1e30f,
                                  std::numeric_limits<float>::max(),
                                  1e-30f,
                                  std::numeric_limits<float>::denorm_min(),
                                  0.19f,
                                  120.5f};
  constexpr int kCount = sizeof(kValues) / sizeof(kValues[0]);
  const int pick = fdp.ConsumeIntegralInRange<int>(0, kCount * 2);
  if (pick < kCount) return kValues[pick];
  return fdp.ConsumeFloatingPointInRange<float>(0.0f, 40.0f);
}

}  // namespace fuzz
}  // namespace rgbd_lane_detector
