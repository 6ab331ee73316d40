// sequence_to_bag: convert a SYNTHIA-SEQS / TUM / KITTI folder (or another bag) to a rosbag
// with the nodelet's input topics.
#include <cmath>
#include <cstdio>
#include <iostream>

#include "rgbd_lane_detector_tools/command_line.h"
#include "rgbd_lane_detector_tools/dataset/bag_writer.h"
#include "rgbd_lane_detector_tools/dataset/dataset.h"
#include "rgbd_lane_detector_tools/detector_setup.h"
#include "rgbd_lane_detector_tools/progress.h"

using namespace rgbd_lane_detector;

int main(int argc, char** argv) {
  tools::DatasetOptions data;
  tools::BagWriterOptions bag;
  std::string out, encoding = "bgr8", depth_encoding = "16UC1";
  double pitch_deg = 0.0, roll_deg = 0.0, yaw_deg = 0.0;
  bool quiet = false;
  tools::CommandLine cl(
      "sequence_to_bag",
      "Convert an RGB-D dataset to a rosbag: <ns>/rgb/image_rect_color, "
      "<ns>/depth_registered/image_rect, <ns>/rgb/camera_info (+ /tf_static).\n"
      "example: sequence_to_bag --dataset build/data/summer --out summer.bag --rate 10 "
      "--tf-parent base_link --tf-z 1.5");
  cl.add("dataset", "dataset folder or bag (required)", &data.path);
  tools::addDatasetOptions(cl, data);
  cl.add("out", "output .bag (required)", &out);
  cl.add("ns", "topic namespace (default /camera)", &bag.ns);
  cl.add("frame-id", "frame of the images (default camera_color_optical_frame)", &bag.frame_id);
  cl.add("rate", "stamp rate in Hz (default 10)", &bag.rate);
  cl.add("start-time", "stamp of the first frame, s (default 1.7e9)", &bag.start_time);
  cl.addFlag("source-stamps", "keep the dataset's stamps (TUM, bags) instead of --rate",
             &bag.use_source_stamps);
  cl.add("encoding", "colour encoding: bgr8 (default) or rgb8", &encoding);
  cl.add("depth-encoding", "depth encoding: 16UC1 (mm, default) or 32FC1 (m)", &depth_encoding);
  cl.addFlag("compress", "LZ4-compress the bag", &bag.compress);
  cl.add("tf-parent", "write a latched /tf_static from this frame to --frame-id", &bag.tf_parent);
  cl.add("tf-x", "camera x in the parent (m)", &bag.tf_x);
  cl.add("tf-y", "camera y in the parent (m)", &bag.tf_y);
  cl.add("tf-z", "camera z in the parent (m, default 1.5)", &bag.tf_z);
  cl.add("tf-roll", "camera roll (deg)", &roll_deg);
  cl.add("tf-pitch", "camera pitch, positive looks down (deg)", &pitch_deg);
  cl.add("tf-yaw", "camera yaw (deg)", &yaw_deg);
  cl.addFlag("quiet", "no progress bar", &quiet);
  const auto parsed = cl.parse(argc, argv);
  if (parsed == tools::CommandLine::Parse::kHelp) return 0;
  if (parsed == tools::CommandLine::Parse::kError) return 2;
  if (data.path.empty() || out.empty()) {
    std::cerr << "sequence_to_bag: --dataset and --out are required\n";
    return 2;
  }
  if (encoding != "bgr8" && encoding != "rgb8") {
    std::cerr << "sequence_to_bag: --encoding must be bgr8 or rgb8\n";
    return 2;
  }
  if (depth_encoding != "16UC1" && depth_encoding != "32FC1") {
    std::cerr << "sequence_to_bag: --depth-encoding must be 16UC1 or 32FC1\n";
    return 2;
  }
  if (!(bag.rate > 0) || !(bag.start_time > 0)) {
    std::cerr << "sequence_to_bag: --rate and --start-time must be > 0\n";
    return 2;
  }
  bag.rgb8 = encoding == "rgb8";
  bag.depth_float = depth_encoding == "32FC1";
  bag.tf_roll = roll_deg * M_PI / 180.0;
  bag.tf_pitch = pitch_deg * M_PI / 180.0;
  bag.tf_yaw = yaw_deg * M_PI / 180.0;

  std::string error;
  auto reader = tools::openDataset(data, error);
  if (!reader) {
    std::cerr << "sequence_to_bag: " << error << "\n";
    return 1;
  }
  tools::BagWriter writer;
  if (!writer.open(out, bag, error)) {
    std::cerr << "sequence_to_bag: " << error << "\n";
    return 1;
  }
  tools::ProgressBar progress(std::string("bag ") + reader->kind(), reader->size(), !quiet);
  tools::DatasetFrame frame;
  int n = 0;
  while (reader->next(frame)) {
    if (!writer.write(frame, error)) {
      progress.finish();
      std::cerr << "sequence_to_bag: " << error << "\n";
      return 1;
    }
    progress.update(++n, frame.name);
  }
  progress.finish();
  writer.close();
  if (!reader->error().empty()) {
    std::cerr << "sequence_to_bag: " << reader->error() << "\n";
    return 1;
  }
  if (n == 0) {
    std::cerr << "sequence_to_bag: no frames read from " << data.path << "\n";
    return 1;
  }
  std::printf("wrote %d frames to %s\n", n, out.c_str());
  return 0;
}
