/**
 * @file line_template.h
 * @brief The left ("/") and right ("\") line templates of the matching stage.
 */
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace rgbd_lane_detector {

/// Largest denominator of a template's slope (columns per row). Every angle between 10 and 80
/// degrees from the horizontal has a slope p / q, q <= 8, within 2 degrees of it.
constexpr int kMaxSlopeDenominator = 8;

/**
 * @brief A square template holding one thick straight line through its centre.
 *
 * The line is drawn at a slope (columns per row, cot angle) that is a fraction
 * slope_p / slope_q: the one with the smallest slope_q <= kMaxSlopeDenominator whose line stays
 * within half a pixel of the requested line over the template's half-length (angle error at
 * most atan(1 / size), 1.8 degrees for size 32), else the nearest such fraction. Pixel
 * (c, r) is on the line when the horizontal distance from its centre (c + 0.5, r + 0.5) to the
 * line through the template centre is at most width / (2 |sin drawn_angle|), i.e. the band of
 * perpendicular thickness @c width, clipped by the square. Every row therefore holds one
 * contiguous run, and the unclipped run ends repeat every slope_q rows shifted by slope_p
 * columns (run_begin[r + q] = run_begin[r] + p), which lets the matcher sum a template along
 * the line with a few running-sum lookups per pixel whatever the template size.
 * The 45-degree templates are exactly the ones of the plain rule (slope 1/1).
 */
struct LineTemplate {
  int size = 0;                ///< side (px)
  int width = 0;               ///< perpendicular line thickness (px)
  double angle = 0.0;          ///< requested image angle (rad), atan2(dv, du) with dv > 0
  double drawn_angle = 0.0;    ///< angle of the drawn line, atan2(slope_q, slope_p)
  int slope_p = 0;             ///< columns the line advances every slope_q rows
  int slope_q = 1;             ///< 1..kMaxSlopeDenominator, coprime with slope_p
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
