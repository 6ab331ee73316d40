// A named scenario of the synthetic generator at a given image size (the tools' gtests).
#pragma once

#include <string>

#include <gtest/gtest.h>

#include "rgbd_lane_detector_tools/synth/scenario.h"

namespace rgbd_lane_detector {
namespace synth {
namespace test {

inline SceneSettings preset(const std::string& name, int width = 640, int height = 380) {
  SceneSettings s;
  s.width = width;
  s.height = height;
  EXPECT_TRUE(applyScenario(name, s)) << name;
  return s;
}

}  // namespace test
}  // namespace synth
}  // namespace rgbd_lane_detector
