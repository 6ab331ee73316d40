#include "row_statistics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace rgbd_lane_detector {
namespace {
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
}  // namespace

float median(std::vector<float>& v) {
  if (v.empty()) return kNaN;
  const size_t n = v.size(), k = n / 2;
  // up to 64 finite samples: the element whose rank range holds k, found by
  // counting (branch-free, vectorised; 2x faster than std::nth_element at 17-48 samples, which
  // partitions by unpredictable branches); the same element nth_element puts at k
  if (n > 16 && n <= 64 &&
      std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); })) {
    const float* a = v.data();
    for (size_t i = 0; i < n; ++i) {
      size_t below = 0, up_to = 0;
      for (size_t j = 0; j < n; ++j) {
        below += a[j] < a[i];
        up_to += a[j] <= a[i];
      }
      if (below <= k && k < up_to) return a[i];
    }
  }
  auto mid = v.begin() + k;
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

float greyMedian(std::vector<float>& v) {
  if (v.size() <= 16) return median(v);
  std::array<uint16_t, 256> count{};
  int b = 255;  // counted from the lowest value on (a road's grey is far above 0)
  for (float g : v) {
    const uint8_t k = static_cast<uint8_t>(g);
    ++count[k];
    b = std::min<int>(b, k);
  }
  const size_t rank = v.size() / 2 + 1;  // nth_element's v.size() / 2, counted from 1
  size_t seen = 0;
  while (b < 255 && (seen += count[b]) < rank) ++b;  // (b < 255: counts wrap past 65535 values)
  return static_cast<float>(b);
}

float greyMedian(const uint8_t* a, int na, const uint8_t* b, int nb) {
  const int n = std::max(na, 0) + std::max(nb, 0);
  if (n == 0) return kNaN;
  std::array<uint16_t, 256> count{};
  int lowest = 255;
  for (int i = 0; i < na; ++i) ++count[a[i]], lowest = std::min<int>(lowest, a[i]);
  for (int i = 0; i < nb; ++i) ++count[b[i]], lowest = std::min<int>(lowest, b[i]);
  const int rank = n / 2 + 1;  // the sorted values' [n / 2], counted from 1
  int seen = 0, g = lowest;
  while (g < 255 && (seen += count[g]) < rank) ++g;  // (g < 255: counts wrap past 65535 values)
  return static_cast<float>(g);
}

bool stepInMostRows(std::vector<float>& steps, float least, int min_rows, double share,
                    float& step) {
  step = kNaN;
  if (static_cast<int>(steps.size()) < min_rows) return false;
  const auto high =
      std::count_if(steps.begin(), steps.end(), [least](float h) { return h >= least; });
  if (high >= share * static_cast<double>(steps.size())) step = median(steps);
  return true;
}

}  // namespace rgbd_lane_detector
