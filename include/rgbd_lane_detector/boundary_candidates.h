/**
 * @file boundary_candidates.h
 * @brief Stages 6-7: each side's candidate boundaries of one frame (seeds, PCA angles, traces),
 * and what each one is (the classification, an improvement).
 *
 * The paper's search: the best match of each side's response map R is a seed, its PCA angle
 * the marker's direction, the sliding box its trace (METHOD.md section 3). The improved mode
 * traces several lines per side (the next best seeds off the lines already traced: a kerb or a
 * rail may outscore the paint beside it), seeks seeds near the tracked boundaries first, adds
 * the tracked painted line followed where the lane model predicts it (a lane change turns lines
 * faster than the templates follow) and the road edges the depth shows (RoadEdgeFinder), and
 * classifies every candidate (BoundaryClassifier: paint, road edge, no boundary), following
 * painted lines and road edges row by row on the image. The lane fit (LaneFitter) then chooses
 * each side's boundary among them.
 */
#pragma once

#include <algorithm>
#include <array>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbd_lane_detector/boundary_classifier.h"
#include "rgbd_lane_detector/lane_fitter.h"
#include "rgbd_lane_detector/params.h"
#include "rgbd_lane_detector/road_edge_finder.h"
#include "rgbd_lane_detector/types.h"

namespace rgbd_lane_detector {

/// The frame as the candidate search sees it (views onto the detector's buffers; nothing is
/// copied). Pixel coordinates of traces are input-image pixels; the maps and points are at the
/// processing scale.
struct CandidateFrame {
  const cv::Mat* colour = nullptr;  ///< input colour image
  PixelFormat format = PixelFormat::kBgr8;
  const cv::Mat* grey = nullptr;  ///< grey of the input image in grey_rows (null: from colour)
  cv::Range grey_rows;
  Intrinsics K;         ///< of the input image
  cv::Size input_size;  ///< input image size
  cv::Size proc_size;   ///< processing image size
  cv::Rect roi;         ///< searched rows at the processing scale
  cv::Range roi_rows;
  const cv::Mat* col_map = nullptr;     ///< source column of each processing column (empty: none)
  const cv::Mat* row_map = nullptr;     ///< source row of each processing row (empty: none)
  const cv::Mat* points = nullptr;      ///< CV_32FC3 organised points at the processing scale
  const cv::Mat* filled = nullptr;      ///< road plane extended over missing depth (may be null)
  const PlaneEstimate* road = nullptr;  ///< this frame's road plane from depth (may be invalid)
  const LaneFitter* fitter = nullptr;   ///< the tracked lane (predictions, previous plane)
  std::array<double, 2> template_angle{{0.0, 0.0}};  ///< each side's template angle (rad)

  /// The processing image's coordinates of input pixel @p p (pixel centres onto centres).
  cv::Point2d toProcessing(const cv::Point2d& p) const {
    const double sx = static_cast<double>(proc_size.width) / input_size.width;
    const double sy = static_cast<double>(proc_size.height) / input_size.height;
    return cv::Point2d((p.x + 0.5) * sx - 0.5, (p.y + 0.5) * sy - 0.5);
  }
  /// The input image's coordinates of processing pixel @p p (toProcessing()'s inverse).
  cv::Point2d toInput(const cv::Point2d& p) const {
    const double sx = static_cast<double>(input_size.width) / proc_size.width;
    const double sy = static_cast<double>(input_size.height) / proc_size.height;
    return cv::Point2d((p.x + 0.5) * sx - 0.5, (p.y + 0.5) * sy - 0.5);
  }
};

/**
 * @brief The classifier's view of a candidate frame on @p plane.
 * @param[in] f the frame.
 * @param[in] plane the road plane the classifier measures heights and widths against.
 * @param[out] in the classifier's input (views).
 */
void classifierInputOf(const CandidateFrame& f, const PlaneEstimate& plane, ClassifierInput& in);

/**
 * @brief Finds and classifies one frame's candidate boundaries. Reuses its buffers: no
 * allocation in steady state.
 */
class BoundaryCandidateFinder {
 public:
  /// Rows a followed line is reserved for (it grows past them once, on a taller image).
  static constexpr size_t kReservedRows = 2048;
  /// Points around a seed roadAround() reads at most: (2 * (template_size / 4) + 1)^2 at the
  /// largest template_size (256).
  static constexpr size_t kReservedSeedHeights = 129 * 129;
  /// Image columns and ridges traceLoneDash() is reserved for (they grow past them once, on a
  /// wider image or a busier road).
  static constexpr size_t kReservedRowPixels = 4096;
  static constexpr size_t kReservedRidges = 8192;
  BoundaryCandidateFinder() {
    seed_pixels_.reserve(kReservedRows);
    seed_points_.reserve(kReservedRows);
    seed_heights_.reserve(kReservedSeedHeights);
    prior_road_.reserve(kReservedRows);
    band_lo_.reserve(kReservedRows);
    band_hi_.reserve(kReservedRows);
    row_grey_.reserve(kReservedRowPixels);
    row_sums_.reserve(kReservedRowPixels + 1);
    row_kept_.reserve(kReservedRowPixels);
    ridges_.reserve(kReservedRidges);
    strokes_.reserve(kReservedRidges);
    live_.reserve(kReservedRidges);
    stroke_pixels_.reserve(kReservedRows);
    wobble_road_.reserve(kReservedRows);
  }

  /// Replace the parameters (already sanitised).
  void setParams(const Params& params) { params_ = params; }

  /// Start a frame: no candidates.
  void clear() {
    counts_ = {0, 0};
    pca_ms_ = tracing_ms_ = 0.0;
  }

  /**
   * @brief Trace up to boundary_candidates lines of one side whose seeds are the best matches
   * of @p R off the lines already traced (on this or an earlier map of the side), appended to
   * the side's candidates.
   * @param[in] f the frame.
   * @param[in] side 0 left, 1 right.
   * @param[in,out] R the side's response map: zeroed around traced lines during the search,
   *                restored afterwards (but for matches the road gate removes for good).
   */
  void traceLines(const CandidateFrame& f, int side, cv::Mat& R);

  /**
   * @brief Classify the traced lines (following paint and road edges on the image), then add
   * the tracked painted lines followed where they are predicted and the road edges the depth
   * shows that no traced line found. Without a road plane, or with classify_boundaries off,
   * every traced line is taken as paint (the paper's view).
   * @param[in] f the frame.
   */
  void classify(const CandidateFrame& f);

  /**
   * @brief After classify(): a side whose search found no painted boundary while the other side
   * is on paint where an ego boundary can be is sought again in the band a lane's width
   * (kNarrowestLane to lane_width_max) beside that line and parallel to it, where its best match
   * (the lines already traced on the side left out), above priorSeedScore(), is followed and
   * classified like any seed; a line found there that is paint by its width (not a narrow line,
   * paint only as worn dashes) and lies mostly in the band is added to the side's candidates.
   * @param[in] f the frame.
   * @param[in] R_left,R_right the sides' response maps (zeroed around traced lines during the
   *            search, restored afterwards).
   */
  void traceBesidePaint(const CandidateFrame& f, cv::Mat& R_left, cv::Mat& R_right);

  /**
   * @brief After traceBesidePaint(): a side with no painted candidate and no tracked boundary is
   * sought for one dash of a dashed line that no template matched (a thin dash far ahead, in
   * dappled shadow, where the half-binary image keeps the sunlit asphalt too): on each image row
   * kPriorNear to kPriorFar ahead, where an ego boundary can be (boundary_offset_min/max), the
   * ridges of paint width that stand out of the same road on both sides by the paint contrast;
   * rows of ridges one after another along the road make strokes, and the longest is classified.
   * It is added as paint when it is one dash of a lane line: paint by its width, flat on the
   * road with road on both sides (no height step), as straight as machine-laid paint (a strip of
   * sunlight between foliage shadows wobbles), running along the road, 2-10 m of road long when
   * followed across no gap (kStrokeGap), and no arrow's head beyond it.
   * @param[in] f the frame.
   */
  void traceLoneDash(const CandidateFrame& f);

  /// Candidates of side @p side (count in @p count), best seed first.
  const BoundaryCandidate* candidates(int side, int& count) const {
    count = counts_[side];
    return candidates_[side].data();
  }
  /// The candidate arrays and counts, for the lane fit.
  std::array<std::vector<BoundaryCandidate>, 2>& candidates() { return candidates_; }
  const std::array<int, 2>& counts() const { return counts_; }

  /// Time of this frame's seed search and PCA, and of its tracing (ms, wall clock).
  double pcaMs() const { return pca_ms_; }
  double tracingMs() const { return tracing_ms_; }

 private:
  /// Zero R around a seed for the next seed search (restore_ keeps the values); @p previous,
  /// the box zeroed just before (0 already, not read again), becomes this one.
  void excludeBox(const CandidateFrame& f, cv::Mat& R, const cv::Point& centre,
                  cv::Rect& previous);
  /// excludeBox() along a traced line and its seed.
  void excludeTrace(const CandidateFrame& f, cv::Mat& R, const MarkerTrace& trace,
                    const cv::Point& peak);
  /// Best match of @p R in its side's search area (near the predicted boundary first); value 0
  /// when nothing is left.
  void findBestMatch(const CandidateFrame& f, const cv::Mat& R, bool left, cv::Point& peak,
                     float& value);
  /// Columns near a side's predicted marker, per row of @p area (band_lo_/band_hi_);
  /// false: no prediction.
  bool predictedBand(const CandidateFrame& f, int side, const cv::Rect& area);
  bool plausibleMarkerAngle(double angle, bool left) const;
  /// road_gate: true when the surface normal at a processing pixel is known and not road-like.
  bool offRoad(const CandidateFrame& f, const cv::Point& pixel) const;
  /// A candidate of @p side classified as a painted boundary.
  bool hasPaintedBoundary(int side) const;
  void buildTrace(const CandidateFrame& f, const cv::Mat& R, const cv::Point& peak,
                  float peak_value, double angle, MarkerTrace& trace);
  /// 3D point of a processing-image pixel: its own, else the nearest valid depth in its box
  /// on the pixel's ray, else NaN (never a zero depth).
  Eigen::Vector3f pointAt(const CandidateFrame& f, const cv::Point2f& c) const;
  /// A candidate of @p side classified as @p kind lies within @p reach of the line
  /// lateral(forward) (road-plane coordinates of @p frame) over most of its points.
  template <typename Lateral>
  bool candidateOnLine(const CandidateFrame& f, int side, BoundaryKind kind,
                       const RoadFrame& frame, double reach, Lateral&& lateral) const;
  /// A tracked painted side is also sought where its model predicts it, row by row: the
  /// template's seeds can miss a line whose image angle changes fast (a lane change).
  void followPredictedLines(const CandidateFrame& f);
  /// The score above which a match a lane's width beside a painted side is followed: tau_g, the
  /// score the geometric map is trusted on, where that is under the trace threshold.
  double priorSeedScore() const { return std::min(params_.tau_g, params_.trace_threshold); }
  /// A seed whose trace is too short to tell what it is (a short dash far ahead, a dash whose
  /// matched blob gave no usable angle): the line through it along the road ahead, followed row
  /// by row across the dash gaps (BoundaryClassifier::followLine), when the seed is a measured
  /// road point where an ego-lane boundary can be (boundary_offset_min/max on its side @p left).
  /// False when no line is found.
  /// With @p prior (the seed lies a lane's width beside a painted line), a seed's match above
  /// priorSeedScore() (not trace_threshold) is followed, also where no depth measures it or only
  /// the road plane's fill does.
  bool followFromSeed(const CandidateFrame& f, bool left, MarkerTrace& m, bool prior);
  /// Classify one candidate of @p side (its seed followed when its trace is short; @p prior as
  /// followFromSeed()'s), and follow it as paint or road edge.
  void classifyCandidate(const CandidateFrame& f, int side, BoundaryCandidate& c, bool prior);
  /// The nearest painted candidate of @p side where an ego boundary can be, as the road line
  /// lateral = @p a + @p b forward (heading within kSideMaxHeading); false: none.
  bool paintedSideLine(const CandidateFrame& f, int side, double& a, double& b);
  /// Columns per processing row (band_lo_/band_hi_) between the road lines lateral = @p lo + @p b
  /// forward and @p hi + @p b forward, kPriorNear to kPriorFar ahead; false: none.
  bool laneBand(const CandidateFrame& f, const RoadFrame& frame, double lo, double hi, double b);
  /// The measured points (depth, not the plane filled in) around the input pixel @p seed lie on
  /// the road (their median within kerb_height of the plane) and agree with each other (their
  /// median deviation within a quarter of it): a seed whose own point is off the road is a
  /// stray return there (a LiDAR scan line's end), not a kerb top or a car.
  bool roadAround(const CandidateFrame& f, const cv::Point2f& seed);
  /// A followed painted line (input pixels, near to far) is one stroke of paint shorter than any
  /// lane line shows (a turn arrow's shaft, a stop line's stub): paint on a single stretch of
  /// road under 8 m, where a dashed line shows two dashes and a solid line more length
  /// (@p length: metres from its nearest to its farthest row).
  bool loneStroke(const CandidateFrame& f, const std::vector<cv::Point2f>& pixels,
                  double* length = nullptr) const;
  /// seed_pixels_ followed row by row (BoundaryClassifier::followLine, paint sought within
  /// @p reach; @p seed_line: they are the straight line through a seed): true when enough rows
  /// were found (they replace seed_pixels_, with seed_points_).
  bool followed(const ClassifierInput& in, double reach, bool seed_line = false);
  /// A followed line (input pixels, near to far) runs ahead on the road: its far end within
  /// kMaxSeedHeading of straight ahead of its near end (not a car's flank, a kerb turning away).
  bool runsAhead(const CandidateFrame& f, const std::vector<cv::Point2f>& pixels) const;
  /// Stretches of a followed line (input pixels, near to far) separated by more than @p gap
  /// metres of road without a row found; @p extent: metres from its nearest to its farthest row,
  /// @p painted: metres of it the stretches cover; @p rows_cover: metres of it the rows found
  /// cover, each up to the next one but at most its own spacing (kRowCell and one image row);
  /// rows beyond @p max_forward are not counted; with @p lone_points, neither are groups of rows
  /// (each within half a metre of road of the next, or kRowsPerGap image rows where a row spans
  /// more) that span no more than a raised pavement
  /// marker and one row step (a marker found on one row or two: no paint's stretch, no bridge).
  int paintStretches(const CandidateFrame& f, const std::vector<cv::Point2f>& pixels, double gap,
                     double* extent = nullptr, double* painted = nullptr,
                     double max_forward = std::numeric_limits<double>::infinity(),
                     double* rows_cover = nullptr, bool lone_points = false) const;
  /// The longest stroke of paint-width ridges on @p side where an ego boundary can be
  /// (traceLoneDash()), its rows near to far in stroke_pixels_; false when none is
  /// min_marker_points rows and kMinStroke long.
  bool longestRidgeStroke(const CandidateFrame& f, int side);
  /// RMS (m) of the road-plane lateral offsets of @p pixels about their least-squares line on
  /// the road (+inf with fewer than three on the road).
  double lateralWobble(const CandidateFrame& f, const std::vector<cv::Point2f>& pixels);
  /// A narrow band taken for a rail head that comes in dashes when followed: worn paint; broken
  /// by dash gaps but covering more than dashes do: no boundary (a seam's or a crack's rim).
  void dashedNarrowLine(const CandidateFrame& f, int side, BoundaryCandidate& c);
  /// Road edges the depth shows (RoadEdgeFinder) that no traced line found.
  void addRoadEdgesFromDepth(const CandidateFrame& f);
  /// The next free candidate of @p side (the array grows on the first frames only).
  BoundaryCandidate& next(int side);
  /// A trace about to be built from a seed: not found, paint until classified, no pixels yet
  /// (the buffers keep their capacity).
  static void startTrace(MarkerTrace& m);

  Params params_;
  std::array<std::vector<BoundaryCandidate>, 2> candidates_;
  std::array<int, 2> counts_{{0, 0}};
  BoundaryClassifier classifier_;
  ClassifierInput classifier_input_;
  RoadEdgeFinder edge_finder_;
  std::array<RoadEdgeLine, 2> depth_edges_;
  double pca_ms_ = 0.0, tracing_ms_ = 0.0;
  std::vector<std::pair<float*, float>> restore_;  ///< R values zeroed by the search
  std::vector<cv::Point> pca_stack_;
  std::vector<uint8_t> pca_visited_;
  std::vector<cv::Point2f> trace_pixels_;
  std::vector<float> trace_scores_;
  std::vector<Eigen::Vector3f> samples_;
  std::vector<cv::Point2f> seed_pixels_;       ///< followFromSeed()'s line
  std::vector<Eigen::Vector3f> seed_points_;
  std::vector<float> seed_heights_;  ///< roadAround()'s heights
  /// longestRidgeStroke()'s buffers: a row's grey, its prefix sums and the columns kept for the
  /// exact test, the ridges found (input pixels, their road coordinates and stroke), each
  /// stroke's last ridge, forward extent and rows
  std::vector<uint8_t> row_grey_;
  std::vector<int> row_sums_;
  std::vector<uint8_t> row_kept_;
  struct Ridge {
    cv::Point2f pixel;
    Eigen::Vector2d road;
    int stroke;
  };
  std::vector<Ridge> ridges_;
  struct Stroke {
    Eigen::Vector2d first, last;
    int rows;
  };
  std::vector<Stroke> strokes_;
  std::vector<int> live_;  ///< the strokes (in order of their first ridge) a row may continue
  std::vector<cv::Point2f> stroke_pixels_;
  std::vector<Eigen::Vector2d> wobble_road_;
  std::vector<Eigen::Vector2d> prior_road_;  ///< paintedSideLine()'s road points
  std::vector<int> band_lo_, band_hi_;
};

}  // namespace rgbd_lane_detector
