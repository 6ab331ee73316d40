// transport_bag: the frames FramePlayerNodelet publishes (frame_source.h: the real fog drive by
// default, resized with the intrinsics scaled), written to a rosbag at a fixed rate with the
// nodelet's input topics, for bench/measure_transport.sh's rosbag runs (issue 23).
#include <iostream>

#include "frame_source.h"
#include "rgbd_lane_detector_tools/command_line.h"
#include "rgbd_lane_detector_tools/dataset/bag_writer.h"

using namespace rgbd_lane_detector;

int main(int argc, char** argv) {
  tools::FrameSourceOptions src;
  tools::BagWriterOptions bag;
  std::string out, encoding = "rgb8", depth_encoding = "16UC1";
  int count = 300;
  bag.rate = 30.0;
  bag.tf_parent = "base_link";
  tools::CommandLine cl(
      "transport_bag",
      "Write the frame player's frames (resized, looped) to a rosbag at a fixed rate.\n"
      "example: transport_bag --width 1280 --height 720 --rate 30 --count 300 --out hd.bag");
  cl.add("dataset", "folder or bag (default: ../shared/realdata/sequences/radiate_fog; a "
         "generated road when absent)", &src.dataset);
  cl.add("type", "reader type (default auto)", &src.type);
  cl.add("filter", "only frames whose name contains this", &src.filter);
  cl.add("frames", "distinct frames loaded (default 30, looped)", &src.max_frames);
  cl.add("width", "output width (default 1920)", &src.width);
  cl.add("height", "output height (default 1080)", &src.height);
  cl.add("count", "frames written (default 300)", &count);
  cl.add("rate", "stamp rate, Hz (default 30)", &bag.rate);
  cl.add("encoding", "colour encoding: rgb8 (default) or bgr8", &encoding);
  cl.add("depth-encoding", "16UC1 (mm, default) or 32FC1 (m)", &depth_encoding);
  cl.add("tf-parent", "latched /tf_static from this frame (default base_link; '' none)",
         &bag.tf_parent);
  cl.add("out", "output .bag (required)", &out);
  const auto parsed = cl.parse(argc, argv);
  if (parsed == tools::CommandLine::Parse::kHelp) return 0;
  if (parsed == tools::CommandLine::Parse::kError) return 2;
  if (out.empty() || count <= 0 || bag.rate <= 0) {
    std::cerr << "transport_bag: give --out, a positive --count and --rate\n";
    return 2;
  }
  bag.rgb8 = encoding == "rgb8";
  bag.depth_float = depth_encoding == "32FC1";
  // a level camera 1.5 m above base_link, as FramePlayerNodelet's publish_tf
  bag.tf_z = 1.5;
  std::vector<tools::DatasetFrame> frames;
  std::string source, warning, error;
  tools::loadFrameSource(src, frames, source, warning);
  if (!warning.empty()) std::cerr << "transport_bag: " << warning << ": using " << source << "\n";
  tools::BagWriter writer;
  if (!writer.open(out, bag, error)) {
    std::cerr << "transport_bag: " << error << "\n";
    return 1;
  }
  for (int i = 0; i < count; ++i) {
    tools::DatasetFrame f = frames[static_cast<size_t>(i) % frames.size()];
    f.index = i;
    if (!writer.write(f, error)) {
      std::cerr << "transport_bag: " << error << "\n";
      return 1;
    }
  }
  writer.close();
  std::cout << "transport_bag: " << count << " frames of " << source << " at "
            << frames.front().colour.cols << "x" << frames.front().colour.rows << ", " << bag.rate
            << " Hz -> " << out << "\n";
  return 0;
}
