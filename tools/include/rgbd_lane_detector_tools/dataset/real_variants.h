/**
 * @file real_variants.h
 * @brief The same real street seen otherwise: stress variants of a hand-labelled real frame and
 * its labels, so that the few real frames also test the failures a vehicle meets (the kerb on
 * the other side, no depth near the car).
 */
#pragma once

#include <string>
#include <vector>

#include "rgbd_lane_detector_tools/dataset/dataset.h"
#include "rgbd_lane_detector_tools/real_labels.h"

namespace rgbd_lane_detector {
namespace tools {

/// A stress variant of a real frame.
enum class RealVariant {
  kAsIs,            ///< the frame as recorded
  kMirrored,        ///< mirrored left-right: a left-hand kerb, lines on the other sides
  kNoNearDepth,     ///< no depth in the bottom 30% of the rows (LiDAR and stereo gaps near the car)
  kHalfResolution,  ///< half the width and height (another camera: a 621x187 image)
  kUnderexposed,    ///< colour at 60% (dusk, a darker camera)
  kOverexposed,     ///< colour at 140%, saturating (low sun on light asphalt)
  kNight,           ///< lit by the vehicle's lamps: 45% at the bottom row to 8% at the horizon, noise
};

/// Every variant, kAsIs first.
const std::vector<RealVariant>& allRealVariants();
/// "as_is", "mirrored", "no_near_depth", "half_resolution", "underexposed", "overexposed",
/// "night" (static text).
const char* realVariantName(RealVariant v);
/// The variant named @p name; false for an unknown name.
bool realVariantFromName(const std::string& name, RealVariant& v);

/**
 * @brief Turn a frame and its label into variant @p v (in place; the images are copied first,
 * never written through shared buffers).
 *
 * kMirrored flips the colour image, the depth and the LiDAR depth left-right, moves the principal
 * point with them (cx' = width - 1 - cx) and mirrors the label (its left and right sides swap).
 * kNoNearDepth sets the depth of the bottom 30% of the rows to "no depth" (0, or NaN for float
 * depth); the LiDAR reference used to check the plane and place the labels is kept.
 * kHalfResolution resizes the colour image (area average) and the depth images (nearest), and
 * scales the intrinsics and the label with them. kUnderexposed and kOverexposed scale the
 * colour values (saturating at 255). kNight scales each row from 45% at the bottom to 8% at the
 * principal point's row and above (quadratically: the vehicle's lamps light the near road) and
 * adds Gaussian noise of sigma 4 (a camera's gain at night), with a fixed seed.
 * @param[in] v variant.
 * @param[in,out] frame the frame.
 * @param[in,out] label its label.
 */
void applyRealVariant(RealVariant v, DatasetFrame& frame, LabelledFrame& label);

}  // namespace tools
}  // namespace rgbd_lane_detector
