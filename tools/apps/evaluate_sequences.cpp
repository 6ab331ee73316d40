// evaluate_sequences: Table-1 evaluation of the detector modes on sequences with lane ground
// truth (METHOD.md section 6 generalised to sides reported separately with a kind: scoring.h),
// plus real data without it (KITTI plane check against the LiDAR depth, TUM frames without any
// lane). Writes a Markdown report, a per-frame CSV and an overlay picture per sequence; the lane
// model (issue 14) is scored against the true lane model (lane_model_scoring.h) into its own
// Markdown report and per-boundary CSV, and the lane grid built from it (issue 25) against the
// true boundaries (lane_grid_scoring.h) into another Markdown table.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector/lane_grid.h"
#include "rgbd_lane_detector/overlay.h"
#include "rgbd_lane_detector_tools/command_line.h"
#include "rgbd_lane_detector_tools/dataset/dataset.h"
#include "rgbd_lane_detector_tools/detector_setup.h"
#include "rgbd_lane_detector_tools/lane_grid_scoring.h"
#include "rgbd_lane_detector_tools/lane_model_report.h"
#include "rgbd_lane_detector_tools/params_io.h"
#include "rgbd_lane_detector_tools/plane_check.h"
#include "rgbd_lane_detector_tools/progress.h"
#include "rgbd_lane_detector_tools/scoring.h"

using namespace rgbd_lane_detector;
namespace fs = std::filesystem;

namespace {

/// Paper's Table 1 (frames, TP %, FP %).
struct PaperRow {
  const char* name;
  int frames;
  double tp, fp;
};
const PaperRow kPaperTable[] = {{"01-SUMMER", 942, 87.0, 0.6},
                                {"01-FOG", 1098, 84.0, 2.0},
                                {"06-FOG", 857, 80.0, 4.0},
                                {"R200", 620, 53.0, 7.0}};

struct Mode {
  std::string name;  // paper, improved, paper-colour, improved-colour
  Params params;
};

struct Input {
  std::string name, path;
  enum Kind { kTruth, kKitti, kNoLane } kind = kTruth;
};

struct RealStats {
  int frames = 0, reported = 0, planes = 0, checked = 0, reference = 0;
  double sum_ms = 0, sum_mean = 0, sum_median = 0, sum_within = 0, sum_angle = 0;
};

bool parseNamed(const std::string& arg, std::string& name, std::string& path) {
  const size_t eq = arg.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 >= arg.size()) return false;
  name = arg.substr(0, eq);
  path = arg.substr(eq + 1);
  return true;
}

std::string fmt(const char* f, double v) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof(buf), f, v);
  return buf;
}

const char* kindText(bool present, BoundaryKind kind) {
  return present ? boundaryKindName(kind) : "none";
}

// Per-frame CSV columns of one side (see the header written in main).
void writeSideCsv(std::ostream& csv, const tools::SideScore& s) {
  csv << kindText(s.truth, s.true_kind) << "," << s.reported << ","
      << (s.reported ? boundaryKindName(s.reported_kind) : "") << ","
      << fmt("%.3f", s.reported ? s.confidence : std::nan("")) << ","
      << tools::sideOutcomeName(s.outcome) << "," << s.points << "," << s.inliers << ","
      << fmt("%.4f", s.mean_lateral) << ",";
  for (double e : s.lateral_error) csv << fmt("%.4f", e) << ",";
}

// "median / p95" of the lateral errors at distance index k, or "-".
std::string lateralCell(const tools::ScoreSummary& s, int k) {
  if (s.lateral_errors[k].empty()) return "-";
  return fmt("%.3f", s.lateralPercentile(k, 50)) + " / " + fmt("%.3f", s.lateralPercentile(k, 95)) +
         " (" + std::to_string(s.lateral_errors[k].size()) + ")";
}

// Overlays of the given modes side by side, labelled.
cv::Mat sideBySide(const std::vector<cv::Mat>& images, const std::vector<std::string>& labels) {
  std::vector<cv::Mat> tiles;
  for (size_t i = 0; i < images.size(); ++i) {
    cv::Mat t = images[i].clone();
    cv::putText(t, labels[i], cv::Point(10, t.rows - 12), cv::FONT_HERSHEY_SIMPLEX, 0.7,
                cv::Scalar(0, 0, 0), 4, cv::LINE_AA);
    cv::putText(t, labels[i], cv::Point(10, t.rows - 12), cv::FONT_HERSHEY_SIMPLEX, 0.7,
                cv::Scalar(255, 255, 255), 2, cv::LINE_AA);
    tiles.push_back(t);
  }
  cv::Mat out;
  cv::hconcat(tiles, out);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> seqs, kittis, nolanes, paper_map, sgbm_inputs;
  tools::SgbmParams sgbm;
  std::string modes_arg = "paper,improved,paper-colour,improved-colour", params_file;
  std::string out_dir = "build/eval", markdown, csv_path, images_dir;
  std::string picture_modes = "paper,improved";
  std::string model_modes = "improved", model_markdown, model_csv_path, model_suffix;
  std::string grid_markdown;
  int picture_frame = -1, max_frames = -1;
  bool quiet = false;
  tools::CommandLine cl(
      "evaluate_sequences",
      "Score detector modes on sequences with lane ground truth (scoring.h: METHOD.md section 6 "
      "per side, with kinds) and on real data.\nexample: evaluate_sequences --seq summer=build/data/summer --paper "
      "summer=01-SUMMER --kitti kitti=../shared/realdata/kitti2015 --markdown build/eval/table.md");
  cl.add("seq", "NAME=PATH of a SYNTHIA-SEQS folder with GT/LANES", &seqs);
  cl.add("kitti", "NAME=PATH of KITTI frames (plane check against the LiDAR depth)", &kittis);
  cl.add("no-lane", "NAME=PATH of frames without any lane (every report is an FP)", &nolanes);
  cl.add("sgbm",
         "NAME of a --kitti / --no-lane input whose depth is computed from its colour stereo pair "
         "(StereoSGBM) instead of read (its LiDAR still checks the plane)",
         &sgbm_inputs);
  tools::addSgbmOptions(cl, sgbm);
  cl.add("paper", "NAME=ROW: show the paper's Table 1 row ROW (01-SUMMER, 01-FOG, 06-FOG, R200)",
         &paper_map);
  cl.add("modes", "comma-separated modes (paper, improved, paper-colour, improved-colour)",
         &modes_arg);
  cl.add("params", "YAML parameter overrides applied to every mode", &params_file);
  cl.add("out", "folder for the CSV and intermediate files (default build/eval)", &out_dir);
  cl.add("markdown", "Markdown report path (default <out>/results.md)", &markdown);
  cl.add("csv", "per-frame CSV path (default <out>/per_frame.csv)", &csv_path);
  cl.add("images", "folder of overlay pictures (default <out>/images)", &images_dir);
  cl.add("picture-modes", "modes drawn side by side in the pictures (default paper,improved)",
         &picture_modes);
  cl.add("picture-frame", "frame of each sequence drawn in the picture (default: middle)",
         &picture_frame);
  cl.add("max-frames", "use at most N frames per sequence", &max_frames);
  cl.add("lane-model-modes",
         "comma-separated modes whose lane model is scored against the true lane model "
         "(default improved)",
         &model_modes);
  cl.add("lane-model-markdown", "Markdown of the lane-model scores (default <out>/lane_model.md)",
         &model_markdown);
  cl.add("lane-model-csv", "per-boundary CSV of the lane model (default <out>/lane_model.csv)",
         &model_csv_path);
  cl.add("lane-model-suffix", "text appended to the lane-model section titles (e.g. ', seed 2')",
         &model_suffix);
  cl.add("lane-grid-markdown",
         "Markdown of the lane grid's scores, for the lane-model modes (default <out>/lane_grid.md)",
         &grid_markdown);
  cl.addFlag("quiet", "no progress bars", &quiet);
  const auto parsed = cl.parse(argc, argv);
  if (parsed == tools::CommandLine::Parse::kHelp) return 0;
  if (parsed == tools::CommandLine::Parse::kError) return 2;

  std::vector<Input> inputs;
  for (auto* list : {&seqs, &kittis, &nolanes}) {
    for (const auto& a : *list) {
      Input in;
      if (!parseNamed(a, in.name, in.path)) {
        std::cerr << "evaluate_sequences: expected NAME=PATH, got '" << a << "'\n";
        return 2;
      }
      in.kind = list == &seqs ? Input::kTruth : list == &kittis ? Input::kKitti : Input::kNoLane;
      inputs.push_back(in);
    }
  }
  if (inputs.empty()) {
    std::cerr << "evaluate_sequences: give at least one --seq, --kitti or --no-lane\n";
    return 2;
  }
  for (const auto& name : sgbm_inputs) {
    if (std::none_of(inputs.begin(), inputs.end(),
                     [&name](const Input& in) { return in.name == name; })) {
      std::cerr << "evaluate_sequences: --sgbm " << name << ": no input of that name\n";
      return 2;
    }
  }
  std::map<std::string, const PaperRow*> paper_rows;
  for (const auto& a : paper_map) {
    std::string name, row;
    const PaperRow* found = nullptr;
    if (parseNamed(a, name, row))
      for (const auto& r : kPaperTable)
        if (row == r.name) found = &r;
    if (!found) {
      std::cerr << "evaluate_sequences: --paper " << a
                << ": expected NAME=01-SUMMER|01-FOG|06-FOG|R200\n";
      return 2;
    }
    paper_rows[name] = found;
  }
  std::vector<Mode> modes;
  std::stringstream ms(modes_arg);
  for (std::string m; std::getline(ms, m, ',');) {
    Mode mode;
    mode.name = m;
    const bool colour = m.size() > 7 && m.compare(m.size() - 7, 7, "-colour") == 0;
    const std::string base = colour ? m.substr(0, m.size() - 7) : m;
    std::string error;
    if (!paramsForMode(base, mode.params)) {
      std::cerr << "evaluate_sequences: unknown mode '" << m << "'\n";
      return 2;
    }
    if (!params_file.empty() && !tools::loadParamsYaml(params_file, mode.params, error)) {
      std::cerr << "evaluate_sequences: " << error << "\n";
      return 2;
    }
    if (colour) mode.params.use_depth = false;
    modes.push_back(mode);
  }
  if (modes.empty()) {
    std::cerr << "evaluate_sequences: no modes\n";
    return 2;
  }
  if (markdown.empty()) markdown = (fs::path(out_dir) / "results.md").string();
  if (csv_path.empty()) csv_path = (fs::path(out_dir) / "per_frame.csv").string();
  if (images_dir.empty()) images_dir = (fs::path(out_dir) / "images").string();
  if (model_markdown.empty()) model_markdown = (fs::path(out_dir) / "lane_model.md").string();
  if (model_csv_path.empty()) model_csv_path = (fs::path(out_dir) / "lane_model.csv").string();
  if (grid_markdown.empty()) grid_markdown = (fs::path(out_dir) / "lane_grid.md").string();
  std::error_code ec;
  for (const std::string& d :
       {out_dir, images_dir, fs::path(markdown).parent_path().string(),
        fs::path(csv_path).parent_path().string(), fs::path(model_markdown).parent_path().string(),
        fs::path(model_csv_path).parent_path().string(),
        fs::path(grid_markdown).parent_path().string()}) {
    if (!d.empty()) fs::create_directories(d, ec);
  }
  std::ofstream csv(csv_path), model_csv(model_csv_path);
  if (!csv || !model_csv) {
    std::cerr << "evaluate_sequences: cannot write " << (csv ? model_csv_path : csv_path) << "\n";
    return 1;
  }
  tools::LaneModelReport model_report(&model_csv);
  tools::LaneGridReport grid_report;
  LaneGrid grid;
  csv << "sequence,mode,frame,outcome,lane_required,reported,plane_valid,plane_ok,"
         "angle_error_deg,offset_error";
  for (const char* side : {"left", "right"})
    for (const char* col : {"truth", "reported", "kind", "confidence", "outcome", "points",
                            "inliers", "mean_lateral", "lateral_5", "lateral_10", "lateral_20",
                            "lateral_40"})
      csv << "," << side << "_" << col;
  csv << ",left_score,right_score,ms\n";

  std::ostringstream table, sides, lateral, real;
  lateral << "| sequence | mode | 5 m | 10 m | 20 m | 40 m |\n"
          << "| --- | --- | ---: | ---: | ---: | ---: |\n";
  table << "| sequence | mode | frames | lane frames | TP % | partial % | FP % | miss % | "
           "plane % | plane ok % | plane angle err (deg) | plane offset err (m) | ms/frame | "
           "paper (TP / FP) |\n"
        << "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | "
           "---: | --- |\n";
  sides << "| sequence | mode | sides reported | correct | precision % | true sides | recall % | "
           "paint on a road edge | road edge on paint | where none |\n"
        << "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
  real << "| data | mode | frames | lane reported % | plane % | mean \\|n.p+d\\| (m) | median (m) "
          "| within 10 cm | angle to LiDAR RANSAC plane (deg) | ms/frame |\n"
       << "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
  bool any_truth = false, any_real = false;

  for (const Input& in : inputs) {
    tools::DatasetOptions opts;
    opts.path = in.path;
    opts.max_frames = max_frames;
    if (std::find(sgbm_inputs.begin(), sgbm_inputs.end(), in.name) != sgbm_inputs.end()) {
      opts.depth = "sgbm";
      opts.sgbm = sgbm;
    }
    std::string error;
    auto reader = tools::openDataset(opts, error);
    if (!reader) {
      std::cerr << "evaluate_sequences: " << in.name << ": " << error << "\n";
      return 1;
    }
    tools::SequenceTruth truth;
    if (in.kind == Input::kTruth) {
      if (reader->groundTruthPath().empty()) {
        std::cerr << "evaluate_sequences: " << in.name << ": no GT/LANES/ground_truth.json in "
                  << in.path << "\n";
        return 1;
      }
      if (!tools::readGroundTruth(reader->groundTruthPath(), truth, error)) {
        std::cerr << "evaluate_sequences: " << error << "\n";
        return 1;
      }
    }
    std::vector<std::unique_ptr<LaneDetector>> detectors;
    for (const auto& m : modes) detectors.push_back(std::make_unique<LaneDetector>(m.params));
    std::vector<tools::ScoreSummary> summaries(modes.size());
    std::vector<RealStats> reals(modes.size());
    std::vector<cv::Mat> pictures(modes.size());
    const int total = reader->size();
    const int pic = picture_frame >= 0 ? picture_frame : std::max(0, total / 2);
    std::vector<bool> score_model(modes.size());
    for (size_t m = 0; m < modes.size(); ++m)
      score_model[m] = in.kind == Input::kTruth && truth.has_mount &&
                       ("," + model_modes + ",").find("," + modes[m].name + ",") != std::string::npos;
    Result r;
    tools::DatasetFrame f;
    tools::ProgressBar progress(in.name, total, !quiet);
    int n = 0;
    while (reader->next(f)) {
      const tools::FrameTruth* t = truth.find(f.index);
      std::vector<Eigen::Vector3d> region;  // the LiDAR, also when the detector gets SGBM depth
      if (in.kind == Input::kKitti) f.referenceRoadPoints(region);
      for (size_t m = 0; m < modes.size(); ++m) {
        if (reader->independentFrames()) detectors[m]->reset();
        Frame frame = f.toFrame();
        if (truth.has_mount) {
          // the lane model in base_link through the fixed mount, as the bag's /tf_static gives it
          frame.has_vehicle_frame = true;
          frame.vehicle_from_camera = truth.mount;
        }
        detectors[m]->detect(frame, r);
        const tools::Detection det = tools::detectionFromResult(r);
        // real data: a lane is reported when a side is (a plane alone is the road surface)
        const bool reported = det.left_reported || det.right_reported;
        // the lane grid of a scored lane model: the default grid and one allowing lane changes
        LaneGridSettings grid_settings = laneGridSettings(detectors[m]->params());
        if (n == pic) {
          drawOverlay(f.colour, f.format, f.intrinsics, r, detectors[m]->params(), pictures[m]);
          if (score_model[m]) {
            grid.build(r.lane_model, grid_settings);
            drawLaneGridInset(grid, pictures[m]);
          }
        }
        if (in.kind == Input::kTruth) {
          if (!t) continue;
          const tools::FrameScore s = tools::scoreFrame(det, *t);
          summaries[m].add(s, r.timings.total);
          if (score_model[m]) {
            model_report.add(in.name, modes[m].name, f.index,
                             tools::scoreLaneModel(r.lane_model, *t));
            grid_settings.allow_lane_change = false;
            grid.build(r.lane_model, grid_settings);
            const tools::LaneGridScore ego = tools::scoreLaneGrid(grid, r.lane_model, *t, false);
            grid_settings.allow_lane_change = true;
            grid.build(r.lane_model, grid_settings);
            grid_report.add(in.name, modes[m].name, f.index, ego,
                            tools::scoreLaneGrid(grid, r.lane_model, *t, true));
          }
          csv << in.name << "," << modes[m].name << "," << f.index << ","
              << tools::outcomeName(s.outcome) << "," << s.lane_required << "," << s.reported
              << "," << s.plane_valid << "," << s.plane_ok << ","
              << fmt("%.4f", s.angle_error_deg) << "," << fmt("%.4f", s.offset_error) << ",";
          writeSideCsv(csv, s.left);
          writeSideCsv(csv, s.right);
          csv << fmt("%.4f", r.left.peak_score) << "," << fmt("%.4f", r.right.peak_score) << ","
              << fmt("%.3f", r.timings.total) << "\n";
        } else {
          RealStats& st = reals[m];
          ++st.frames;
          st.reported += reported;
          st.planes += det.plane_valid;
          st.sum_ms += r.timings.total;
          if (in.kind == Input::kKitti && det.plane_valid && !region.empty()) {
            const tools::PlaneResiduals res =
                tools::planeResiduals(region, r.plane.normal, r.plane.distance);
            ++st.checked;
            st.sum_mean += res.mean_abs;
            st.sum_median += res.median_abs;
            st.sum_within += res.within_10cm;
            Eigen::Vector3d nr;
            double dr;
            if (tools::ransacPlane(region, 0.05, nr, dr)) {
              ++st.reference;
              st.sum_angle +=
                  std::acos(std::min(1.0, std::fabs(nr.dot(r.plane.normal)))) * 180.0 / M_PI;
            }
          }
        }
      }
      progress.update(++n);
    }
    progress.finish();
    if (!reader->error().empty()) {
      std::cerr << "evaluate_sequences: " << in.name << ": " << reader->error() << "\n";
      return 1;
    }
    // picture: every mode's overlay of one frame side by side
    std::vector<cv::Mat> imgs;
    std::vector<std::string> labels;
    for (size_t m = 0; m < modes.size(); ++m) {
      if (pictures[m].empty() ||
          ("," + picture_modes + ",").find("," + modes[m].name + ",") == std::string::npos)
        continue;
      imgs.push_back(pictures[m]);
      labels.push_back(in.name + " / " + modes[m].name);
    }
    if (!imgs.empty()) {
      cv::Mat pic_img = sideBySide(imgs, labels);
      if (pic_img.cols > 2600) cv::resize(pic_img, pic_img, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
      cv::imwrite((fs::path(images_dir) / (in.name + ".jpg")).string(), pic_img,
                  {cv::IMWRITE_JPEG_QUALITY, 85});
    }
    for (size_t m = 0; m < modes.size(); ++m) {
      if (in.kind == Input::kTruth) {
        any_truth = true;
        const tools::ScoreSummary& s = summaries[m];
        std::string paper = "";
        const auto it = paper_rows.find(in.name);
        if (it != paper_rows.end() && modes[m].name == "paper") {
          paper = std::string(it->second->name) + ": " + fmt("%.0f", it->second->tp) + "% / " +
                  fmt("%.1f", it->second->fp) + "% (" + std::to_string(it->second->frames) +
                  " fr.)";
        }
        table << "| " << in.name << " | " << modes[m].name << " | " << s.frames << " | "
              << s.required << " | " << fmt("%.1f", s.tpPercent()) << " | "
              << fmt("%.1f", s.partialPercent()) << " | " << fmt("%.1f", s.fpPercent()) << " | "
              << fmt("%.1f", s.missPercent()) << " | " << fmt("%.0f", s.planePercent()) << " | "
              << fmt("%.0f", s.planeOkPercent()) << " | " << fmt("%.3f", s.meanAngleError())
              << " | " << fmt("%.3f", s.meanOffsetError()) << " | " << fmt("%.1f", s.meanMs())
              << " | " << paper << " |\n";
        sides << "| " << in.name << " | " << modes[m].name << " | " << s.sides_reported << " | "
              << s.sides_correct << " | " << fmt("%.1f", s.sidePrecision()) << " | "
              << s.sides_true << " | " << fmt("%.1f", s.sideRecall()) << " | "
              << s.confusion[1][0] << " | " << s.confusion[0][1] << " | "
              << s.confusion[2][0] + s.confusion[2][1] << " |\n";
        lateral << "| " << in.name << " | " << modes[m].name;
        for (int k = 0; k < tools::kNumLateralDistances; ++k) lateral << " | " << lateralCell(s, k);
        lateral << " |\n";
        std::printf("%-22s %-16s frames %4d (%4d need a lane)  TP %5s%%  partial %5s%%  "
                    "FP %5s%%  miss %5s%%\n",
                    in.name.c_str(), modes[m].name.c_str(), s.frames, s.required,
                    fmt("%.1f", s.tpPercent()).c_str(), fmt("%.1f", s.partialPercent()).c_str(),
                    fmt("%.1f", s.fpPercent()).c_str(), fmt("%.1f", s.missPercent()).c_str());
      } else {
        any_real = true;
        const RealStats& st = reals[m];
        const double fr = std::max(1, st.frames);
        real << "| " << in.name << (opts.depth == "sgbm" ? " (SGBM depth)" : "")
             << (in.kind == Input::kNoLane ? " (no lane: reports are FP)" : "")
             << " | " << modes[m].name << " | " << st.frames << " | "
             << fmt("%.0f", 100.0 * st.reported / fr) << " | "
             << fmt("%.0f", 100.0 * st.planes / fr) << " | "
             << (st.checked ? fmt("%.3f", st.sum_mean / st.checked) : "-") << " | "
             << (st.checked ? fmt("%.3f", st.sum_median / st.checked) : "-") << " | "
             << (st.checked ? fmt("%.0f%%", 100.0 * st.sum_within / st.checked) : "-") << " | "
             << (st.reference ? fmt("%.2f", st.sum_angle / st.reference) : "-") << " | "
             << fmt("%.1f", st.sum_ms / fr) << " |\n";
        std::printf("%-22s %-16s frames %4d  reported %d  planes %d\n", in.name.c_str(),
                    modes[m].name.c_str(), st.frames, st.reported, st.planes);
      }
    }
  }

  std::ofstream md(markdown);
  if (any_truth) {
    md << "#### Synthetic sequences: frames\n\n"
       << "Rules: `tools/include/rgbd_lane_detector_tools/scoring.h` (METHOD.md section 6 with "
          "each side scored on its own, kind included). TP, partial and miss are % of the lane "
          "frames (frames that require a lane: the ego lane has a boundary and no intersection "
          "ends its lines within 20 m); FP (a wrong side, or a side with a wrong or missing "
          "plane) is % of all frames. METHOD.md's classic FP (reported, not TP) is partial + "
          "FP. A plane alone is no lane report: plane % counts valid planes over all frames, "
          "plane ok % those within 3 deg / 0.15 m; the errors average every valid plane.\n\n"
       << table.str() << "\n";
    md << "#### Synthetic sequences: sides\n\n"
       << "Per reported side (left and right counted apart): precision = correct / reported "
          "(all frames); recall = correct / true sides of the lane frames; the last three "
          "columns count reported sides by their kind against the true kind of that side, on "
          "its line or not (paint on a kerb, rail or asphalt edge; a road edge on paint), and "
          "sides reported where the ego lane has no boundary."
          "\n\n"
       << sides.str() << "\n";
    md << "#### Synthetic sequences: lateral error of the reported ego sides\n\n"
       << "Median / 95th percentile (m) and count of |y_reported - y_true| at 5, 10, 20 and "
          "40 m ahead in base_link (the true vehicle frame), over every reported side with a "
          "true boundary whose trace reaches that distance (right or wrong).\n\n"
       << lateral.str() << "\n";
    md << "The paper's Table 1 for reference (SYNTHIA-SEQS and RealSense R200 data, not these "
          "sequences):\n\n| sequence | frames | TP | FP |\n| --- | ---: | ---: | ---: |\n";
    for (const auto& p : kPaperTable)
      md << "| " << p.name << " | " << p.frames << " | " << fmt("%.0f", p.tp) << "% | "
         << fmt("%.1f", p.fp) << "% |\n";
    md << "\n";
  }
  if (any_real) md << "#### Real data (no lane ground truth)\n\n" << real.str() << "\n";
  if (!md) {
    std::cerr << "evaluate_sequences: cannot write " << markdown << "\n";
    return 1;
  }
  std::ofstream model_md(model_markdown);
  if (!model_report.empty()) model_report.writeMarkdown(model_md, model_suffix);
  if (!model_md || !model_csv) {
    std::cerr << "evaluate_sequences: cannot write " << model_markdown << "\n";
    return 1;
  }
  std::ofstream grid_md(grid_markdown);
  if (!grid_report.empty()) grid_report.writeMarkdown(grid_md, model_suffix);
  if (!grid_md) {
    std::cerr << "evaluate_sequences: cannot write " << grid_markdown << "\n";
    return 1;
  }
  return 0;
}
