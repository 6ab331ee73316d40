#include "rgbd_lane_detector/line_follower.h"

#include <algorithm>
#include <cmath>

#include "rgbd_lane_detector/geometry.h"
#include "row_statistics.h"

namespace rgbd_lane_detector {
namespace {

constexpr double kFollowReach = 0.15;   // m: a followed row's band is sought this close
constexpr double kFollowSpacing = 0.1;  // m of road between followed rows at least
constexpr double kFollowFit = 4.0;  // m of road behind the last row found that make the line ahead
constexpr double kDoublePitch = 0.27;  // m between the two lines of a double line, expected
constexpr double kDoubleReach = 0.1;   // m: the second line is sought this far around it
constexpr double kDoubleMin = 0.17;    // m: a second line this near ...
constexpr double kDoubleMax = 0.4;     // ... to this far makes a double line
constexpr double kDoubleShare = 0.6;   // share of the measured rows that must show it
// On a painted line, the rows found steer the line ahead (predict the next rows' column) only
// where their band is paint-like, at least this share of paint_width_min wide at half its
// contrast, once two such rows are found (the bright core of worn paint keeps a few centimetres;
// a grain of the aggregate, sensor noise at night or the bright rim of a dark seam beside the line
// is a centimetre or two, and followed one row after another they walk the line off its paint)
constexpr double kSteeringWidthShare = 0.35;
// ... where that width spans this many pixels at least (on coarser rows a band's width in whole
// pixels does not tell a grain from paint: every row found steers there)
constexpr double kSteeringResolved = 2.0;
// Below a seed's line (toward the car), where the pixels resolve the grains of the road (as for
// kSteeringResolved), the rows found steer the line only once this many of them were found each
// on the row measured just after another found one (a stretch of paint; rows along paint are
// found one after the other): rows found one at a time between rows that find nothing are grains
// of the aggregate, a patch's texture or a raised marker beside a worn dash's end, and a line
// fitted through two or three of them, over a few tenths of a metre of road, points anywhere;
// until then the seed's straight line continues. (On coarser pixels no grain stands out, and
// paint seen through noise, at night, is itself found one row at a time.)
constexpr int kStretchRows = 2;

// The pixels resolve the road's grains at ppm pixels per metre: the steering width
// (kSteeringWidthShare of paint_width_min) spans kSteeringResolved pixels or more.
bool resolvesGrains(const Params& p, double ppm) {
  return kSteeringWidthShare * p.paint_width_min * ppm >= kSteeringResolved;
}

}  // namespace

LineFollower::LineFollower() {
  // the per-line buffers at their largest, so that no frame grows them
  followed_.reserve(kReservedPixels);
  followed_near_.reserve(kReservedPixels);
  follow_f_.reserve(kReservedPixels);
  follow_steers_.reserve(kReservedPixels);
}

template <typename FindInRow>
int LineFollower::followRows(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                             std::vector<Eigen::Vector3f>& points, double max_gap, double max_range,
                             bool seed_line, FindInRow&& find) {
  if (pixels.size() < 2 || in.plane == nullptr || !in.plane->valid || !in.frame.valid()) return 0;
  // the trace by row, near (bottom) to far (top)
  int v_near = 0, v_far = in.colour->rows;
  for (const auto& c : pixels) {
    v_near = std::max(v_near, static_cast<int>(std::lround(c.y)));
    v_far = std::min(v_far, static_cast<int>(std::lround(c.y)));
  }
  // (rows that never rise from near to far, as a trace's mostly do: the first segment holding a
  // row is found by bisection, not by a walk from the trace's start on every row)
  const bool descending =
      std::all_of(pixels.begin(), pixels.end(),
                  [](const cv::Point2f& c) { return std::isfinite(c.y); }) &&
      std::is_sorted(pixels.begin(), pixels.end(),
                     [](const cv::Point2f& a, const cv::Point2f& b) { return a.y > b.y; });
  auto traceColumn = [&](double v) {  // the trace polyline's column at row v (rows decrease)
    size_t i = 1;
    if (descending) {
      // the first point at or above row v ends the first segment holding it (those before it
      // lie below v; the segment holds v when its near end is at or below v)
      i = static_cast<size_t>(
          std::partition_point(pixels.begin() + 1, pixels.end(),
                               [v](const cv::Point2f& c) { return !(v >= c.y); }) -
          pixels.begin());
      if (i < pixels.size() && !(v <= pixels[i - 1].y)) i = pixels.size();
    }
    for (; i < pixels.size(); ++i) {
      const cv::Point2f& a = pixels[i - 1];
      const cv::Point2f& b = pixels[i];
      if ((v <= a.y && v >= b.y) || (v >= a.y && v <= b.y)) {
        const double t = std::fabs(b.y - a.y) > 1e-6 ? (v - a.y) / (b.y - a.y) : 0.0;
        return a.x + t * (b.x - a.x);
      }
    }
    return static_cast<double>(v >= pixels.front().y ? pixels.front().x : pixels.back().x);
  };
  // the straight line u(v) through the trace: where nothing has been found beyond it yet
  double ta = 0.0, tb = 0.0;
  {
    LineSums sums;
    for (const auto& c : pixels) sums.add(c.y, c.x);
    sums.fit(1e-9, ta, tb);
  }
  // forward distance of a road pixel, and pixels per metre across the road there
  auto road = [&](double u, int v, double& f, double& ppm) {
    return in.roadAt(u, v, f, ppm) && f > 0.0 && f <= max_range && ppm >= 1.5;
  };
  // One direction from the trace: rows v0, v0 + step, ...; inside the trace's rows the column
  // comes from the trace, outside it from a line through the last rows found.
  auto follow = [&](int v0, int step, std::vector<cv::Point2f>& out) {
    out.clear();
    follow_f_.clear();
    follow_steers_.clear();
    double last_f = -1.0, measured_f = -1.0;
    int steering = 0;  // paint-like rows found
    // the line u = fit_a + fit_b v through the rows found, fitted for fit_rows rows found
    // (refitted only when a row is found: most rows are passed over, or find nothing)
    double fit_a = 0.0, fit_b = 0.0;
    size_t fit_rows = 0;
    // below a seed's line: rows found right after another found one (kStretchRows)
    const bool hold = seed_line && step > 0;
    bool last_found = false;
    int stretch_rows = 0;
    for (int v = v0; v >= 0 && v < in.colour->rows; v += step) {
      const bool inside = v <= v_near && v >= v_far;
      double u;
      if (inside) {
        u = traceColumn(v);
      } else if (out.size() < 2 || (hold && stretch_rows < kStretchRows)) {
        u = ta + tb * v;
      } else {  // least-squares line u(v) through the last rows found that steer
        if (fit_rows != out.size()) {
          // (the paint-like ones where two are found, else all)
          const bool all = steering < 2;
          size_t last = out.size() - 1;
          while (!all && !follow_steers_[last]) --last;
          LineSums sums;
          // the steering rows within kFollowFit of the last one
          for (size_t i = last + 1; i-- > 0;) {
            if (!all && !follow_steers_[i]) continue;
            if (sums.n >= 2 && std::fabs(follow_f_[i] - follow_f_[last]) > kFollowFit) break;
            sums.add(out[i].y, out[i].x);
          }
          sums.fit(1e-9, fit_a, fit_b);
          fit_rows = out.size();
        }
        u = fit_a + fit_b * v;
      }
      double f = 0.0, ppm = 0.0;
      if (!road(u, v, f, ppm)) {
        if (!inside) break;
        continue;
      }
      if (!inside && last_f >= 0.0 && std::fabs(f - last_f) > max_gap) break;  // past the line
      // near the car rows are a few centimetres apart: one in kFollowSpacing of road is enough
      if (measured_f >= 0.0 && std::fabs(f - measured_f) < kFollowSpacing) continue;
      measured_f = f;
      double centre;
      bool steers = true;
      const bool found = find(v, u, ppm, inside || out.size() < 2, centre, steers);
      stretch_rows += found && last_found;
      last_found = found;
      if (found) {
        out.emplace_back(static_cast<float>(centre), static_cast<float>(v));
        follow_f_.push_back(f);
        follow_steers_.push_back(steers);
        steering += steers;
        last_f = f;
      } else if (!inside && last_f < 0.0 && out.empty()) {
        last_f = f;  // a gap from the trace's end on
      }
    }
  };
  follow(v_near, -1, followed_);          // from the trace's nearest row to the far end
  follow(v_near + 1, 1, followed_near_);  // below it, toward the car
  const int found = static_cast<int>(followed_.size() + followed_near_.size());
  if (found < 3) return found;
  pixels.clear();
  points.clear();
  for (auto it = followed_near_.rbegin(); it != followed_near_.rend(); ++it) pixels.push_back(*it);
  pixels.insert(pixels.end(), followed_.begin(), followed_.end());
  for (const auto& c : pixels)
    points.push_back(
        in.pointAt(static_cast<int>(std::lround(c.x)), static_cast<int>(std::lround(c.y))));
  return found;
}

int LineFollower::followLine(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                             std::vector<Eigen::Vector3f>& points, const Params& p, double max_gap,
                             double max_range, double reach, bool painted, bool seed_line) {
  // (a seed's line is held below it where the pixels at its near end resolve grains)
  if (seed_line && !pixels.empty() && in.plane != nullptr && in.plane->valid) {
    const auto nearest = std::max_element(
        pixels.begin(), pixels.end(),
        [](const cv::Point2f& a, const cv::Point2f& b) { return a.y < b.y; });
    double f = 0.0, ppm = 0.0;
    seed_line = in.roadAt(nearest->x, nearest->y, f, ppm) && resolvesGrains(p, ppm);
  }
  return followRows(
      in, pixels, points, max_gap, max_range, seed_line,
      [&](int v, double u, double ppm, bool from_trace, double& centre, bool& steers) {
        // where the column comes from the trace (@p reach: wider for a predicted
        // line), else from the rows found
        const double r = from_trace ? reach : kFollowReach;
        const int half = std::min(48, std::max(2, static_cast<int>(std::lround(r * ppm))));
        int width = 0;
        if (!profile_.bandCentre(in, v, u, half, p.paint_width_max * ppm + 2.0, p, centre,
                                 &width))
          return false;
        steers = !painted || !resolvesGrains(p, ppm) ||
                 width >= kSteeringWidthShare * p.paint_width_min * ppm;
        return true;
      });
}

bool LineFollower::centreDoubleLine(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                                    std::vector<Eigen::Vector3f>& points, const Params& p) {
  if (in.plane == nullptr || !in.plane->valid ||
      pixels.size() < static_cast<size_t>(BandProfile::kMinRows))
    return false;
  // pixels per metre across the road at an input pixel (0: not on the road)
  auto ppmAt = [&](const cv::Point2f& c) {
    return roadPixelsPerMetre(in.K, *in.plane, in.K.ray(c.x, c.y));
  };
  twin_[0].clear();
  twin_[1].clear();
  int measured = 0;
  const size_t stride =
      (pixels.size() + BandProfile::kMaxMeasuredRows - 1) / BandProfile::kMaxMeasuredRows;
  for (size_t i = 0; i < pixels.size(); i += stride) {
    const cv::Point2f& c = pixels[i];
    const double ppm = ppmAt(c);
    if (ppm < BandProfile::kWidthPixelsPerMetre) continue;  // the gap is not resolved
    ++measured;
    const int half = std::max(2, static_cast<int>(std::lround(kDoubleReach * ppm)));
    const int v = static_cast<int>(std::lround(c.y));
    for (int s = 0; s < 2; ++s) {
      const double probe = c.x + (s == 0 ? -1.0 : 1.0) * kDoublePitch * ppm;
      double twin;
      if (!profile_.bandCentre(in, v, probe, half, p.paint_width_max * ppm + 2.0, p, twin))
        continue;
      const double offset = (twin - c.x) / ppm;
      if (std::fabs(offset) >= kDoubleMin && std::fabs(offset) <= kDoubleMax)
        twin_[s].push_back(static_cast<float>(offset));
    }
  }
  if (measured < BandProfile::kMinRows) return false;
  const int s = twin_[0].size() >= twin_[1].size() ? 0 : 1;
  if (twin_[s].size() < kDoubleShare * measured || twin_[1 - s].size() > 0.2 * measured)
    return false;
  const float offset = median(twin_[s]);  // metres across the road to the second line
  for (size_t i = 0; i < pixels.size(); ++i) {
    pixels[i].x += static_cast<float>(0.5 * offset * ppmAt(pixels[i]));
    points[i] = in.pointAt(static_cast<int>(std::lround(pixels[i].x)),
                           static_cast<int>(std::lround(pixels[i].y)));
  }
  return true;
}

int LineFollower::followEdge(const ClassifierInput& in, std::vector<cv::Point2f>& pixels,
                             std::vector<Eigen::Vector3f>& points, bool left, const Params& p,
                             double max_gap, double max_range, double reach) {
  return followRows(in, pixels, points, max_gap, max_range, false,
                    [&](int v, double u, double ppm, bool from_trace, double& edge, bool&) {
                      // the rows found predict the edge itself
                      const double inside = from_trace
                                                ? std::min(reach, BandProfile::kEdgeReference[0])
                                                : kFollowReach;
                      return profile_.edgeInRow(in, v, u, ppm, left, p, inside, edge);
                    });
}

}  // namespace rgbd_lane_detector
