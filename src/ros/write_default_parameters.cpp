// write_default_parameters > config/default.yaml: every node and detector parameter with its
// default, from the parameter tables (default_parameter_file.h).
#include <iostream>

#include "default_parameter_file.h"

int main() {
  std::cout << rgbd_lane_detector::defaultParameterFile();
  return 0;
}
