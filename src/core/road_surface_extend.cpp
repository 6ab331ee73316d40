// The road surface extended toward the camera (RoadSurface::extendToCamera()): where a column's
// nearest depth is road, the road continues down to the image's bottom rows, which LiDAR and
// stereo often leave empty.
#include "rgbd_lane_detector/road_surface.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "rgbd_lane_detector/depth_points.h"
#include "rgbd_lane_detector/geometry.h"

namespace rgbd_lane_detector {
namespace {

// No number among the n floats at p.
bool noNumber(const float* p, int n) {
  int numbers = 0;
  for (int i = 0; i < n; ++i) numbers += p[i] == p[i];
  return numbers == 0;
}

}  // namespace

int RoadSurface::extendToCamera(cv::Mat& points, const cv::Range& rows, const Intrinsics& K,
                                const PlaneEstimate& plane, double band0, double growth,
                                cv::Mat& filled, const cv::Mat& col_map, const cv::Mat& row_map) {
  filled.create(points.size(), CV_8UC1);
  for (int y = 0; y < filled.rows; ++y)  // (cv::Mat::setTo allocates)
    std::memset(filled.ptr<uint8_t>(y), 0, filled.cols);
  if (!plane.valid || points.type() != CV_32FC3) return 0;
  const int r0 = std::max(rows.start, 0);
  const int r1 = std::min(rows.end, points.rows);
  const int w = points.cols;
  const int* cm = col_map.empty() ? nullptr : col_map.ptr<int>();
  const int* rm = row_map.empty() ? nullptr : row_map.ptr<int>();
  // the nearest (lowest) row with depth of every column, rows read in memory order (a column
  // walk strides a whole row per pixel: on sparse LiDAR depth it cost 10 ms at 1600x900), each
  // at the columns still open only; a row without a number at all (by the depth block map, else
  // by a test the compiler vectorises) and blocks without depth are passed over
  fill_from_.assign(w, -1);
  fill_open_.resize(w);
  for (int x = 0; x < w; ++x) fill_open_[x] = x;
  int open = w;
  const int nb = (w + kDepthBlock - 1) / kDepthBlock;
  for (int y = r1 - 1; y >= r0 && open > 0; --y) {
    const float* row = points.ptr<float>(y);
    const uint8_t* blocks = blockRow(points, y);
    if (blocks ? std::none_of(blocks, blocks + nb, [](uint8_t b) { return b != 0; })
               : open > w / 4 && noNumber(row, 3 * w))
      continue;
    int k = 0;
    for (int i = 0; i < open; ++i) {
      const int x = fill_open_[i];
      if ((blocks && !blocks[x / kDepthBlock]) || std::isnan(row[3 * x + 2]))
        fill_open_[k++] = x;
      else
        fill_from_[x] = y;
    }
    open = k;
  }
  // the first row to fill: below a nearest depth on the road; none without depth, below
  // something else (a car, a wall) or with nothing missing below it
  int first = r1;
  for (int x = 0; x < w; ++x) {
    const int y = fill_from_[x];
    fill_from_[x] = r1;
    if (y < r0 || y == r1 - 1) continue;
    const cv::Vec3f& q = points.at<cv::Vec3f>(y, x);
    const double z = q[2];
    const double h = planeDistance(plane, Eigen::Vector3f(q[0], q[1], q[2]));
    if (!(std::fabs(h) <= band0 + growth * z * z)) continue;  // not road: nothing to extend
    fill_from_[x] = y + 1;
    first = std::min(first, y + 1);
  }
  // each pixel's ray K.ray(u, v) from its column's and its row's part, and rayPlaneDepth()
  // written out: the same operations in the same order (n . ray is (nx rx + ny ry) + nz 1)
  // (the products nx rx per column and ny ry per row, once)
  const double nx = plane.normal.x(), ny = plane.normal.y(), nz = plane.normal.z();
  fill_rx_.resize(2 * w);
  for (int x = 0; x < w; ++x) {
    fill_rx_[2 * x] = K.ray(cm ? cm[x] : x, 0.0).x();
    fill_rx_[2 * x + 1] = nx * fill_rx_[2 * x];
  }
  int count = 0;
  for (int v = first; v < r1; ++v) {
    const double ry = K.ray(0.0, rm ? rm[v] : v).y(), ny_ry = ny * ry;
    cv::Vec3f* row = points.ptr<cv::Vec3f>(v);
    uint8_t* mark = filled.ptr<uint8_t>(v);
    for (int x = 0; x < w; ++x) {
      if (v < fill_from_[x]) continue;
      const double den = (fill_rx_[2 * x + 1] + ny_ry) + nz * 1.0;
      if (!(den < -1e-9)) continue;  // the ray misses the road plane
      // (no depth here: the column's nearest depth is above; the point is not read)
      cv::Vec3f& p = row[x];
      const double t = -plane.distance / den;
      p = cv::Vec3f(static_cast<float>(fill_rx_[2 * x] * t), static_cast<float>(ry * t),
                    static_cast<float>(t));
      mark[x] = 255;
      ++count;
    }
  }
  return count;
}

}  // namespace rgbd_lane_detector
