// evaluate_real: score the lane detector on the hand-labelled real frames and sequences of
// ../shared/realdata (test/data/realdata_labels.yaml and the other label files) with each depth
// source the data offers (the LiDAR, and StereoSGBM where there is a right image), the frames
// also in stress variants (real_variants.h), and compare each road plane with a RANSAC plane of
// the LiDAR's road points (in a sequence, of the frames within 0.25 s). A sequence (frames that are not independent snapshots) runs in order
// at its own stamps with tracking and the lane model, each frame scored, and the lane model's
// ego boundaries scored too, with their frame-to-frame change. Writes a summary and per-frame
// Markdown tables, a CSV and the overlays.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector/lane_model.h"
#include "rgbd_lane_detector/overlay.h"
#include "rgbd_lane_detector_tools/command_line.h"
#include "rgbd_lane_detector_tools/dataset/dataset.h"
#include "rgbd_lane_detector_tools/dataset/real_variants.h"
#include "rgbd_lane_detector_tools/detector_setup.h"
#include "rgbd_lane_detector_tools/plane_check.h"
#include "rgbd_lane_detector_tools/real_labels.h"

using namespace rgbd_lane_detector;
namespace fs = std::filesystem;

namespace {

struct Row {
  std::string dataset, frame, depth, variant, mode;
  tools::LabelledFrame label;  ///< as the variant sees it
  bool sequence = false;       ///< a frame of a sequence run in order (tracking, lane model)
  bool lane = false;
  tools::RealFrameScore score;
  bool plane = false;
  bool have_reference = false;                   // the LiDAR shows a road plane
  double plane_angle = NAN, plane_offset = NAN;  // against the LiDAR RANSAC plane
  double ms = 0.0;
  // sequences: the lane model's ego boundaries against the labels, and their c0 (m, vehicle
  // frame) for the frame-to-frame change (NaN: not valid)
  bool model_valid = false;
  tools::RealFrameScore model;
  double c0[2] = {NAN, NAN};
};

// A reference road plane n . p + d = 0 (optical frame, n up).
struct ReferencePlane {
  bool valid = false;
  Eigen::Vector3d normal = Eigen::Vector3d(0.0, -1.0, 0.0);
  double distance = 0.0;
};

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// The component-wise median of the valid planes among @p planes (invalid when there is none).
ReferencePlane medianPlane(const std::vector<const ReferencePlane*>& planes) {
  std::vector<double> nx, ny, nz, d;
  for (const ReferencePlane* p : planes) {
    if (!p->valid) continue;
    nx.push_back(p->normal.x());
    ny.push_back(p->normal.y());
    nz.push_back(p->normal.z());
    d.push_back(p->distance);
  }
  ReferencePlane m;
  if (d.empty()) return m;
  m.valid = true;
  m.normal = Eigen::Vector3d(median(nx), median(ny), median(nz)).normalized();
  m.distance = median(d);
  return m;
}

// Frames of a sequence within this time of a frame share its LiDAR reference (s).
constexpr double kReferenceWindow = 0.25;

// The LiDAR reference plane of each frame of a sequence: a RANSAC plane of the road returns of
// the frames within kReferenceWindow of it, together. One frame's few returns (a wet road in fog
// returns almost only from its paint) can hold more points of a passing car than of the road, or
// lie along one painted line; the road seen from the car does not turn within a quarter of a
// second, and a car's points move between frames while the road's stay on one plane. The
// detector's plane is still checked frame by frame against it.
std::vector<ReferencePlane> sequenceReferences(const std::vector<tools::DatasetFrame>& frames) {
  std::vector<std::vector<Eigen::Vector3d>> own(frames.size());
  for (size_t i = 0; i < frames.size(); ++i) frames[i].referenceRoadPoints(own[i]);
  std::vector<ReferencePlane> references(frames.size());
  std::vector<Eigen::Vector3d> points;
  for (size_t i = 0; i < frames.size(); ++i) {
    if (frames[i].has_road_plane) {  // the dataset's own
      references[i].valid = frames[i].referenceRoadPlane(references[i].normal,
                                                          references[i].distance);
      continue;
    }
    points.clear();
    for (size_t j = 0; j < frames.size(); ++j)
      if (std::fabs(frames[j].stamp - frames[i].stamp) <= kReferenceWindow)
        points.insert(points.end(), own[j].begin(), own[j].end());
    references[i].valid =
        tools::ransacPlane(points, 0.05, references[i].normal, references[i].distance);
  }
  return references;
}

// The camera mount a vehicle would have calibrated: the road frame of the median LiDAR road
// plane over the sequence's frames (x forward on the road, z up, the origin on the road below
// the camera).
bool sequenceMount(const std::vector<ReferencePlane>& references, Eigen::Isometry3d& T) {
  std::vector<const ReferencePlane*> all;
  for (const ReferencePlane& r : references) all.push_back(&r);
  const ReferencePlane m = medianPlane(all);
  if (!m.valid) return false;
  PlaneEstimate plane;
  plane.valid = true;
  plane.normal = m.normal;
  plane.distance = m.distance;
  T = RoadFrame::fromPlane(plane).roadFromCamera();
  return true;
}

// A lane-model boundary as a trace in the optical frame (points on the road every metre of its
// range up to 40 m), so that it is scored like a traced side.
void modelBoundaryTrace(const LaneBoundaryModel& b, const Eigen::Isometry3d& vehicle_from_camera,
                        MarkerTrace& m) {
  m = MarkerTrace();
  if (!b.valid) return;
  m.found = true;
  m.kind = b.kind == LineKind::kRoadEdge ? BoundaryKind::kRoadEdge : BoundaryKind::kPaint;
  m.paint_coverage = b.kind == LineKind::kDashed ? 0.0f : b.kind == LineKind::kSolid ? 1.0f : -1.0f;
  m.yellowness = b.colour == LineColour::kYellow ? 1.0f : b.colour == LineColour::kWhite ? 0.0f : -1.0f;
  const Eigen::Isometry3d camera_from_vehicle = vehicle_from_camera.inverse();
  for (double x = std::max(1.0, std::ceil(b.x_min)); x <= std::min(40.0, b.x_max); x += 1.0)
    m.points.push_back((camera_from_vehicle * Eigen::Vector3d(x, b.lateral(x), 0.0)).cast<float>());
  m.num_valid_points = static_cast<int>(m.points.size());
}

const char* sideText(const tools::RealSideScore& s) {
  if (!s.labelled && !s.reported) return "-";
  if (s.correct) return "right";
  if (s.missed) return "missed";
  if (!s.labelled) return "WRONG (no boundary)";
  if (s.on_line) return "WRONG kind";
  return "WRONG place";
}

std::string kindText(const tools::RealSideScore& s, const tools::LabelledSide& label) {
  std::string t = label.present ? boundaryKindName(label.kind) : "none";
  if (s.reported) t += std::string(" / ") + boundaryKindName(s.reported_kind);
  return t;
}

std::string fmt(double v, const char* f = "%.2f") {
  if (!std::isfinite(v)) return "-";
  char b[32];
  std::snprintf(b, sizeof(b), f, v);
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  std::string realdata, markdown, csv, images;
  std::vector<std::string> labels_paths, modes_list, depths_list, variants_list, overrides;
  tools::CommandLine cl(
      "evaluate_real",
      "Score the detector on the hand-labelled real frames and sequences (each side right when\n"
      ">= 80% of its points lie within 0.30 m of the labelled line and its kind is the labelled\n"
      "kind; every side reported on a frame without a lane is wrong), with every depth source.\n"
      "Frame sets: each frame on its own (the detector reset), in every variant. Sequences: the\n"
      "frames in order at their own stamps (tracking, lane model), as recorded; the lane model's\n"
      "ego boundaries scored the same way, and their frame-to-frame change.\n"
      "example: evaluate_real --labels test/data/realdata_labels.yaml --realdata ../shared/realdata"
      " --markdown build/eval/real.md --images docs/images");
  cl.add("labels", "label file (at least one)", &labels_paths);
  cl.add("realdata", "folder holding the labelled datasets (required)", &realdata);
  cl.add("mode", "detector mode to score: improved or paper (default improved)", &modes_list);
  cl.add("param", "key=value override of a detector parameter, every mode",
         &overrides);
  cl.add("depth", "depth source for stereo datasets: dataset, sgbm (default both)",
         &depths_list);
  cl.add("variant",
         "frame variant of frame sets: as_is, mirrored (left-right), no_near_depth (no depth in "
         "the bottom 30% of the rows), half_resolution (half the width and height), underexposed "
         "(colour at 60%), overexposed (colour at 140%, saturating), night (45% near to 8% at the "
         "horizon, noise) (default all)",
         &variants_list);
  cl.add("markdown", "write the tables here", &markdown);
  cl.add("csv", "write one line per frame, depth, variant and mode here", &csv);
  cl.add("images",
         "write the overlays (real_<dataset>_<frame>_<depth>[_<variant>]_<mode>.jpg) here",
         &images);
  bool draw_candidates = false;
  cl.addFlag("candidates", "draw every traced candidate line and its verdict on the overlays",
             &draw_candidates);
  const auto parsed = cl.parse(argc, argv);
  if (parsed == tools::CommandLine::Parse::kHelp) return 0;
  if (parsed == tools::CommandLine::Parse::kError) return 2;
  if (labels_paths.empty() || realdata.empty()) {
    std::cerr << "evaluate_real: --labels and --realdata are required\n";
    return 2;
  }
  if (modes_list.empty()) modes_list = {"improved"};
  if (depths_list.empty()) depths_list = {"dataset", "sgbm"};
  for (const std::string& depth : depths_list)
    if (depth != "dataset" && depth != "sgbm") {
      std::cerr << "evaluate_real: unknown --depth " << depth << " (dataset or sgbm)\n";
      return 2;
    }
  for (const std::string& mode : modes_list) {
    Params p;
    if (!paramsForMode(mode, p)) {
      std::cerr << "evaluate_real: unknown --mode " << mode << " (improved or paper)\n";
      return 2;
    }
  }
  std::vector<tools::RealVariant> variants;
  for (const std::string& name : variants_list) {
    tools::RealVariant v;
    if (!tools::realVariantFromName(name, v)) {
      std::cerr << "evaluate_real: unknown variant " << name << "\n";
      return 2;
    }
    variants.push_back(v);
  }
  if (variants.empty()) variants = tools::allRealVariants();
  std::string error;
  std::vector<tools::LabelledFrame> labels;
  for (const std::string& path : labels_paths) {
    std::vector<tools::LabelledFrame> more;
    if (!tools::readRealLabels(path, more, error)) {
      std::cerr << "evaluate_real: " << error << "\n";
      return 1;
    }
    labels.insert(labels.end(), more.begin(), more.end());
  }
  if (!images.empty()) fs::create_directories(images);

  std::vector<std::string> datasets;
  for (const auto& l : labels)
    if (std::find(datasets.begin(), datasets.end(), l.dataset) == datasets.end())
      datasets.push_back(l.dataset);

  std::vector<Row> rows;
  cv::Mat overlay;
  for (const std::string& ds : datasets) {
    const fs::path folder = fs::path(realdata) / ds;
    if (!fs::is_directory(folder)) {
      std::cerr << "evaluate_real: " << folder.string() << " not found, skipped\n";
      continue;
    }
    for (const std::string& depth : depths_list) {
      tools::DatasetOptions opt;
      opt.path = folder.string();
      opt.depth = depth;
      auto reader = tools::openDataset(opt, error);
      if (!reader) {
        if (depth != "dataset") continue;  // no stereo pair: that depth source does not apply
        std::cerr << "evaluate_real: " << error << "\n";
        return 1;
      }
      const bool sequence = !reader->independentFrames();
      // the frames of this dataset and depth source (a frame set: the labelled ones; a
      // sequence: all of them), kept in memory so that the stereo depth is computed once for
      // every mode
      std::vector<tools::DatasetFrame> frames;
      std::vector<tools::LabelledFrame> frame_labels;
      std::vector<bool> has_label;
      tools::DatasetFrame frame;
      while (reader->next(frame)) {
        tools::LabelledFrame label;
        const bool labelled = tools::realLabelOf(labels, ds, frame.name, label);
        if (!labelled && !sequence) continue;
        if (!labelled) label.dataset = ds, label.frame = frame.name;
        tools::undistortLabel(frame.intrinsics, frame.distortion, label);
        frames.push_back(frame);
        frame_labels.push_back(label);
        has_label.push_back(labelled);
        frame = tools::DatasetFrame();
      }
      if (!reader->error().empty()) {
        std::cerr << "evaluate_real: " << reader->error() << "\n";
        return 1;
      }
      const std::vector<ReferencePlane> references =
          sequence ? sequenceReferences(frames) : std::vector<ReferencePlane>();
      Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();
      const bool have_mount = sequence && sequenceMount(references, mount);
      const std::vector<tools::RealVariant> run_variants =
          sequence ? std::vector<tools::RealVariant>{tools::RealVariant::kAsIs} : variants;
      for (const std::string& mode : modes_list) {
        tools::ParamChoice choice;
        choice.mode = mode;
        choice.overrides = overrides;
        Params params;
        if (!tools::buildParams(choice, params, error)) {
          std::cerr << "evaluate_real: " << error << "\n";
          return 2;
        }
        tools::RealScoringRules rules;
        rules.dashed_coverage = params.dashed_coverage;
        rules.yellowness = params.yellow_threshold;
        LaneDetector detector(params);
        Result result;
        for (const tools::RealVariant variant : run_variants) {
          if (sequence) detector.reset();  // a new drive
          for (size_t i = 0; i < frames.size(); ++i) {
            tools::DatasetFrame f = frames[i];
            tools::LabelledFrame variant_label = frame_labels[i];
            tools::applyRealVariant(variant, f, variant_label);
            const tools::LabelledFrame* label = &variant_label;
            if (!sequence) detector.reset();  // unrelated snapshots
            Frame input = f.toFrame();
            if (have_mount) {
              input.has_vehicle_frame = true;
              input.vehicle_from_camera = mount;
            }
            detector.detect(input, result);
            if (!has_label[i]) continue;  // a sequence's frame outside its labelled key frames
            Row row;
            row.dataset = ds;
            row.frame = f.name;
            row.depth = f.depth_source;
            row.variant = tools::realVariantName(variant);
            row.label = variant_label;
            row.mode = mode;
            row.sequence = sequence;
            row.lane = label->lane;
            row.ms = result.timings.total;
            // reference plane: RANSAC on the LiDAR (or the sensor's) road points; in a
            // sequence the median over the frames around (sequenceReferences())
            Eigen::Vector3d n(0, -1, 0);
            double d = 0.0;
            bool have_plane = false;
            if (sequence) {
              have_plane = references[i].valid;
              n = references[i].normal;
              d = references[i].distance;
            } else {
              have_plane = f.referenceRoadPlane(n, d);
            }
            // the plane check: frames with a LiDAR (an RGB-D sensor's own depth is no reference)
            row.have_reference = have_plane && (!f.lidar_depth.empty() || f.has_road_plane);
            if (label->lane && !have_plane) {
              std::cerr << "evaluate_real: no reference road plane for " << ds << "/" << f.name
                        << ": its labels cannot be placed\n";
              return 1;
            }
            row.score = tools::scoreRealFrame(result, *label, f.intrinsics, n, d, rules);
            row.plane = result.status == Status::kOk && result.plane.valid;
            if (row.plane && have_plane) {
              row.plane_angle =
                  std::acos(std::min(1.0, std::fabs(n.dot(result.plane.normal)))) * 180.0 / M_PI;
              row.plane_offset = std::fabs(d - result.plane.distance);
            }
            if (sequence && params.lane_model) {
              const LaneModelEstimate& lm = result.lane_model;
              row.model_valid = lm.valid;
              Result model_sides;  // the model's ego boundaries as traces, scored like sides
              modelBoundaryTrace(lm.at(BoundaryPosition::kEgoLeft), mount, model_sides.left);
              modelBoundaryTrace(lm.at(BoundaryPosition::kEgoRight), mount, model_sides.right);
              row.model = tools::scoreRealFrame(model_sides, *label, f.intrinsics, n, d, rules);
              for (int side = 0; side < 2; ++side) {
                const LaneBoundaryModel& b =
                    lm.at(side == 0 ? BoundaryPosition::kEgoLeft : BoundaryPosition::kEgoRight);
                if (lm.valid && b.valid) row.c0[side] = b.c[0];
              }
            }
            rows.push_back(row);
            if (!images.empty()) {
              drawOverlay(f.colour, f.format, f.intrinsics, result, params, overlay);
              for (int side = 0; side < 2 && draw_candidates; ++side) {
                int count = 0;
                const BoundaryCandidate* c = detector.candidates(side, count);
                drawCandidates(c, count, overlay);
              }
              // the labels, thin white
              for (const tools::LabelledSide* s : {&label->left, &label->right}) {
                if (!label->lane || !s->present) continue;
                for (size_t k = 1; k < s->points.size(); ++k)
                  cv::line(overlay, s->points[k - 1], s->points[k], cv::Scalar(255, 255, 255), 1,
                           cv::LINE_AA);
              }
              std::string stem = ds;
              std::replace(stem.begin(), stem.end(), '/', '_');
              const std::string name = "real_" + stem + "_" + f.name + "_" + f.depth_source +
                                       (variant == tools::RealVariant::kAsIs
                                            ? std::string()
                                            : std::string("_") + row.variant) +
                                       "_" + mode + ".jpg";
              const fs::path dir = sequence ? fs::path(images) / ("sequence_" + stem) : fs::path(images);
              fs::create_directories(dir);
              cv::imwrite((dir / name).string(), overlay, {cv::IMWRITE_JPEG_QUALITY, 85});
            }
          }
        }
      }
    }
  }

  if (rows.empty()) {
    std::cerr << "evaluate_real: no labelled frame was scored (does " << realdata
              << " hold the labelled datasets?)\n";
    return 1;
  }

  // Summary: per set (frame sets together, each sequence on its own), depth, variant and mode
  struct Typing {  // solid/dashed and colour of the sides right where scored
    int style_scored = 0, style_right = 0, colour_scored = 0, colour_right = 0;
    void add(const tools::RealSideScore& s) {
      if (s.style_right >= 0) ++style_scored, style_right += s.style_right;
      if (s.colour_right >= 0) ++colour_scored, colour_right += s.colour_right;
    }
  };
  struct Tally {
    int frames = 0, labelled = 0, right = 0, wrong = 0, missed = 0, negatives = 0, clean = 0;
    Typing typing, model_typing;
    int planes = 0, planes_within = 0, planes_missing = 0;
    int model_frames = 0, model_valid = 0, model_labelled = 0, model_right = 0, model_wrong = 0;
    std::vector<double> jumps;
    double ms = 0.0;
  };
  std::vector<std::pair<std::string, Tally>> tallies;
  auto tallyOf = [&](const std::string& key) -> Tally& {
    for (auto& t : tallies)
      if (t.first == key) return t.second;
    tallies.emplace_back(key, Tally());
    return tallies.back().second;
  };
  const Row* previous = nullptr;
  for (const Row& r : rows) {
    const std::string set = r.sequence ? r.dataset : std::string("frames");
    Tally& t = tallyOf(set + " | " + r.depth + " | " + r.variant + " | " + r.mode);
    ++t.frames;
    t.ms += r.ms;
    for (const tools::RealSideScore* s : {&r.score.left, &r.score.right}) {
      t.labelled += s->labelled;
      t.right += s->correct;
      t.wrong += s->wrong;
      t.missed += s->missed;
      t.typing.add(*s);
    }
    if (!r.lane) {
      ++t.negatives;
      t.clean += !r.score.wrong;
    }
    if (r.have_reference) {
      ++t.planes;
      if (!r.plane) ++t.planes_missing;
      else t.planes_within += r.plane_angle <= 1.5;
    }
    if (r.sequence) {
      ++t.model_frames;
      t.model_valid += r.model_valid;
      for (const tools::RealSideScore* s : {&r.model.left, &r.model.right}) {
        t.model_labelled += s->labelled;
        t.model_right += s->correct;
        t.model_wrong += s->wrong;
        t.model_typing.add(*s);
      }
      if (previous && previous->sequence && previous->dataset == r.dataset &&
          previous->depth == r.depth && previous->mode == r.mode)
        for (int side = 0; side < 2; ++side)
          if (std::isfinite(r.c0[side]) && std::isfinite(previous->c0[side]))
            t.jumps.push_back(std::fabs(r.c0[side] - previous->c0[side]));
    }
    previous = &r;
  }
  auto pct = [](int a, int b) { return b ? fmt(100.0 * a / b, "%.0f%%") : std::string("-"); };
  auto of = [](int a, int b) { return std::to_string(a) + " of " + std::to_string(b); };
  std::ostringstream md;
  md << "| set | depth | variant | mode | frames | labelled sides | right | wrong | missed | "
        "no-lane frames clean | solid/dashed right | colour right | plane within 1.5 deg | "
        "lane model valid | model sides right / wrong | model solid/dashed right | model colour "
        "right | model c0 change p95 (m) | ms/frame |\n";
  md << "| --- | --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | "
        "---: | ---: | ---: | ---: | ---: | ---: |\n";
  for (auto& [key, t] : tallies) {
    std::string p95 = "-";
    if (!t.jumps.empty()) {
      std::sort(t.jumps.begin(), t.jumps.end());
      p95 = fmt(t.jumps[std::min(t.jumps.size() - 1,
                                 static_cast<size_t>(std::ceil(0.95 * t.jumps.size())) - 1)],
                "%.3f");
    }
    md << "| " << key << " | " << t.frames << " | " << t.labelled << " | " << t.right << " ("
       << pct(t.right, t.labelled) << ") | " << t.wrong << " (" << pct(t.wrong, t.labelled)
       << ") | " << t.missed << " | " << of(t.clean, t.negatives) << " | "
       << of(t.typing.style_right, t.typing.style_scored) << " | "
       << of(t.typing.colour_right, t.typing.colour_scored) << " | " << of(t.planes_within, t.planes)
       << (t.planes_missing ? " (" + std::to_string(t.planes_missing) + " none)" : std::string())
       << " | "
       << (t.model_frames ? pct(t.model_valid, t.model_frames) : std::string("-")) << " | "
       << (t.model_frames ? pct(t.model_right, t.model_labelled) + " / " +
                                pct(t.model_wrong, t.model_labelled)
                          : std::string("-"))
       << " | "
       << (t.model_frames ? of(t.model_typing.style_right, t.model_typing.style_scored)
                          : std::string("-"))
       << " | "
       << (t.model_frames ? of(t.model_typing.colour_right, t.model_typing.colour_scored)
                          : std::string("-"))
       << " | " << p95 << " | " << fmt(t.ms / std::max(1, t.frames), "%.1f") << " |\n";
  }
  md << "\nPer frame (as recorded, each mode):\n\n";
  md << "| data | frame | depth | mode | left (label / reported) | left | right (label / "
        "reported) | right | plane vs LiDAR (deg / m) |\n";
  md << "| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  int sides_wrong = 0;
  for (const Row& r : rows) {
    sides_wrong += r.score.left.wrong + r.score.right.wrong;
    if (r.variant != "as_is") continue;
    const tools::LabelledFrame* label = &r.label;
    const tools::LabelledSide none;
    const tools::LabelledSide& ll = label->lane ? label->left : none;
    const tools::LabelledSide& lr = label->lane ? label->right : none;
    md << "| " << r.dataset << " | " << r.frame << " | " << r.depth << " | " << r.mode << " | "
       << kindText(r.score.left, ll) << " | " << sideText(r.score.left) << " | "
       << kindText(r.score.right, lr) << " | " << sideText(r.score.right) << " | "
       << (r.plane ? fmt(r.plane_angle) + " / " + fmt(r.plane_offset, "%.3f") : "no plane")
       << " |\n";
  }
  std::cout << md.str();
  if (!markdown.empty() && !(std::ofstream(markdown) << md.str())) {
    std::cerr << "evaluate_real: cannot write " << markdown << "\n";
    return 1;
  }
  if (!csv.empty()) {
    std::ofstream out(csv);
    // (a side's style / colour: 1 the labelled one, 0 another, empty not scored)
    out << "dataset,frame,depth,variant,mode,sequence,lane,left_labelled,left_reported,left_kind,"
           "left_fraction,left_correct,left_style_right,left_colour_right,right_labelled,"
           "right_reported,right_kind,right_fraction,right_correct,right_style_right,"
           "right_colour_right,plane,plane_angle_deg,plane_offset_m,model_valid,"
           "model_left_correct,model_right_correct,model_left_style_right,model_left_colour_right,"
           "model_right_style_right,model_right_colour_right,model_c0_left,model_c0_right,ms\n";
    const auto scored = [](int v) { return v < 0 ? std::string() : std::to_string(v); };
    for (const Row& r : rows) {
      out << r.dataset << "," << r.frame << "," << r.depth << "," << r.variant << "," << r.mode
          << "," << r.sequence << "," << r.lane;
      for (const tools::RealSideScore* s : {&r.score.left, &r.score.right})
        out << "," << s->labelled << "," << s->reported << ","
            << (s->reported ? boundaryKindName(s->reported_kind) : "") << "," << fmt(s->fraction)
            << "," << s->correct << "," << scored(s->style_right) << ","
            << scored(s->colour_right);
      out << "," << r.plane << "," << fmt(r.plane_angle, "%.3f") << ","
          << fmt(r.plane_offset, "%.4f") << "," << r.model_valid << "," << r.model.left.correct
          << "," << r.model.right.correct;
      for (const tools::RealSideScore* s : {&r.model.left, &r.model.right})
        out << "," << scored(s->style_right) << "," << scored(s->colour_right);
      out << "," << fmt(r.c0[0], "%.3f") << ","
          << fmt(r.c0[1], "%.3f") << "," << fmt(r.ms) << "\n";
    }
    if (!out.flush()) {
      std::cerr << "evaluate_real: cannot write " << csv << "\n";
      return 1;
    }
  }
  return sides_wrong == 0 ? 0 : 3;
}
