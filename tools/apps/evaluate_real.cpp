// evaluate_real: score the lane detector on the hand-labelled real frames of ../shared/realdata
// (test/data/realdata_labels.yaml) with each depth source the data offers (KITTI: the LiDAR and
// StereoSGBM on the colour pair), each also mirrored and without depth near the car
// (real_variants.h), and compare each road plane with a RANSAC plane of the LiDAR's road points.
// Writes a Markdown table, a CSV and the overlays of every frame.
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
#include "rgbd_lane_detector/overlay.h"
#include "rgbd_lane_detector_tools/command_line.h"
#include "rgbd_lane_detector_tools/dataset/dataset.h"
#include "rgbd_lane_detector_tools/dataset/real_variants.h"
#include "rgbd_lane_detector_tools/detector_setup.h"
#include "rgbd_lane_detector_tools/real_labels.h"

using namespace rgbd_lane_detector;
namespace fs = std::filesystem;

namespace {

struct Row {
  std::string dataset, frame, depth, variant, mode;
  tools::LabelledFrame label;  ///< as the variant sees it
  bool lane = false;
  tools::RealFrameScore score;
  bool plane = false;
  double plane_angle = NAN, plane_offset = NAN;  // against the LiDAR RANSAC plane
  double ms = 0.0;
};

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
  std::string labels_path, realdata, markdown, csv, images;
  std::vector<std::string> modes_list, depths_list, variants_list;
  tools::CommandLine cl(
      "evaluate_real",
      "Score the detector on the hand-labelled real frames (each side right when >= 80% of its\n"
      "points lie within 0.30 m of the labelled line of its kind; every side reported on a frame\n"
      "without a lane is wrong), with every depth source of each dataset.\n"
      "example: evaluate_real --labels test/data/realdata_labels.yaml --realdata ../shared/realdata"
      " --markdown build/eval/real.md --images docs/images");
  cl.add("labels", "label file (required)", &labels_path);
  cl.add("realdata", "folder holding the labelled datasets (required)", &realdata);
  cl.add("mode", "detector mode to score (repeatable; default improved)", &modes_list);
  cl.add("depth", "depth source for stereo datasets: dataset, sgbm (repeatable; default both)",
         &depths_list);
  cl.add("variant",
         "frame variant: as_is, mirrored (left-right), no_near_depth (no depth in the bottom 30% "
         "of the rows), half_resolution (half the width and height), underexposed (colour at "
         "60%), overexposed (colour at 140%, saturating) (repeatable; default all)",
         &variants_list);
  cl.add("markdown", "write the table here", &markdown);
  cl.add("csv", "write one line per frame, depth, variant and mode here", &csv);
  cl.add("images",
         "write the overlays (real_<dataset>_<frame>_<depth>[_<variant>]_<mode>.jpg) here",
         &images);
  const auto parsed = cl.parse(argc, argv);
  if (parsed == tools::CommandLine::Parse::kHelp) return 0;
  if (parsed == tools::CommandLine::Parse::kError) return 2;
  if (labels_path.empty() || realdata.empty()) {
    std::cerr << "evaluate_real: --labels and --realdata are required\n";
    return 2;
  }
  if (modes_list.empty()) modes_list = {"improved"};
  if (depths_list.empty()) depths_list = {"dataset", "sgbm"};
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
  if (!tools::readRealLabels(labels_path, labels, error)) {
    std::cerr << "evaluate_real: " << error << "\n";
    return 1;
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
      // the labelled frames of this dataset and depth source (a handful: kept in memory so that
      // the stereo depth is computed once for every mode)
      std::vector<tools::DatasetFrame> frames;
      tools::DatasetFrame frame;
      while (reader->next(frame)) {
        if (!tools::findRealLabel(labels, ds, frame.name)) continue;
        frames.push_back(frame);
        frame = tools::DatasetFrame();
      }
      if (!reader->error().empty()) {
        std::cerr << "evaluate_real: " << reader->error() << "\n";
        return 1;
      }
      for (const std::string& mode : modes_list) {
        tools::ParamChoice choice;
        choice.mode = mode;
        Params params;
        if (!tools::buildParams(choice, params, error)) {
          std::cerr << "evaluate_real: " << error << "\n";
          return 2;
        }
        LaneDetector detector(params);
        Result result;
        for (size_t run = 0; run < variants.size() * frames.size(); ++run) {  // every variant
          const tools::RealVariant variant = variants[run / frames.size()];   // of every frame
          tools::DatasetFrame f = frames[run % frames.size()];
          tools::LabelledFrame variant_label = *tools::findRealLabel(labels, ds, f.name);
          tools::applyRealVariant(variant, f, variant_label);
          const tools::LabelledFrame* label = &variant_label;
          detector.reset();  // unrelated snapshots
          detector.detect(f.toFrame(), result);
          Row row;
          row.dataset = ds;
          row.frame = f.name;
          row.depth = f.depth_source;
          row.variant = tools::realVariantName(variant);
          row.label = variant_label;
          row.mode = mode;
          row.lane = label->lane;
          row.ms = result.timings.total;
          // reference plane: RANSAC on the LiDAR (or the sensor's) road points
          Eigen::Vector3d n(0, -1, 0);
          double d = 0.0;
          const bool have_ref = f.referenceRoadPlane(n, d);
          if (label->lane && !have_ref) {
            std::cerr << "evaluate_real: no reference road plane for " << ds << "/" << f.name
                      << ": its labels cannot be placed\n";
            return 1;
          }
          row.score = tools::scoreRealFrame(result, *label, f.intrinsics, n, d);
          row.plane = result.status == Status::kOk && result.plane.valid;
          if (row.plane && have_ref) {
            row.plane_angle =
                std::acos(std::min(1.0, std::fabs(n.dot(result.plane.normal)))) * 180.0 / M_PI;
            row.plane_offset = std::fabs(d - result.plane.distance);
          }
          rows.push_back(row);
          if (!images.empty()) {
            drawOverlay(f.colour, f.format, f.intrinsics, result, params, overlay);
            // the labels, thin white
            for (const tools::LabelledSide* s : {&label->left, &label->right}) {
              if (!label->lane || !s->present) continue;
              for (size_t i = 1; i < s->points.size(); ++i)
                cv::line(overlay, s->points[i - 1], s->points[i], cv::Scalar(255, 255, 255), 1,
                         cv::LINE_AA);
            }
            const std::string name = "real_" + ds + "_" + f.name + "_" + f.depth_source +
                                     (variant == tools::RealVariant::kAsIs
                                          ? std::string()
                                          : std::string("_") + row.variant) +
                                     "_" + mode + ".jpg";
            cv::imwrite((fs::path(images) / name).string(), overlay,
                        {cv::IMWRITE_JPEG_QUALITY, 85});
          }
        }
      }
    }
  }

  // Markdown table
  std::ostringstream md;
  md << "| data | frame | depth | variant | mode | left (label / reported) | left | right (label / "
        "reported) | right | plane vs LiDAR (deg / m) |\n";
  md << "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  int sides_labelled = 0, sides_right = 0, sides_wrong = 0, negatives = 0, negatives_clean = 0;
  for (const Row& r : rows) {
    const tools::LabelledFrame* label = &r.label;
    const tools::LabelledSide none;
    const tools::LabelledSide& ll = label->lane ? label->left : none;
    const tools::LabelledSide& lr = label->lane ? label->right : none;
    md << "| " << r.dataset << " | " << r.frame << " | " << r.depth << " | " << r.variant << " | "
       << r.mode << " | "
       << kindText(r.score.left, ll) << " | " << sideText(r.score.left) << " | "
       << kindText(r.score.right, lr) << " | " << sideText(r.score.right) << " | "
       << (r.plane ? fmt(r.plane_angle) + " / " + fmt(r.plane_offset, "%.3f") : "no plane")
       << " |\n";
    for (const tools::RealSideScore* s : {&r.score.left, &r.score.right}) {
      sides_labelled += s->labelled;
      sides_right += s->correct;
      sides_wrong += s->wrong;
    }
    if (!r.lane) {
      ++negatives;
      negatives_clean += !r.score.wrong;
    }
  }
  md << "\nLabelled sides reported right: " << sides_right << " of " << sides_labelled
     << "; sides reported wrong: " << sides_wrong << "; frames without a lane that report "
     << "nothing: " << negatives_clean << " of " << negatives << ".\n";
  std::cout << md.str();
  if (!markdown.empty()) std::ofstream(markdown) << md.str();
  if (!csv.empty()) {
    std::ofstream out(csv);
    out << "dataset,frame,depth,variant,mode,lane,left_labelled,left_reported,left_kind,left_fraction,"
           "left_correct,right_labelled,right_reported,right_kind,right_fraction,right_correct,"
           "plane,plane_angle_deg,plane_offset_m,ms\n";
    for (const Row& r : rows) {
      out << r.dataset << "," << r.frame << "," << r.depth << "," << r.variant << "," << r.mode
          << "," << r.lane;
      for (const tools::RealSideScore* s : {&r.score.left, &r.score.right})
        out << "," << s->labelled << "," << s->reported << ","
            << (s->reported ? boundaryKindName(s->reported_kind) : "") << "," << fmt(s->fraction)
            << "," << s->correct;
      out << "," << r.plane << "," << fmt(r.plane_angle, "%.3f") << ","
          << fmt(r.plane_offset, "%.4f") << "," << fmt(r.ms) << "\n";
    }
  }
  return sides_wrong == 0 ? 0 : 3;
}
