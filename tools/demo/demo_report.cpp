// demo_report: the report of a `make demo` run. Scores the LanePlane + LaneMarkings recorded
// from the ROS graph against the sequence's ground truth with the tools' scoring library
// (METHOD.md section 6, the same code as run_dataset / evaluate_sequences) and summarises the
// latencies measured by demo_probe.
//
// Frame i of the sequence is the i-th colour message of the played bag (sequence_to_bag writes
// frames in order); an output belongs to the frame whose colour stamp it carries. A played
// frame without any output counts as a miss (nothing reported).
// Exit status: 0 ok, 1 unreadable input, 2 usage, 3 no lane_plane output at all, 4 fewer than
// 90% of the played frames answered.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>

#include <rgbd_lane_detector/LaneMarkings.h>
#include <rgbd_lane_detector/LanePlane.h>

#include "rgbd_lane_detector_tools/command_line.h"
#include "rgbd_lane_detector_tools/ground_truth.h"
#include "rgbd_lane_detector_tools/scoring.h"

using namespace rgbd_lane_detector;

namespace {

std::string joinTopic(const std::string& ns, const std::string& name) {
  if (ns.empty() || ns == "/") return "/" + name;
  std::string t = ns.front() == '/' ? ns : "/" + ns;
  if (t.back() != '/') t += '/';
  return t + name;
}

std::vector<Eigen::Vector3d> toPoints(const std::vector<geometry_msgs::Point>& in) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(in.size());
  for (const auto& p : in) out.emplace_back(p.x, p.y, p.z);
  return out;
}

/// Nearest-rank percentile of sorted values.
double percentile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return std::nan("");
  const size_t rank = static_cast<size_t>(std::ceil(q / 100.0 * sorted.size()));
  return sorted[std::min(sorted.size() - 1, rank > 0 ? rank - 1 : 0)];
}

struct Latency {
  int inputs = 0, outputs = 0, matched = 0;
  std::vector<double> ms;  // sorted
};

bool readLatency(const std::string& path, Latency& lat, std::string& error) {
  std::ifstream f(path);
  if (!f) {
    error = "cannot read " + path;
    return false;
  }
  std::map<uint64_t, double> in_time;
  std::vector<std::pair<uint64_t, double>> outs;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream s(line);
    std::string kind, stamp, wall;
    if (!std::getline(s, kind, ',') || !std::getline(s, stamp, ',') || !std::getline(s, wall, ',')) continue;
    const uint64_t ns = std::stoull(stamp);
    const double t = std::stod(wall);
    if (kind == "in") {
      ++lat.inputs;
      in_time.emplace(ns, t);  // first receipt of a stamp (a looped bag repeats stamps)
    } else if (kind == "out") {
      ++lat.outputs;
      outs.emplace_back(ns, t);
    }
  }
  for (const auto& o : outs) {
    auto it = in_time.find(o.first);
    if (it == in_time.end()) continue;
    lat.ms.push_back(1000.0 * (o.second - it->second));
    ++lat.matched;
  }
  std::sort(lat.ms.begin(), lat.ms.end());
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string input_bag, output_bag, truth_path, latency_csv, ns = "/camera", label = "improved";
  tools::CommandLine cl("demo_report",
                        "Report of a make demo run: frames in/out, TP/FP against the ground truth, "
                        "latency.\nexample: demo_report --input summer.bag --outputs outputs.bag "
                        "--truth summer/GT/LANES/ground_truth.json --latency latency.csv");
  cl.add("input", "the played bag (required)", &input_bag);
  cl.add("outputs", "bag recorded from the graph: lane_plane, lane_markings (required)", &output_bag);
  cl.add("truth", "ground truth JSON of the sequence (GT/LANES/ground_truth.json)", &truth_path);
  cl.add("latency", "latency CSV written by demo_probe", &latency_csv);
  cl.add("ns", "camera namespace of the topics (default /camera)", &ns);
  cl.add("label", "mode name printed in the report (default improved)", &label);
  const auto parsed = cl.parse(argc, argv);
  if (parsed == tools::CommandLine::Parse::kHelp) return 0;
  if (parsed == tools::CommandLine::Parse::kError) return 2;
  if (input_bag.empty() || output_bag.empty()) {
    std::cerr << "demo_report: --input and --outputs are required\n";
    return 2;
  }

  // Played frames: stamp -> position.
  std::map<uint64_t, int> frame_of_stamp;
  int frames_in = 0;
  try {
    rosbag::Bag bag(input_bag, rosbag::bagmode::Read);
    rosbag::View view(bag, rosbag::TopicQuery(joinTopic(ns, "rgb/image_rect_color")));
    for (const rosbag::MessageInstance& m : view) {
      const auto image = m.instantiate<sensor_msgs::Image>();
      if (!image) continue;
      frame_of_stamp.emplace(image->header.stamp.toNSec(), frames_in);
      ++frames_in;
    }
  } catch (const std::exception& e) {
    std::cerr << "demo_report: " << input_bag << ": " << e.what() << "\n";
    return 1;
  }

  // Recorded outputs by stamp.
  std::map<uint64_t, rgbd_lane_detector::LanePlaneConstPtr> planes;
  std::map<uint64_t, rgbd_lane_detector::LaneMarkingsConstPtr> markings;
  int planes_out = 0, markings_out = 0;
  try {
    rosbag::Bag bag(output_bag, rosbag::bagmode::Read);
    const std::vector<std::string> topics = {joinTopic(ns, "lane_plane"), joinTopic(ns, "lane_markings")};
    rosbag::View view(bag, rosbag::TopicQuery(topics));
    for (const rosbag::MessageInstance& m : view) {
      if (auto p = m.instantiate<rgbd_lane_detector::LanePlane>()) {
        planes.emplace(p->header.stamp.toNSec(), p);
        ++planes_out;
      } else if (auto k = m.instantiate<rgbd_lane_detector::LaneMarkings>()) {
        markings.emplace(k->header.stamp.toNSec(), k);
        ++markings_out;
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "demo_report: " << output_bag << ": " << e.what() << "\n";
    return 1;
  }
  int frames_with_output = 0;
  for (const auto& f : frame_of_stamp) frames_with_output += planes.count(f.first) > 0;

  std::printf("  frames in : %d colour frames played from %s\n", frames_in, input_bag.c_str());
  std::printf("  frames out: %d lane_plane + %d lane_markings messages recorded; %d of %d frames answered\n",
              planes_out, markings_out, frames_with_output, frames_in);

  // Scoring (METHOD.md section 6) of every played frame.
  if (!truth_path.empty()) {
    tools::SequenceTruth truth;
    std::string error;
    if (!tools::readGroundTruth(truth_path, truth, error)) {
      std::cerr << "demo_report: " << error << "\n";
      return 1;
    }
    tools::ScoreSummary summary;
    int no_truth = 0;
    for (const auto& f : frame_of_stamp) {
      const tools::FrameTruth* t = truth.find(f.second);
      if (!t) {
        ++no_truth;
        continue;
      }
      tools::Detection d;
      auto p = planes.find(f.first);
      if (p != planes.end() && p->second->valid) {
        d.plane_valid = true;
        d.normal = Eigen::Vector3d(p->second->normal.x, p->second->normal.y, p->second->normal.z);
        d.distance = p->second->distance;
      }
      auto k = markings.find(f.first);
      if (k != markings.end()) {
        d.left = toPoints(k->second->left);
        d.right = toPoints(k->second->right);
        d.left_reported = !d.left.empty();
        d.right_reported = !d.right.empty();
      }
      summary.add(tools::scoreFrame(d, *t), 0.0);
    }
    std::printf("  vs ground truth (%s mode, scoring.h rules, %d frames%s): TP %.1f%%  partial %.1f%%  FP %.1f%%"
                "  miss %.1f%%  (planes: angle err %.3f deg, offset err %.3f m)\n",
                label.c_str(), summary.frames, no_truth ? (", " + std::to_string(no_truth) + " without truth").c_str() : "",
                summary.tpPercent(), summary.partialPercent(), summary.fpPercent(), summary.missPercent(),
                summary.meanAngleError(), summary.meanOffsetError());
  }

  if (!latency_csv.empty()) {
    Latency lat;
    std::string error;
    if (!readLatency(latency_csv, lat, error)) {
      std::cerr << "demo_report: " << error << "\n";
      return 1;
    }
    double sum = 0.0;
    for (double v : lat.ms) sum += v;
    std::printf("  latency   : input colour frame received -> its lane_plane received (probe node, steady clock)\n");
    if (lat.ms.empty()) {
      std::printf("              no frame measured (probe saw %d inputs, %d outputs)\n", lat.inputs, lat.outputs);
    } else {
      std::printf("              mean %.1f ms  p50 %.1f ms  p99 %.1f ms  max %.1f ms  over %d frames "
                  "(probe saw %d inputs, %d outputs)\n",
                  sum / lat.ms.size(), percentile(lat.ms, 50), percentile(lat.ms, 99), lat.ms.back(), lat.matched,
                  lat.inputs, lat.outputs);
    }
  }
  if (planes_out == 0) return 3;
  // a healthy graph answers every frame at 10-15 Hz; losing more than a tenth means it stalled or died
  return 10 * frames_with_output >= 9 * frames_in ? 0 : 4;
}
