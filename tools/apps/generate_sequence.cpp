// generate_sequence: render a synthetic RGB-D road sequence with exact lane ground truth, as a
// SYNTHIA-SEQS folder and/or a rosbag.
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "rgbd_lane_detector_tools/command_line.h"
#include "rgbd_lane_detector_tools/dataset/bag_writer.h"
#include "rgbd_lane_detector_tools/progress.h"
#include "rgbd_lane_detector_tools/synth/renderer.h"
#include "rgbd_lane_detector_tools/synth/scenario.h"
#include "rgbd_lane_detector_tools/synth/sequence_writer.h"

using namespace rgbd_lane_detector;

namespace {

void printLists() {
  std::cout << "scenarios:";
  for (const auto& n : synth::scenarioNames()) std::cout << " " << n;
  std::cout << "\nsensors:";
  for (const auto& n : synth::sensorNames()) std::cout << " " << n;
  std::cout << "\n\nsettings (--set key=value; defaults of the summer preset):\n";
  synth::SceneSettings s;
  for (const auto& f : synth::settingFields(s)) {
    std::string name = std::string("  ") + f.name;
    if (name.size() < 24) name.resize(24, ' ');
    std::cout << name << f.help << "\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenario = "summer", sensor = "clean", out, bag;
  int frames = 300, width = 640, height = 380, seed = 1;
  double bag_rate = 0.0;
  bool skip_if_same = false, quiet = false, list = false;
  std::vector<std::string> overrides;
  tools::CommandLine cl("generate_sequence",
                        "Render a synthetic road sequence (SYNTHIA-SEQS layout with lane ground "
                        "truth) and/or a rosbag.\nexample: generate_sequence --scenario fog "
                        "--sensor kinect --frames 300 --out build/data/fog_kinect");
  cl.add("scenario", "named scenario (see --list)", &scenario);
  cl.add("sensor", "depth sensor model: clean, kinect, sparse, lidar", &sensor);
  cl.add("out", "output folder (SYNTHIA-SEQS layout)", &out);
  cl.add("frames", "number of frames (default 300)", &frames);
  cl.add("width", "image width (default 640; intrinsics scale with it)", &width);
  cl.add("height", "image height (default 380)", &height);
  cl.add("seed", "random seed (default 1)", &seed);
  cl.add("set", "override a setting, key=value (see --list)", &overrides);
  cl.add("bag", "also write a rosbag with the nodelet's input topics", &bag);
  cl.add("bag-rate", "stamp rate of the bag (Hz, default: the scenario's fps)", &bag_rate);
  cl.addFlag("skip-if-same", "do nothing when --out already holds this exact sequence",
             &skip_if_same);
  cl.addFlag("quiet", "no progress bar", &quiet);
  cl.addFlag("list", "list scenarios, sensors and settings", &list);
  const auto parsed = cl.parse(argc, argv);
  if (parsed == tools::CommandLine::Parse::kHelp) return 0;
  if (parsed == tools::CommandLine::Parse::kError) return 2;
  if (list) {
    printLists();
    return 0;
  }
  if (out.empty() && bag.empty()) {
    std::cerr << "generate_sequence: give --out and/or --bag\n";
    return 2;
  }

  synth::SceneSettings s;
  s.frames = frames;
  s.width = width;
  s.height = height;
  s.seed = seed;
  s.sensor = sensor;
  if (!synth::applyScenario(scenario, s)) {
    std::cerr << "generate_sequence: unknown scenario '" << scenario << "' (see --list)\n";
    return 2;
  }
  if (!synth::applySensor(sensor, s)) {
    std::cerr << "generate_sequence: unknown sensor '" << sensor << "' (clean, kinect, sparse)\n";
    return 2;
  }
  std::string error;
  for (const auto& kv : overrides) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos ||
        !synth::setSetting(s, kv.substr(0, eq), kv.substr(eq + 1), error)) {
      std::cerr << "generate_sequence: --set " << kv << ": "
                << (eq == std::string::npos ? "expected key=value" : error) << "\n";
      return 2;
    }
  }
  if (!synth::validateSettings(s, error)) {
    std::cerr << "generate_sequence: " << error << "\n";
    return 2;
  }
  if (!out.empty() && bag.empty() && skip_if_same && synth::sequenceUpToDate(out, s)) {
    if (!quiet) std::cerr << "generate_sequence: " << out << " is up to date\n";
    return 0;
  }

  synth::Renderer renderer(s);
  synth::SequenceWriter writer;
  if (!out.empty() && !writer.open(out, s, renderer.intrinsics(), error)) {
    std::cerr << "generate_sequence: " << error << "\n";
    return 1;
  }
  tools::BagWriter bag_writer;
  if (!bag.empty()) {
    tools::BagWriterOptions bo;
    bo.rate = bag_rate > 0 ? bag_rate : s.fps;
    bo.tf_parent = "base_link";
    bo.tf_z = s.camera_height;
    bo.tf_pitch = s.pitch_deg * M_PI / 180.0;
    // the generator's roll turns the image's right side up: REP-103 roll about x is its negative
    bo.tf_roll = -s.roll_deg * M_PI / 180.0;
    if (!bag_writer.open(bag, bo, error)) {
      std::cerr << "generate_sequence: " << error << "\n";
      return 1;
    }
  }
  tools::ProgressBar progress(scenario + "/" + sensor, s.frames, !quiet);
  synth::RenderedFrame frame;
  for (int i = 0; i < s.frames; ++i) {
    renderer.render(i, frame);
    if (!out.empty() && !writer.write(i, frame, renderer.truth(i), error)) {
      progress.finish();
      std::cerr << "generate_sequence: " << error << "\n";
      return 1;
    }
    if (!bag.empty()) {
      tools::DatasetFrame df;
      df.index = i;
      df.name = synth::SynthiaLayout::frameName(i);
      df.colour = frame.bgr;
      df.format = PixelFormat::kBgr8;
      df.depth = frame.depth;
      df.depth_scale = 1.0;
      df.intrinsics = renderer.intrinsics();
      if (!bag_writer.write(df, error)) {
        progress.finish();
        std::cerr << "generate_sequence: " << error << "\n";
        return 1;
      }
    }
    progress.update(i + 1);
  }
  progress.finish();
  if (!out.empty() && !writer.finish(error)) {
    std::cerr << "generate_sequence: " << error << "\n";
    return 1;
  }
  bag_writer.close();
  return 0;
}
