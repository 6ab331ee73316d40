/**
 * @file row_statistics.h
 * @brief Robust statistics of the boundary classifier's per-row measurements: medians (of any
 * floats, and fast ones of grey values) and the step most rows agree on.
 */
#pragma once

#include <cstdint>
#include <vector>

namespace rgbd_lane_detector {

/// Median of @p v (reordered): the element std::nth_element puts at v.size() / 2; NaN when empty.
float median(std::vector<float>& v);

/// median() of grey values (integers 0-255), the same element: above 16 samples (where
/// std::nth_element stops sorting by insertion) by counting, 4-8x faster at 30-120 samples.
float greyMedian(std::vector<float>& v);

/// greyMedian() of the grey values a[0, na) and b[0, nb) together (the element of rank
/// (na + nb) / 2), counted straight from the bytes; NaN when both are empty.
float greyMedian(const uint8_t* a, int na, const uint8_t* b, int nb);

/**
 * @brief The step of per-row height differences @p steps: their median, when at least @p share
 * of them reach @p least (else NaN: no consistent step).
 * @return false when fewer than @p min_rows are measured (@p step NaN).
 */
bool stepInMostRows(std::vector<float>& steps, float least, int min_rows, double share,
                    float& step);

}  // namespace rgbd_lane_detector
