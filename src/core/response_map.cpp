#include "rgbd_lane_detector/response_map.h"

#include <algorithm>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define RLD_RM_AVX2 1
#endif

#include "rgbd_lane_detector/template_matching.h"  // simdLevel()

namespace rgbd_lane_detector {

void geometricMap(const cv::Mat& points, const cv::Mat& normals, const Params& p,
                  const cv::Range& rows, cv::Mat& G) {
  if (G.size() != points.size() || G.type() != CV_32FC1) {
    G.create(points.size(), CV_32FC1);
    G.setTo(0);
  }
  const int r0 = std::max(rows.start, 0), r1 = std::min(rows.end, points.rows);
  const float ux = static_cast<float>(p.up_x), uy = static_cast<float>(p.up_y),
              uz = static_cast<float>(p.up_z);
  for (int y = r0; y < r1; ++y) {
    const float* pt = points.ptr<float>(y);
    const float* n = normals.ptr<float>(y);
    float* g = G.ptr<float>(y);
    for (int x = 0; x < points.cols; ++x, pt += 3, n += 3) {
      const float dot = n[0] * ux + n[1] * uy + n[2] * uz;
      g[x] = geometricValue(pt[2], dot, y, points.rows, p);
    }
  }
}

namespace {

#ifdef RLD_RM_AVX2
__attribute__((target("avx2"))) int fuseAvx2(const float* m, const float* g, float tau, int n,
                                             float* r) {
  const __m256 t = _mm256_set1_ps(tau);
  int x = 0;
  for (; x + 8 <= n; x += 8) {
    const __m256 mv = _mm256_loadu_ps(m + x);
    const __m256 below = _mm256_cmp_ps(mv, t, _CMP_LT_OQ);
    _mm256_storeu_ps(r + x, _mm256_blendv_ps(_mm256_add_ps(mv, _mm256_loadu_ps(g + x)), mv, below));
  }
  return x;
}

__attribute__((target("avx2"))) float rowMaxAvx2(const float* r, int n, float m, int& done) {
  __m256 v = _mm256_set1_ps(m);
  int x = 0;
  for (; x + 8 <= n; x += 8) v = _mm256_max_ps(v, _mm256_loadu_ps(r + x));
  const __m128 h = _mm_max_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
  const __m128 q = _mm_max_ps(h, _mm_movehl_ps(h, h));
  done = x;
  return _mm_cvtss_f32(_mm_max_ss(q, _mm_shuffle_ps(q, q, 1)));
}

__attribute__((target("avx2"))) int rowFindAvx2(const float* r, int n, float m, int& done) {
  const __m256 v = _mm256_set1_ps(m);
  int x = 0;
  for (; x + 8 <= n; x += 8) {
    const int hit = _mm256_movemask_ps(_mm256_cmp_ps(_mm256_loadu_ps(r + x), v, _CMP_EQ_OQ));
    if (hit) return x + __builtin_ctz(static_cast<unsigned>(hit));
  }
  done = x;
  return -1;
}
#endif

}  // namespace

void maxLocation(const cv::Mat& R, double& max_value, cv::Point& max_location) {
  CV_Assert(R.type() == CV_32FC1);
  max_location = cv::Point(-1, -1);
  max_value = 0.0;
  if (R.empty()) return;
#ifdef RLD_RM_AVX2
  const bool avx2 = simdLevel() >= 1;
#endif
  // the maximum, then its first occurrence (cv::minMaxLoc keeps the first on ties)
  float m = R.at<float>(0, 0);
  for (int y = 0; y < R.rows; ++y) {
    const float* r = R.ptr<float>(y);
    int x = 0;
#ifdef RLD_RM_AVX2
    if (avx2) m = rowMaxAvx2(r, R.cols, m, x);
#endif
    for (; x < R.cols; ++x) m = std::max(m, r[x]);
  }
  max_value = m;
  for (int y = 0; y < R.rows; ++y) {
    const float* r = R.ptr<float>(y);
    int x = 0;
#ifdef RLD_RM_AVX2
    if (avx2) {
      const int at = rowFindAvx2(r, R.cols, m, x);
      if (at >= 0) {
        max_location = cv::Point(at, y);
        return;
      }
    }
#endif
    for (; x < R.cols; ++x) {
      if (r[x] == m) {
        max_location = cv::Point(x, y);
        return;
      }
    }
  }
}

void fuseResponse(const cv::Mat& M, const cv::Mat& G, float tau_g, const cv::Range& rows,
                  cv::Mat& R) {
  if (R.data != M.data && (R.size() != M.size() || R.type() != CV_32FC1)) {
    R.create(M.size(), CV_32FC1);
    R.setTo(0);
  }
  const int r0 = std::max(rows.start, 0), r1 = std::min(rows.end, M.rows);
#ifdef RLD_RM_AVX2
  const bool avx2 = simdLevel() >= 1;
#endif
  for (int y = r0; y < r1; ++y) {
    const float* m = M.ptr<float>(y);
    const float* g = G.ptr<float>(y);
    float* r = R.ptr<float>(y);
    int x = 0;
#ifdef RLD_RM_AVX2
    if (avx2) x = fuseAvx2(m, g, tau_g, M.cols, r);
#endif
    for (; x < M.cols; ++x) r[x] = fusedValue(m[x], g[x], tau_g);
  }
}

}  // namespace rgbd_lane_detector
