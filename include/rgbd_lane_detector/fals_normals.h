/**
 * @file fals_normals.h
 * @brief Stage 3: FALS surface normals (Badino et al. 2011), and the geometric map G fused.
 */
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/**
 * @brief Fast approximate least-squares normals from an organised point matrix.
 *
 * For each pixel and its w x w window: M = sum v_i v_i^T over unit rays (intrinsics only),
 * b = sum v_i / r_i over the ranges, n = M^-1 b, normalised and oriented toward the camera
 * (n . p < 0). A window with invalid points uses its valid pixels only; fewer than 3 of them,
 * or (when some are missing) valid pixels all in one row or one column, gives a NaN normal.
 *
 * Computed exactly, but not as written: with w = ((u - cx) / fx, (v - cy) / fy, 1) the pixel's
 * ray, k = 1 / |w|^2 and (du, dv) a window pixel's offset from the centre, M = B Q B^T and
 * b = B s where B = [w_centre, e_x / fx, e_y / fy], Q = sum k (1, du, dv)(1, du, dv)^T and
 * s = sum (k / z)(1, du, dv) (v / r = k w / z for a point on its ray). So n = B^-T Q^-1 s.
 * Q is well conditioned (about diag(25, 50, 50) k for 5x5) where M has a condition number near
 * 1e5. For windows without missing pixels Q depends on the pixel only: adj(Q) is precomputed
 * (in double) and s is a box and moment filter (separable, float). Windows with missing pixels
 * (holes, the edge of the valid depth) build Q from their own moments; where their valid pixels
 * form a thin crescent and Q is ill conditioned (det Q <= K0 Kuu Kvv / 4) they are solved
 * directly in double.
 */
class FalsNormals {
 public:
  /**
   * @brief Prepare the per-pixel tables for an image geometry (no-op when unchanged).
   * @param[in] size image size.
   * @param[in] K intrinsics of the points' image (after any resampling).
   * @param[in] window window side, 3, 5 or 7.
   * @param[in] col_map optional CV_32SC1 1xW source column of each column (resampled images).
   * @param[in] row_map optional CV_32SC1 1xH source row of each row.
   */
  void configure(const cv::Size& size, const Intrinsics& K, int window,
                 const cv::Mat& col_map = cv::Mat(), const cv::Mat& row_map = cv::Mat());

  /**
   * @brief Normals of the rows @p rows (windows may read neighbouring rows).
   * @param[in] points CV_32FC3 organised points (NaN = invalid) of the configured size.
   * @param[in] rows output rows to compute.
   * @param[out] normals CV_32FC3 unit normals toward the camera, NaN where unknown.
   */
  void compute(const cv::Mat& points, const cv::Range& rows, cv::Mat& normals);

  /**
   * @brief The geometric map G (Eq. 2, geometricValue()) of the rows @p rows straight from the
   * normals, which are kept only when @p normals is given (one pass, no normal image).
   * @param[in] points CV_32FC3 organised points of the configured size.
   * @param[in] rows rows to compute; other rows of @p G are 0 when G is (re)allocated.
   * @param[in] p alpha, beta, T_D, depth term and up axis are read.
   * @param[out] G CV_32FC1.
   * @param[out] normals optional CV_32FC3 normals as compute() gives them.
   */
  void computeGeometric(const cv::Mat& points, const cv::Range& rows, const Params& p, cv::Mat& G,
                        cv::Mat* normals = nullptr);

  /**
   * @brief G of the rows @p rows at the pixels of a mask only (where G enters R, fusionMask()),
   * 0 at the others: the windows are summed and solved only in the 16-column units that hold
   * mask pixels. Where the mask is set G has the same bits as the overload without a mask.
   * @param[in] points CV_32FC3 organised points of the configured size.
   * @param[in] rows rows to compute; other rows of @p G are 0 when G is (re)allocated.
   * @param[in] p alpha, beta, T_D, depth term and up axis are read.
   * @param[in] mask CV_8UC1 of the configured size: G where nonzero.
   * @param[out] G CV_32FC1.
   */
  void computeGeometric(const cv::Mat& points, const cv::Range& rows, const Params& p,
                        const cv::Mat& mask, cv::Mat& G);

  int window() const { return window_; }

 private:
  struct Output;
  /// The output of computeGeometric() (G allocated and zeroed when new, constants of @p p).
  Output geometricOutput(const Params& p, cv::Mat& G) const;
  void run(const cv::Mat& points, const cv::Range& rows, const Output& out);
  void ensureTable(const cv::Range& rows);
  /// Prepared row y over the columns of @p units (nullptr: every column; see run()).
  void prepareRow(const cv::Mat& points, int y, const uint64_t* units, float* kv, float* t,
                  float* c, float* z, uint64_t* bad) const;
  bool solveWindow(int x, int y, const float* const* kv, const float* const* t,
                   const float* const* c, float n[3]);

  cv::Size size_;
  Intrinsics K_;
  int window_ = 0;
  cv::Mat col_map_, row_map_;
  bool uniform_ = true;  ///< maps are x -> a + step x: the fast separable path applies
  float step_u_ = 1.f, step_v_ = 1.f;
  std::vector<float> ax_, ay_;      ///< ray coordinates (u - cx) / fx per column, per row
  std::vector<int> src_u_, src_v_;  ///< source pixel of each column, row
  std::vector<float> ncols_;        ///< window columns inside the image, per column
  cv::Mat k_;                       ///< CV_32FC1 1 / |w|^2 per pixel
  cv::Mat table_;  ///< CV_32FC1 6 planes of the rows table_rows_: adj(Q), whole windows
  cv::Range table_rows_;
  cv::Mat prep_;                ///< CV_32FC1 ring of prepared rows: k valid, k / z, valid, z
  std::vector<uint64_t> bad_;   ///< bit per ring slot and 8-pixel block: invalid pixels
  std::vector<uint64_t> near_;  ///< bit per block: missing pixels within the windows' reach
  cv::Mat vert_;                ///< CV_32FC1 vertical sums of one row (8 padded planes)
  std::vector<int> slow_;       ///< columns of the current row left to the exact path
  static constexpr int kColumnSums = 8;
  std::vector<double> column_;   ///< exact path: per column, sums over the window's rows
  std::vector<int> column_row_;  ///< row whose sums column_ holds, per column
  std::vector<double> exact_cols_;  ///< vector exact path: column sums, 8 planes padded by h
  std::vector<double> exact_su_;    ///< src_u_ padded by h (clamped) each side
  std::vector<float> exact_n_;      ///< its unit normals (3 planes) where normals are wanted
  std::vector<uint8_t> exact_ok_;   ///< and whether each column has one
  // with a mask (run()): bits of 16-column units per output row
  std::vector<uint64_t> solve_units_;  ///< units holding mask pixels
  std::vector<uint64_t> read_units_;   ///< and their neighbours, whose vertical sums they read
  std::vector<uint64_t> prep_units_;   ///< units of the row being prepared
};

/**
 * @brief FALS normal of one pixel, straight from the definition in double precision (M and b
 * summed over the valid pixels of its window): for the few pixels where a normal is needed
 * without computing a whole normal image.
 * @param[in] points CV_32FC3 organised points (NaN = invalid).
 * @param[in] x,y pixel.
 * @param[in] window window side (3, 5 or 7).
 * @param[in] K intrinsics of the source pixels.
 * @param[in] col_map,row_map optional CV_32SC1 source column / row of each pixel.
 * @param[out] n unit normal toward the camera.
 * @return false when the window has fewer than 3 valid pixels or they lie in one row or column.
 */
bool falsNormalAt(const cv::Mat& points, int x, int y, int window, const Intrinsics& K,
                  const cv::Mat& col_map, const cv::Mat& row_map, float n[3]);

}  // namespace rgbd_lane_detector
