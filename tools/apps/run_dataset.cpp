// run_dataset: run the lane detector over a SYNTHIA-SEQS / TUM / KITTI folder or a rosbag;
// writes JSON Lines results, overlay images and an overlay video, and scores the frames when
// the dataset has lane ground truth.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector/overlay.h"
#include "rgbd_lane_detector_tools/command_line.h"
#include "rgbd_lane_detector_tools/dataset/dataset.h"
#include "rgbd_lane_detector_tools/detector_setup.h"
#include "rgbd_lane_detector_tools/params_io.h"
#include "rgbd_lane_detector_tools/plane_check.h"
#include "rgbd_lane_detector_tools/progress.h"
#include "rgbd_lane_detector_tools/result_json.h"
#include "rgbd_lane_detector_tools/scoring.h"

using namespace rgbd_lane_detector;
namespace fs = std::filesystem;

namespace {

struct PlaneCheckTotals {
  int frames = 0;
  double sum_mean = 0, sum_median = 0, sum_within = 0, sum_angle = 0, sum_offset = 0;
  int reference_frames = 0;
};

// Residuals of the LiDAR (else depth) points of the road region with respect to the detected
// plane, and the angle to a RANSAC plane of the same points. Returns a JSON member.
std::string checkPlane(const tools::DatasetFrame& f, const Result& r, PlaneCheckTotals& t) {
  if (!r.plane.valid) return "\"plane_check\": null";
  std::vector<Eigen::Vector3d> pts;
  f.referenceRoadPoints(pts);
  const tools::PlaneResiduals res = tools::planeResiduals(pts, r.plane.normal, r.plane.distance);
  std::string out = "\"plane_check\": {\"points\": " + std::to_string(res.points) +
                    ", \"mean_abs\": " + tools::jsonNumber(res.mean_abs) +
                    ", \"median_abs\": " + tools::jsonNumber(res.median_abs) +
                    ", \"within_10cm\": " + tools::jsonNumber(res.within_10cm);
  if (res.points > 0) {
    ++t.frames;
    t.sum_mean += res.mean_abs;
    t.sum_median += res.median_abs;
    t.sum_within += res.within_10cm;
  }
  Eigen::Vector3d n;
  double d;
  if (tools::ransacPlane(pts, 0.05, n, d)) {
    const double angle = std::acos(std::min(1.0, std::fabs(n.dot(r.plane.normal)))) * 180.0 / M_PI;
    out += ", \"reference_angle_deg\": " + tools::jsonNumber(angle) +
           ", \"reference_offset\": " + tools::jsonNumber(std::fabs(d - r.plane.distance));
    ++t.reference_frames;
    t.sum_angle += angle;
    t.sum_offset += std::fabs(d - r.plane.distance);
  }
  return out + "}";
}

}  // namespace

int main(int argc, char** argv) {
  tools::DatasetOptions data;
  tools::ParamChoice choice;
  std::string out_dir, video, overlay_format = "jpg";
  int overlay_every = 1;
  double video_fps = 10.0;
  bool draw_candidates = false, plane_check = false, quiet = false;
  tools::CommandLine cl(
      "run_dataset",
      "Run the lane detector over a dataset (SYNTHIA-SEQS, TUM, KITTI folder or rosbag).\n"
      "Writes <out>/results.jsonl, <out>/params.yaml, <out>/overlays/ and an overlay video.\n"
      "example: run_dataset --dataset build/data/summer --mode improved --out build/run/summer");
  cl.add("dataset", "dataset folder or .bag file (required)", &data.path);
  tools::addDatasetOptions(cl, data);
  tools::addParamOptions(cl, choice);
  cl.add("out", "output folder (required)", &out_dir);
  cl.add("overlays", "write the overlay of every N-th frame (0: none, default 1)", &overlay_every);
  cl.add("overlay-format", "overlay image format: jpg (default) or png", &overlay_format);
  cl.add("video", "overlay video path (MJPG .avi; default <out>/overlay.avi, 'none' to skip)",
         &video);
  cl.add("video-fps", "frame rate of the overlay video (default 10)", &video_fps);
  cl.addFlag("plane-check",
             "compare each plane with the depth of the road region (the LiDAR when the dataset "
             "has one, also with --depth sgbm)",
             &plane_check);
  cl.addFlag("candidates", "draw every traced candidate line and its verdict on the overlays",
             &draw_candidates);
  cl.addFlag("quiet", "no progress bar", &quiet);
  const auto parsed = cl.parse(argc, argv);
  if (parsed == tools::CommandLine::Parse::kHelp) return 0;
  if (parsed == tools::CommandLine::Parse::kError) return 2;
  if (data.path.empty() || out_dir.empty()) {
    std::cerr << "run_dataset: --dataset and --out are required\n";
    return 2;
  }
  if (overlay_format != "jpg" && overlay_format != "png") {
    std::cerr << "run_dataset: --overlay-format must be jpg or png\n";
    return 2;
  }
  std::string error;
  Params params;
  if (!tools::buildParams(choice, params, error)) {
    std::cerr << "run_dataset: " << error << "\n";
    return 2;
  }
  auto reader = tools::openDataset(data, error);
  if (!reader) {
    std::cerr << "run_dataset: " << error << "\n";
    return 1;
  }
  tools::SequenceTruth truth;
  const bool have_truth = !reader->groundTruthPath().empty();
  if (have_truth && !tools::readGroundTruth(reader->groundTruthPath(), truth, error)) {
    std::cerr << "run_dataset: " << error << "\n";
    return 1;
  }
  std::error_code ec;
  fs::create_directories(fs::path(out_dir) / "overlays", ec);
  if (ec) {
    std::cerr << "run_dataset: cannot create " << out_dir << ": " << ec.message() << "\n";
    return 1;
  }
  std::ofstream jsonl(fs::path(out_dir) / "results.jsonl");
  std::ofstream(fs::path(out_dir) / "params.yaml") << tools::paramsToYaml(params);
  if (!jsonl) {
    std::cerr << "run_dataset: cannot write " << out_dir << "/results.jsonl\n";
    return 1;
  }
  if (video.empty()) video = (fs::path(out_dir) / "overlay.avi").string();
  cv::VideoWriter writer;

  LaneDetector detector(params);
  Result result;
  tools::DatasetFrame frame;
  tools::ScoreSummary summary;
  PlaneCheckTotals plane_totals;
  int frames = 0, processed = 0, reported = 0, planes = 0, no_truth = 0;
  double sum_ms = 0;
  cv::Mat overlay;
  tools::ProgressBar progress(std::string("run ") + reader->kind(), reader->size(), !quiet);
  while (reader->next(frame)) {
    if (reader->independentFrames()) detector.reset();  // snapshots, not a drive
    detector.detect(frame.toFrame(), result);
    ++frames;
    std::string line;
    tools::FrameScore score;
    const tools::FrameScore* score_ptr = nullptr;
    if (have_truth) {
      if (const tools::FrameTruth* t = truth.find(frame.index)) {
        score = tools::scoreFrame(tools::detectionFromResult(result), *t);
        summary.add(score, result.timings.total);
        score_ptr = &score;
      } else {
        ++no_truth;
      }
    }
    line = tools::resultToJson(frame.index, frame.name, frame.stamp, result, score_ptr);
    if (result.status == Status::kOk) {
      ++processed;
      sum_ms += result.timings.total;
      const tools::Detection det = tools::detectionFromResult(result);
      reported += det.plane_valid || det.left_reported || det.right_reported;
      planes += det.plane_valid;
      if (plane_check) {
        line.pop_back();
        line += ", " + checkPlane(frame, result, plane_totals) + "}";
      }
    }
    jsonl << line << "\n";
    const bool want_image = overlay_every > 0 && (frames - 1) % overlay_every == 0;
    if (want_image || video != "none") {
      drawOverlay(frame.colour, frame.format, frame.intrinsics, result, detector.params(), overlay);
      if (draw_candidates) {
        for (int side = 0; side < 2; ++side) {
          int count = 0;
          const BoundaryCandidate* c = detector.candidates(side, count);
          drawCandidates(c, count, overlay);
        }
      }
      if (want_image)
        cv::imwrite((fs::path(out_dir) / "overlays" / (frame.name + "." + overlay_format)).string(),
                    overlay);
      if (video != "none") {
        if (!writer.isOpened()) {
          writer.open(video, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), video_fps,
                      overlay.size());
          if (!writer.isOpened()) {
            std::cerr << "\nrun_dataset: warning: cannot open video " << video << ", skipping it\n";
            video = "none";
          }
        }
        if (writer.isOpened()) writer.write(overlay);
      }
    }
    char extra[96];
    std::snprintf(extra, sizeof(extra), "%s %.1f ms", result.plane.valid ? "plane" : "-----",
                  result.timings.total);
    progress.update(frames, extra);
  }
  progress.finish();
  writer.release();
  if (!reader->error().empty()) {
    std::cerr << "run_dataset: " << reader->error() << "\n";
    return 1;
  }
  if (frames == 0) {
    std::cerr << "run_dataset: no frames read\n";
    return 1;
  }
  if (processed == 0) {  // every frame refused: the same reason for all, as a rule
    std::cerr << "run_dataset: no frame was processed: " << statusMessage(result.status) << "\n";
    return 1;
  }
  std::printf(
      "frames %d, processed %d, lane reported %d (%.1f%%), plane %d (%.1f%%), %.2f ms/frame "
      "(depth: %s)\n",
      frames, processed, reported, 100.0 * reported / frames, planes, 100.0 * planes / frames,
      processed ? sum_ms / processed : 0.0, frame.depth_source.c_str());
  if (have_truth) {
    std::printf(
        "ground truth: TP %.1f%%  partial %.1f%%  FP %.1f%%  miss %.1f%%  angle err %.3f deg  "
        "offset err %.3f m (%d frames scored, %d require a lane, %d without truth)\n",
        summary.tpPercent(), summary.partialPercent(), summary.fpPercent(),
        summary.missPercent(), summary.meanAngleError(), summary.meanOffsetError(),
        summary.frames, summary.required, no_truth);
  }
  if (plane_check) {
    const PlaneCheckTotals& t = plane_totals;
    if (t.frames) {
      std::printf(
          "plane check (road region depth, <= 40 m): mean |n.p+d| %.3f m, median %.3f m, "
          "%.0f%% within 10 cm (%d frames)",
          t.sum_mean / t.frames, t.sum_median / t.frames, 100.0 * t.sum_within / t.frames,
          t.frames);
      if (t.reference_frames)
        std::printf("; vs RANSAC plane: %.2f deg, %.3f m", t.sum_angle / t.reference_frames,
                    t.sum_offset / t.reference_frames);
      std::printf("\n");
    } else {
      std::printf("plane check: no frame with a plane and depth in the road region\n");
    }
  }
  return 0;
}
