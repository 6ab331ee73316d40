#include "rgbd_lane_detector_tools/progress.h"

#include <algorithm>
#include <cstdio>

namespace rgbd_lane_detector {
namespace tools {

ProgressBar::ProgressBar(std::string label, int total, bool enabled)
    : label_(std::move(label)), total_(total), enabled_(enabled) {
  start_ = last_draw_ = std::chrono::steady_clock::now();
}

ProgressBar::~ProgressBar() {
  finish();
}

void ProgressBar::update(int done, const std::string& extra) {
  done_ = done;
  extra_ = extra;
  if (!enabled_ || finished_) return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && now - last_draw_ < std::chrono::milliseconds(100) && done != total_) return;
  last_draw_ = now;
  draw();
}

void ProgressBar::finish() {
  if (finished_) return;
  finished_ = true;
  if (!enabled_) return;
  if (!drawn_ || last_drawn_done_ != done_) draw();
  std::fputc('\n', stderr);
  std::fflush(stderr);
}

void ProgressBar::draw() {
  drawn_ = true;
  last_drawn_done_ = done_;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = elapsed > 0 ? done_ / elapsed : 0.0;
  char line[512];
  int n;
  if (total_ > 0) {
    constexpr int kWidth = 30;
    const double frac = std::min(1.0, std::max(0.0, static_cast<double>(done_) / total_));
    char bar[kWidth + 1];
    const int full = static_cast<int>(frac * kWidth);
    for (int i = 0; i < kWidth; ++i) bar[i] = i < full ? '=' : (i == full ? '>' : ' ');
    bar[kWidth] = '\0';
    const double eta = rate > 0 ? (total_ - done_) / rate : 0.0;
    n = std::snprintf(line, sizeof(line), "\r%s [%s] %5d/%d %3d%% %6.1f fps ETA %4.0fs %s",
                      label_.c_str(), bar, done_, total_, static_cast<int>(100 * frac), rate, eta,
                      extra_.c_str());
  } else {
    n = std::snprintf(line, sizeof(line), "\r%s %6d %6.1f fps %s", label_.c_str(), done_, rate,
                      extra_.c_str());
  }
  if (n < 0) return;
  // pad so a shorter line fully overwrites the previous one
  std::fprintf(stderr, "%-110s", line);
  std::fflush(stderr);
}

}  // namespace tools
}  // namespace rgbd_lane_detector
