#include "rgbd_lane_detector/adaptive_threshold.h"

#include <algorithm>

namespace rgbd_lane_detector {

namespace {

// out[x] = in[x] where in[x] >= tau, else 0 (distinct buffers: the compiler vectorises it)
void keepAtLeast(const uint8_t* __restrict in, uint8_t* __restrict out, int n, uint8_t tau) {
  for (int x = 0; x < n; ++x) out[x] = in[x] >= tau ? in[x] : uint8_t(0);
}

// More than kBrightTail of a row's sampled pixels at or above @p tau: the row shows something
// the fixed offset keeps (paint, a zebra stripe), not a low-contrast row.
bool brightTail(const std::vector<int>& histogram, int tau) {
  int n = 0, above = 0;
  for (int g = 0; g < 256; ++g) {
    n += histogram[g];
    if (g >= tau) above += histogram[g];
  }
  return above > kBrightTail * n;
}

}  // namespace

int rowMedian(const uint8_t* row, int width, std::vector<int>& histogram, int stride) {
  // four histograms, one per sample of four in turn (a road's neighbouring samples often share a
  // grey level: one histogram would wait for each count before the next), summed into one
  int part[4][256] = {};
  int n = 0, x = 0;
  for (; x + 3 * stride < width; x += 4 * stride, n += 4) {
    ++part[0][row[x]];
    ++part[1][row[x + stride]];
    ++part[2][row[x + 2 * stride]];
    ++part[3][row[x + 3 * stride]];
  }
  for (; x < width; x += stride, ++n) ++part[0][row[x]];
  histogram.resize(256);
  int* h = histogram.data();
  for (int g = 0; g < 256; ++g) h[g] = (part[0][g] + part[1][g]) + (part[2][g] + part[3][g]);
  const int half = (n + 1) / 2;
  int seen = 0;
  for (int g = 0; g < 256; ++g) {
    seen += h[g];
    if (seen >= half) return g;
  }
  return 255;
}

void applyRowThreshold(const cv::Mat& grey, cv::Mat& out, const cv::Range& rows, int offset,
                       std::vector<int>& histogram, double relative) {
  CV_Assert(grey.type() == CV_8UC1);
  if (out.data != grey.data && (out.size() != grey.size() || out.type() != CV_8UC1)) {
    out.create(grey.size(), CV_8UC1);
    out.setTo(0);
  }
  const int r0 = std::max(rows.start, 0), r1 = std::min(rows.end, grey.rows);
  for (int y = r0; y < r1; ++y) {
    const uint8_t* in = grey.ptr<uint8_t>(y);
    // a median of every 4th pixel is as good a level as the exact one, at a quarter of the cost
    const int level = rowMedian(in, grey.cols, histogram, 4);
    int row_offset = offset;
    if (relative > 0.0 && level < kDarkRow && !brightTail(histogram, level + offset))
      row_offset = std::min(offset, std::max(kMinRowOffset, static_cast<int>(relative * level + 0.5)));
    const uint8_t tau = static_cast<uint8_t>(std::min(std::max(level + row_offset, 0), 255));
    uint8_t* row = out.ptr<uint8_t>(y);
    if (row == in) {
      for (int x = 0; x < grey.cols; ++x) row[x] = row[x] >= tau ? row[x] : uint8_t(0);
    } else {
      keepAtLeast(in, row, grey.cols, tau);
    }
  }
}

}  // namespace rgbd_lane_detector
