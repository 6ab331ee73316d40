/**
 * @file line_template.h
 * @brief The left ("/") and right ("\") line templates of the matching stage.
 */
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace rgbd_lane_detector {

/**
 * @brief A square template holding one thick straight line through its centre.
 *
 * Pixel (c, r) is on the line when the horizontal distance from its centre (c + 0.5, r + 0.5)
 * to the line through the template centre with direction (cos angle, sin angle) is at most
 * width / (2 |sin angle|), i.e. the band of perpendicular thickness @c width. Every row
 * therefore holds one contiguous run, which the fast matcher exploits.
 */
struct LineTemplate {
  int size = 0;                ///< side (px)
  int width = 0;               ///< perpendicular line thickness (px)
  double angle = 0.0;          ///< image angle of the line (rad), atan2(dv, du) with dv > 0
  cv::Mat image;               ///< CV_8UC1, 255 on the line, 0 elsewhere
  std::vector<int> run_begin;  ///< per row: first column on the line
  std::vector<int> run_end;    ///< per row: one past the last column (== run_begin: empty row)
  int count = 0;               ///< number of line pixels
};

/**
 * @brief Draw a line template.
 * @param[in] size side in pixels (>= 3).
 * @param[in] width line thickness in pixels (>= 1).
 * @param[in] angle image angle (rad); pi/4 is the right template "\", 3 pi/4 the left "/".
 * @param[out] out the template (its buffers are reused).
 */
void makeLineTemplate(int size, int width, double angle, LineTemplate& out);

/// Image angle of the default left template ("/", bottom-left to top-right) for a given
/// angle from the horizontal in degrees.
double defaultLeftAngle(double template_angle_deg);
/// Image angle of the default right template ("\", top-left to bottom-right).
double defaultRightAngle(double template_angle_deg);

}  // namespace rgbd_lane_detector
