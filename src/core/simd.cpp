#include "simd.h"

#include <strings.h>

#ifdef RLD_HAVE_HWY
#include <hwy/highway.h>
#endif

namespace rgbd_lane_detector {
namespace simd {
namespace {

#ifdef RLD_HAVE_HWY
constexpr int64_t kNotVector = HWY_EMU128 | HWY_SCALAR;

// The vector targets compiled here that the CPU (or Highway's test mock) has, best first.
std::vector<Target> vectorTargets() {
  std::vector<Target> t;
  for (Target target : hwy::SupportedAndGeneratedTargets())
    if ((target & kNotVector) == 0) t.push_back(target);
  return t;
}
#endif

std::atomic<Target> g_forced{kBest};

}  // namespace

namespace detail {
#ifdef RLD_HAVE_HWY
std::atomic<bool> g_vector{!vectorTargets().empty()};
#else
std::atomic<bool> g_vector{false};
#endif
}  // namespace detail

std::vector<Target> availableTargets() {
#ifdef RLD_HAVE_HWY
  const Target forced = g_forced.load();
  if (forced > 0) hwy::SetSupportedTargetsForTest(0);  // what the CPU has
  std::vector<Target> targets = vectorTargets();
  if (forced > 0) hwy::SetSupportedTargetsForTest(forced);
  targets.push_back(kScalar);
  return targets;
#else
  return {kScalar};
#endif
}

void forceTarget(Target target) {
  g_forced = target;
#ifdef RLD_HAVE_HWY
  hwy::SetSupportedTargetsForTest(target > 0 ? target : 0);  // 0: what the CPU has
  detail::g_vector = target == kBest ? !vectorTargets().empty() : target != kScalar;
#endif
}

const char* targetName(Target target) {
#ifdef RLD_HAVE_HWY
  if (target > 0) return hwy::TargetName(target);
#endif
  return target == kScalar ? "scalar" : "best";
}

Target targetByName(const char* name) {
  for (Target t : availableTargets())
    if (strcasecmp(targetName(t), name) == 0) return t;
  return -1;
}

Target currentTarget() {
#ifdef RLD_HAVE_HWY
  if (vectorTarget()) return vectorTargets().front();
#endif
  return kScalar;
}

}  // namespace simd

namespace {
std::atomic<bool> g_reference_stages{false};
}  // namespace

void setReferenceStages(bool enabled) {
  g_reference_stages = enabled;
}
bool referenceStages() {
  return g_reference_stages;
}

}  // namespace rgbd_lane_detector
