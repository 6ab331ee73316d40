/**
 * @file simd.h
 * @brief Private to the core (not installed): CPU dispatch of the vector kernels and the test
 * hooks (forcing a target, the reference stages).
 *
 * Every hot kernel (half-binary, depth to points, FALS normals and G, NCC matching, R and its
 * maximum) is written once with Google Highway and compiled for each target of the architecture
 * (x86: SSE4, AVX2, AVX-512; aarch64: NEON; Highway's emulated EMU128 is compiled as its
 * baseline but never chosen: the plain loops are faster). The best target the CPU has is
 * chosen at run time (HWY_DYNAMIC_DISPATCH). Built without Highway (RLD_HAVE_HWY undefined, e.g.
 * Ubuntu 20.04), the kernels are the plain C++ loops, which are also the per-pixel definitions
 * every vector lane follows, the tails of every vector loop and the scalar target (kScalar).
 *
 * Kernel files include this header, then Highway's foreach_target.h (see half_binary.cpp).
 * Every target computes the same bits: integer sums are exact, float operations are the same
 * IEEE operations in the same order (the core is compiled with -ffp-contract=off, no FMA), so
 * forcing any target gives identical results (test_lane_detector, EveryTargetGivesTheSameBits).
 */
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#ifdef RLD_HAVE_HWY
/// Open and close the per-target part of a kernel file, compiled once per target (after
/// foreach_target.h and highway.h): inside, namespace rgbd_lane_detector::HWY_NAMESPACE with
/// hn = Highway's ops.
#define RLD_KERNELS_BEGIN        \
  HWY_BEFORE_NAMESPACE();        \
  namespace rgbd_lane_detector { \
  namespace HWY_NAMESPACE {      \
  namespace hn = hwy::HWY_NAMESPACE;
#define RLD_KERNELS_END \
  }                     \
  }                     \
  HWY_AFTER_NAMESPACE();
#else
#define HWY_ONCE 1  // no per-target passes: the shared part of a kernel file is compiled once
#endif

/// Call a kernel on the current target: the vector kernel exported with HWY_EXPORT(name), or on
/// the scalar target name##Scalar, which each kernel file defines as "no column done" (its
/// scalar loops, the per-pixel definitions, then do every column).
#ifdef RLD_HAVE_HWY
#define RLD_DISPATCH(name) \
  (::rgbd_lane_detector::simd::vectorTarget() ? HWY_DYNAMIC_DISPATCH(name) : name##Scalar)
#else
#define RLD_DISPATCH(name) name##Scalar
#endif

namespace rgbd_lane_detector {
namespace simd {

/// A dispatch target: one of Highway's HWY_* bits of a vector target, or kScalar.
using Target = int64_t;
/// The plain C++ loops (one pixel at a time; what a build without Highway runs, and what runs on
/// a CPU without any vector target: faster than Highway's emulated EMU128 lanes).
constexpr Target kScalar = 0;
/// forceTarget(kBest): back to the best target of the CPU.
constexpr Target kBest = -1;

/**
 * @brief The targets this build has compiled and this CPU runs, best first, kScalar last
 * (whatever forceTarget() says). Without Highway: {kScalar}.
 */
std::vector<Target> availableTargets();

/// Short name of a target: "AVX3" (AVX-512), "AVX2", "SSE4", "NEON", "scalar".
const char* targetName(Target target);

/// The available target named @p name (as targetName() gives it, any case), or -1.
Target targetByName(const char* name);

/// The target the kernels dispatch to now.
Target currentTarget();

/**
 * @brief Test and benchmark hook: run every kernel on @p target (one of availableTargets()),
 * or on the best one again with kBest. Process-wide; not to be called while another thread runs
 * the detector.
 */
void forceTarget(Target target);

namespace detail {
extern std::atomic<bool> g_vector;  ///< the current target is a vector one
}  // namespace detail

/// Whether the kernels run on a vector target now (RLD_DISPATCH).
inline bool vectorTarget() {
  return detail::g_vector.load(std::memory_order_relaxed);
}

}  // namespace simd

/**
 * @brief Test and benchmark hook: while enabled, NccMatcher::match() computes with
 * cv::matchTemplate and FalsNormals solves every window directly in double (the method as
 * written), so detect() can be run on both implementations and compared. Process-wide, slow,
 * allocates; never enabled by the package itself.
 */
void setReferenceStages(bool enabled);
/// Whether setReferenceStages(true) is in effect.
bool referenceStages();

}  // namespace rgbd_lane_detector
