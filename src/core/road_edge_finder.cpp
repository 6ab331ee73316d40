#include "rgbd_lane_detector/road_edge_finder.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rgbd_lane_detector/fals_normals.h"

namespace rgbd_lane_detector {
namespace {

constexpr double kRoadBand = 0.04;       // m: a point this near the plane is road
constexpr int kRoadRun = 3;              // road points a row needs inside its edge
constexpr int kRaisedRun = 3;            // raised points that make the step
constexpr double kLineGate = 0.15;       // m: a row's edge this near the side's line is on it
constexpr int kMinRows = 8;              // rows on the line that make an edge
constexpr double kRowSpacing = 0.25;     // m of road between the rows searched at least
constexpr double kColumnSpacing = 0.04;  // m across the road between the columns searched
constexpr double kMinLength = 3.0;       // m of road along which they lie
constexpr double kMaxHeading = 0.35;     // rad: an edge runs along the road
constexpr float kSidewalkCheck = 0.3f;   // m beyond a step that must stay at a sidewalk's height
constexpr float kMaxCamber = 0.15f;      // m: road this far below or above the plane (camber)
constexpr float kCamberGain = 0.3f;      // gain of the road's running height along a row
constexpr float kLevelNear = 0.15f;      // m beyond a step where its top's normal is read ...
constexpr float kLevelFar = 0.6f;        // ... at the latest
constexpr double kLevelAngle = 0.44;     // rad (25 deg): a sidewalk's top is that level at least
constexpr float kRiseReach = 0.6f;       // m across which a rolled kerb or a verge rises at most
constexpr float kFootBand = 0.01f;       // m above the lowest point that is still the foot

// The surface from column @p x0 outward (step @p step) up to kSidewalkCheck metres beyond the
// lateral position @p x_edge: every measured point at most @p max_step above the plane.
bool sidewalkBeyond(const cv::Vec3f* row, const uint8_t* fill, int x0, int step, int cols,
                    float x_edge, const Eigen::Vector3f& n, float d, float max_step) {
  for (int x = x0; x >= 0 && x < cols; x += step) {
    if (fill && fill[x]) continue;
    const cv::Vec3f& p = row[x];
    if (std::isnan(p[2])) continue;
    if (std::fabs(p[0] - x_edge) > kSidewalkCheck) break;
    if (n.x() * p[0] + n.y() * p[1] + n.z() * p[2] + d > max_step) return false;
  }
  return true;
}

// The surface a little beyond a step at column @p x0 of row @p y (the first measured point
// kLevelNear..kLevelFar metres beyond it) is level: its normal within kLevelAngle of the road's.
// True also where the depth is too sparse to tell.
bool levelBeyond(const cv::Mat& points, const cv::Mat* filled, int x0, int y, int step,
                 const Intrinsics& K, const cv::Mat& col_map, const cv::Mat& row_map,
                 const PlaneEstimate& plane, const RoadEdgeSettings& s) {
  const cv::Vec3f* row = points.ptr<cv::Vec3f>(y);
  const uint8_t* fill = filled ? filled->ptr<uint8_t>(y) : nullptr;
  const float x_edge = row[x0][0];
  for (int x = x0 + step; x >= 0 && x < points.cols; x += step) {
    if ((fill && fill[x]) || std::isnan(row[x][2])) continue;
    const float off = std::fabs(row[x][0] - x_edge);
    if (off < kLevelNear) continue;
    if (off > kLevelFar) break;
    float nrm[3];
    if (!falsNormalAt(points, x, y, s.normal_window, K, col_map, row_map, nrm)) return true;
    const double up = std::fabs(nrm[0] * plane.normal.x() + nrm[1] * plane.normal.y() +
                                nrm[2] * plane.normal.z());
    return up >= std::cos(kLevelAngle);
  }
  return true;
}

// The foot of a rise whose first raised point is samples[top] (one side of a row, outward): the
// lowest point within kRiseReach inward of it, moved out to the last point still within
// kFootBand of that height (where the rise starts: a gutter's bottom, a rolled kerb's toe).
// -1 when no point lies inward.
int footOf(const std::vector<RoadEdgeFinder::RowSample>& samples, int top) {
  const float reach = samples[top].lateral;
  int low = -1;
  for (int i = top - 1; i >= 0 && reach - samples[i].lateral <= kRiseReach; --i)
    if (samples[i].lateral <= reach && (low < 0 || samples[i].height < samples[low].height))
      low = i;
  if (low < 0) return -1;
  int foot = low;
  for (int i = low + 1; i < top; ++i)
    if (samples[i].lateral <= reach && samples[i].height <= samples[low].height + kFootBand)
      foot = i;
  return foot;
}

// A rolled (mountable) kerb or a verge: no step between two points, the surface rising over up
// to kRiseReach. In @p samples (one side of a row, outward), the first point @p top that stands
// @p kerb above its foot (footOf(): near the plane, at least @p offset_min beside the camera)
// and stays that high over kSidewalkCheck beyond, at kRaisedRun points at least (a lone bump
// is a seam's rim or a wheel).
bool gradualRise(const std::vector<RoadEdgeFinder::RowSample>& samples, float kerb,
                 double offset_min, int& foot, int& top) {
  const int count = static_cast<int>(samples.size());
  float lowest = std::numeric_limits<float>::infinity();  // of the points inward of j
  for (int j = 0; j < count; ++j) {
    const float below = lowest;
    lowest = std::min(lowest, samples[j].height);
    if (samples[j].height - below < kerb) continue;  // (no foot of it anywhere inward)
    const int f = footOf(samples, j);
    if (f < 0 || samples[j].height - samples[f].height < kerb ||
        std::fabs(samples[f].height) > kMaxCamber || samples[f].lateral < offset_min)
      continue;
    int raised = 1;
    bool stays = true;
    for (int k = j + 1;
         k < count && stays && samples[k].lateral - samples[j].lateral <= kSidewalkCheck;
         ++k, ++raised)
      stays = samples[k].height - samples[f].height >= kerb;
    if (!stays || raised < kRaisedRun) continue;
    foot = f;
    top = j;
    return true;
  }
  return false;
}

}  // namespace

void RoadEdgeFinder::find(const cv::Mat& points, const cv::Mat* filled, const cv::Range& rows,
                          const Intrinsics& K, const cv::Mat& col_map, const cv::Mat& row_map,
                          const PlaneEstimate& plane, const RoadEdgeSettings& s, RoadEdgeLine& left,
                          RoadEdgeLine& right) {
  for (RoadEdgeLine* e : {&left, &right}) {
    e->found = false;
    e->pixels.clear();
    e->points.clear();
  }
  edges_[0].clear();
  edges_[1].clear();
  const RoadFrame frame = RoadFrame::fromPlane(plane);
  if (!frame.valid() || points.type() != CV_32FC3) return;
  const Eigen::Vector3f n = plane.normal.cast<float>();
  const float d = static_cast<float>(plane.distance);
  const int* cm = col_map.empty() ? nullptr : col_map.ptr<int>();
  const int* rm = row_map.empty() ? nullptr : row_map.ptr<int>();
  // the processing column of the camera's own column (the principal point)
  int centre = 0;
  for (int x = 0; x < points.cols; ++x)
    if ((cm ? cm[x] : x) <= K.cx) centre = x;
  const float kerb = static_cast<float>(s.kerb_height);
  const float max_step = static_cast<float>(s.max_step);
  const float road_band = std::max(static_cast<float>(kRoadBand), 0.5f * kerb);
  const int r0 = std::max(rows.start, 0), r1 = std::min(rows.end, points.rows);
  double searched = -1.0;               // road distance of the last row searched
  for (int y = r1 - 1; y >= r0; --y) {  // near to far
    // the road's distance on this row, and how finely the input image resolves it across
    double depth = 0.0;
    if (!rayPlaneDepth(plane, K.ray(K.cx, rm ? rm[y] : y), depth)) continue;
    if (depth > s.max_range || K.fx / depth < s.min_pixels_per_metre) continue;
    // near the car rows are a centimetre apart: one in kRowSpacing of road is enough
    if (searched >= 0.0 && depth - searched < kRowSpacing) continue;
    searched = depth;
    const cv::Vec3f* row = points.ptr<cv::Vec3f>(y);
    const uint8_t* fill = filled ? filled->ptr<uint8_t>(y) : nullptr;
    // columns kColumnSpacing of road apart (processing pixels per metre across this row)
    const double ppm =
        K.fx / depth * (cm ? static_cast<double>(points.cols) / (cm[points.cols - 1] + 1) : 1.0);
    const int stride = std::max(1, static_cast<int>(kColumnSpacing * ppm));
    for (int side = 0; side < 2; ++side) {
      const int step = side == 0 ? -stride : stride;
      int road_run = 0, raised_run = 0, last_road = -1, first_raised = -1;
      bool stepped = false;
      samples_.clear();
      // a rise's foot in road coordinates, between the road point i and the point j outward of
      // it: across the road half-way, ahead where i's pixel ray meets the plane (a point up a
      // kerb's face or on a rolled kerb is nearer than the road on its row)
      const auto footAt = [&](int i, int j) {
        const auto across = [&](int k) {
          const cv::Vec3f& q = row[samples_[k].x];
          return frame.toRoad(Eigen::Vector3d(q[0], q[1], q[2])).y();
        };
        const int u = cm ? cm[samples_[i].x] : samples_[i].x;
        const Eigen::Vector3d ray = K.ray(u, rm ? rm[y] : y);
        double z = depth;
        rayPlaneDepth(plane, ray, z);  // (the row's centre meets it: so does its column)
        return Eigen::Vector2d(frame.toRoad(z * ray).x(), 0.5 * (across(i) + across(j)));
      };
      // the road's own height along the row: a cambered road falls toward its gutter, and a
      // kerb rises from the gutter, not from the plane
      float local = 0.f;
      for (int x = centre; x >= 0 && x < points.cols; x += step) {
        if (fill && fill[x]) continue;  // the plane extended over missing depth: no measurement
        const cv::Vec3f& p = row[x];
        if (std::isnan(p[2])) continue;
        if (std::fabs(p[0]) > s.offset_max) break;  // beyond any lane's edge
        const float h = n.x() * p[0] + n.y() * p[1] + n.z() * p[2] + d;
        if (h - local > max_step) break;  // a car's side, a wall: no road edge on this row
        samples_.push_back({std::fabs(p[0]), h, x});
        if (std::fabs(h - local) <= road_band && std::fabs(h) <= kMaxCamber) {
          if (raised_run > 0) {  // the raised stretch was not the road's end
            raised_run = 0;
            road_run = 0;
          }
          ++road_run;
          last_road = static_cast<int>(samples_.size()) - 1;
          local += kCamberGain * (h - local);
        } else if (h - local >= kerb && road_run >= kRoadRun) {
          if (raised_run++ == 0) first_raised = static_cast<int>(samples_.size()) - 1;
          if (raised_run >= kRaisedRun) {
            // the step's foot: where the rise to it starts (the road point followed up a kerb's
            // sloped face is not the foot)
            const cv::Vec3f& b = row[samples_[first_raised].x];
            const int foot = footOf(samples_, first_raised);
            RowEdge e;
            // (with no point measured within kRiseReach inward, between the last road point and
            // the first raised one)
            e.road = foot >= 0 ? footAt(foot, foot + 1) : footAt(last_road, first_raised);
            // a sidewalk stays low beyond its kerb, and its top is level; a car's or a truck's
            // side rises, its rear face is vertical
            if (sidewalkBeyond(row, fill, x + step, step, points.cols, b[0], n, d + local,
                               max_step) &&
                levelBeyond(points, filled, samples_[first_raised].x, y, step, K, col_map, row_map,
                            plane, s))
              edges_[side].push_back(e);
            stepped = true;
            break;
          }
        }
      }
      // no step on this row: a rise spread over a hand's breadth or more, at its foot
      int foot = -1, top = -1;
      if (stepped || !gradualRise(samples_, kerb, s.offset_min, foot, top)) continue;
      const cv::Vec3f& t = row[samples_[top].x];
      if (!sidewalkBeyond(row, fill, samples_[top].x + step, step, points.cols, t[0], n,
                          d + samples_[foot].height, max_step) ||
          !levelBeyond(points, filled, samples_[top].x, y, step, K, col_map, row_map, plane, s))
        continue;
      RowEdge e;
      e.road = footAt(foot, foot + 1);
      edges_[side].push_back(e);
    }
  }
  fitSide(edges_[0], K, frame, s, true, left);
  fitSide(edges_[1], K, frame, s, false, right);
}

void RoadEdgeFinder::fitSide(const std::vector<RowEdge>& edges, const Intrinsics& K,
                             const RoadFrame& frame, const RoadEdgeSettings& s, bool left,
                             RoadEdgeLine& out) {
  if (static_cast<int>(edges.size()) < kMinRows) return;
  road_.clear();
  for (const RowEdge& e : edges) road_.push_back(e.road);
  double a = 0.0, b = 0.0;
  if (!fitRobustLine(road_, kLineGate, a, b)) return;
  const double side = left ? a : -a;
  if (side < s.offset_min || side > s.offset_max || std::fabs(std::atan(b)) > kMaxHeading) return;
  double near = 1e9, far = -1e9;
  inliers_.clear();
  for (size_t i = 0; i < edges.size(); ++i) {
    if (std::fabs(edges[i].road.y() - (a + b * edges[i].road.x())) > kLineGate) continue;
    inliers_.push_back(static_cast<int>(i));
    near = std::min(near, edges[i].road.x());
    far = std::max(far, edges[i].road.x());
  }
  if (static_cast<int>(inliers_.size()) < kMinRows || far - near < kMinLength) return;
  for (int i : inliers_) {  // near to far (rows were searched bottom up)
    const Eigen::Vector3d P = frame.toCamera(edges[i].road.x(), edges[i].road.y());
    out.pixels.emplace_back(K.project(P));
    out.points.push_back(P.cast<float>());
  }
  out.offset = a;
  out.heading = std::atan(b);
  out.found = true;
}

}  // namespace rgbd_lane_detector
