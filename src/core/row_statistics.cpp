#include "row_statistics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace rgbd_lane_detector {
namespace {
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Counts of grey values (0-255) in 256 bins and in 16 coarse bins of 16 grey levels: the value of
// a rank is found in the coarse bins first, then in the 16 of its bin (at most 32 bins looked at,
// not the up to 255 of a walk up from the lowest value: a row's grey spreads over a hundred
// levels, its dark pixels far below its median).
class GreyCounts {
 public:
  void add(uint8_t g) {
    ++fine_[g];
    ++coarse_[g >> 4];
  }
  // The @p rank-th lowest value counted (from 1; at most the values counted).
  int valueOfRank(size_t rank) const {
    size_t seen = 0;
    int c = 0;
    while (c < 15 && seen + coarse_[c] < rank) seen += coarse_[c++];
    int g = 16 * c;
    while (g < 255 && (seen += fine_[g]) < rank) ++g;
    return g;
  }

 private:
  std::array<uint16_t, 256> fine_{};  // (a row's values: far fewer than 65536)
  std::array<uint32_t, 16> coarse_{};
};

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
  GreyCounts counts;
  for (float g : v) counts.add(static_cast<uint8_t>(g));
  return static_cast<float>(counts.valueOfRank(v.size() / 2 + 1));  // nth_element's v.size() / 2
}

float greyMedian(const uint8_t* a, int na, const uint8_t* b, int nb) {
  const int n = std::max(na, 0) + std::max(nb, 0);
  if (n == 0) return kNaN;
  GreyCounts counts;
  for (int i = 0; i < na; ++i) counts.add(a[i]);
  for (int i = 0; i < nb; ++i) counts.add(b[i]);
  return static_cast<float>(counts.valueOfRank(n / 2 + 1));  // the sorted values' [n / 2]
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
