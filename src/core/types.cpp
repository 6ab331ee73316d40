#include "rgbd_lane_detector/types.h"

#include <cmath>

namespace rgbd_lane_detector {

bool Intrinsics::valid() const {
  return std::isfinite(fx) && std::isfinite(fy) && std::isfinite(cx) && std::isfinite(cy) &&
         fx > 0.0 && fy > 0.0;
}

const char* statusMessage(Status status) {
  switch (status) {
    case Status::kOk:
      return "ok";
    case Status::kEmptyImage:
      return "empty colour or depth image";
    case Status::kSizeMismatch:
      return "colour and depth images differ in size (depth must be registered to colour)";
    case Status::kUnsupportedColour:
      return "unsupported colour image (expected 8-bit mono, 3-channel or 4-channel matching "
             "the encoding)";
    case Status::kUnsupportedDepth:
      return "unsupported depth image (expected 16UC1 with a positive scale, or 32FC1 metres)";
    case Status::kInvalidIntrinsics:
      return "invalid camera intrinsics (zero, negative or non-finite focal length or "
             "principal point)";
    case Status::kImageTooSmall:
      return "searched image region is smaller than the template";
  }
  return "unknown status";
}

const char* boundaryKindName(BoundaryKind kind) {
  switch (kind) {
    case BoundaryKind::kPaint:
      return "paint";
    case BoundaryKind::kRoadEdge:
      return "road_edge";
  }
  return "unknown";
}

}  // namespace rgbd_lane_detector
