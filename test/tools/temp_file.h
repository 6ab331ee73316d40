// Test helper: a text file in gtest's temporary folder.
#pragma once

#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace rgbd_lane_detector {
namespace tools {

/// Write @p text to TempDir()/@p name. @return the path.
inline std::string writeTempFile(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace tools
}  // namespace rgbd_lane_detector
