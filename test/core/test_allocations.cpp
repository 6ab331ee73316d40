// Steady state allocates nothing: after warm-up frames, detect() makes no heap allocation.
// This test binary replaces malloc and friends (which operator new, cv::fastMalloc and the STL
// all reach) with counting wrappers around glibc's own allocator.
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <limits>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector/lane_detector.h"
#include "rgbd_lane_detector/lane_grid.h"
#include "synthetic_scene.h"

// The sanitizers own malloc: under them (make test-sanitize) the counter is compiled out and the
// tests are skipped (they run in every normal build).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define RLD_COUNT_ALLOCATIONS 0
#else
#define RLD_COUNT_ALLOCATIONS 1
#endif

#if RLD_COUNT_ALLOCATIONS
extern "C" {
void* __libc_malloc(size_t size);
void* __libc_calloc(size_t n, size_t size);
void* __libc_realloc(void* p, size_t size);
void* __libc_memalign(size_t alignment, size_t size);
void __libc_free(void* p);
}
#endif

namespace {

std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
std::atomic<size_t> g_first_size{0};

inline void count(size_t size) {
  if (!g_counting.load(std::memory_order_relaxed)) return;
  if (g_allocations.fetch_add(1) == 0) g_first_size = size;
}

}  // namespace

#if RLD_COUNT_ALLOCATIONS
extern "C" {
void* malloc(size_t size) {
  count(size);
  return __libc_malloc(size);
}
void* calloc(size_t n, size_t size) {
  count(n * size);
  return __libc_calloc(n, size);
}
void* realloc(void* p, size_t size) {
  count(size);
  return __libc_realloc(p, size);
}
void* memalign(size_t alignment, size_t size) {
  count(size);
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(size_t alignment, size_t size) {
  count(size);
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, size_t alignment, size_t size) {
  count(size);
  void* p = __libc_memalign(alignment, size);
  if (!p) return ENOMEM;
  *out = p;
  return 0;
}
void free(void* p) {
  __libc_free(p);
}
}
#endif  // RLD_COUNT_ALLOCATIONS

namespace rgbd_lane_detector {
namespace {

using test::RoadScene;

struct Drive {
  std::vector<cv::Mat> bgr, depth;
  Intrinsics K;
};

// Four frames of a drive (moving dashes, sway, depth holes) at the given size.
Drive makeDrive(int width, int height) {
  Drive d;
  for (int i = 0; i < 4; ++i) {
    RoadScene scene;
    scene.width = width;
    scene.height = height;
    const double s = width / 640.0;
    scene.K = Intrinsics{266.37 * s, 266.37 * s, 0.5 * width, 0.5 * height};
    scene.right_dashed = true;
    scene.lateral_offset = 0.3 * std::sin(0.9 * i);
    cv::Mat bgr, depth;
    scene.render(bgr, depth);
    for (int k = 0; k < 6; ++k)  // hole blobs: windows with missing depth take other paths
      cv::circle(depth,
                 cv::Point((97 * (i + 1) * (k + 3)) % width, height / 2 + 37 * k % (height / 2)),
                 static_cast<int>(3 + 2 * k * s), cv::Scalar(0), -1);
    d.bgr.push_back(bgr);
    d.depth.push_back(depth);
    d.K = scene.K;
  }
  return d;
}

Frame frameOf(const Drive& d, int i) {
  Frame f;
  f.colour = d.bgr[i % 4];
  f.depth = d.depth[i % 4];
  f.format = PixelFormat::kBgr8;
  f.depth_scale = 0.001;
  f.intrinsics = d.K;
  return f;
}

TEST(Allocations, SteadyStateDetectAllocatesNothing) {
  if (!RLD_COUNT_ALLOCATIONS) GTEST_SKIP() << "the sanitizer's allocator replaces the counting one";
  for (const cv::Size size : {cv::Size(640, 380), cv::Size(1280, 760)}) {
    const Drive drive = makeDrive(size.width, size.height);
    for (const Params& params : {Params::paper(), Params::improved()}) {
      for (int threads : {1, 2}) {  // 2: normals next to matching on the helper thread
        cv::setNumThreads(threads);
        SCOPED_TRACE(testing::Message() << size << (params.road_gate ? " improved" : " paper")
                                        << ", " << threads << " thread(s)");
        LaneDetector det(params);
        Result r;
        for (int i = 0; i < 8; ++i) ASSERT_EQ(det.detect(frameOf(drive, i), r), Status::kOk);
        g_allocations = 0;
        g_counting = true;
        for (int i = 0; i < 12; ++i) det.detect(frameOf(drive, i), r);
        g_counting = false;
        EXPECT_EQ(g_allocations.load(), 0)
            << "first allocation: " << g_first_size.load() << " bytes";
        EXPECT_TRUE(r.left.found || r.right.found);  // the frames exercise the whole pipeline
      }
    }
  }
  cv::setNumThreads(1);
}

// The lane grid (lane_grid, the debug inset) rebuilt from every frame's lane model reuses its
// cells: after the first build at a size, none allocates, with lane changes allowed or not.
TEST(Allocations, SteadyStateLaneGridAllocatesNothing) {
  if (!RLD_COUNT_ALLOCATIONS) GTEST_SKIP() << "the sanitizer's allocator replaces the counting one";
  const Drive drive = makeDrive(640, 380);
  LaneDetector det(Params::improved());
  Result r;
  LaneGrid grid;
  LaneGridSettings settings;
  for (int i = 0; i < 8; ++i) {
    ASSERT_EQ(det.detect(frameOf(drive, i), r), Status::kOk);
    grid.build(r.lane_model, settings);
  }
  long free_cells = 0;
  g_allocations = 0;
  g_counting = true;
  for (int i = 0; i < 12; ++i) {
    det.detect(frameOf(drive, i), r);
    settings.allow_lane_change = i % 2 == 0;
    grid.build(r.lane_model, settings);
    for (int8_t v : grid.cells()) free_cells += v == LaneGrid::kFree;
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0) << "first allocation: " << g_first_size.load() << " bytes";
  EXPECT_TRUE(r.lane_model.valid);
  EXPECT_GT(free_cells, 0) << "the grids hold a lane";
}

TEST(Allocations, TheCounterSeesEveryAllocator) {
  if (!RLD_COUNT_ALLOCATIONS) GTEST_SKIP() << "the sanitizer's allocator replaces the counting one";
  g_allocations = 0;
  g_counting = true;
  cv::Mat m(100, 100, CV_32FC1);  // cv::fastMalloc
  std::vector<int> v(10);         // operator new
  void* p = std::malloc(7);
  g_counting = false;
  std::free(p);
  EXPECT_GE(g_allocations.load(), 3);
}


// prepare() is called with whatever a camera_info says: a size or camera detect() would refuse
// is refused before anything is allocated (a broken driver must not make the node allocate).
TEST(Allocations, PrepareRefusesAnUnusableCameraWithoutAllocating) {
  if (!RLD_COUNT_ALLOCATIONS) GTEST_SKIP() << "the sanitizer's allocator replaces the counting one";
  LaneDetector det(Params::improved());
  const Intrinsics good{266.37, 266.37, 320.0, 190.0};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  g_allocations = 0;
  g_counting = true;
  const Status empty = det.prepare(cv::Size(0, 380), good);
  const Status negative = det.prepare(cv::Size(640, -1), good);
  const Status zero_f = det.prepare(cv::Size(640, 380), Intrinsics{0.0, 266.37, 320.0, 190.0});
  const Status nan_c = det.prepare(cv::Size(640, 380), Intrinsics{266.37, 266.37, nan, 190.0});
  g_counting = false;
  EXPECT_EQ(empty, Status::kEmptyImage);
  EXPECT_EQ(negative, Status::kEmptyImage);
  EXPECT_EQ(zero_f, Status::kInvalidIntrinsics);
  EXPECT_EQ(nan_c, Status::kInvalidIntrinsics);
  EXPECT_EQ(g_allocations.load(), 0) << "first allocation: " << g_first_size.load() << " bytes";
  EXPECT_EQ(det.prepare(cv::Size(640, 380), good), Status::kOk);  // a usable camera still plans
}
}  // namespace
}  // namespace rgbd_lane_detector
