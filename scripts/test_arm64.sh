#!/usr/bin/env bash
# make test-arm64: the ROS-free core, its gtests and the benchmarks cross-compiled for aarch64
# (Debian's g++-aarch64-linux-gnu against Debian's arm64 libraries in build/arm64/sysroot, see
# arm64_sysroot.sh), the gtests run under qemu-aarch64, and detect() on a fixed drive compared
# with this machine's own build (test_golden_detections). Timings under emulation are not speed
# figures. Ends with "N passed, N failed"; non-zero exit on any failure.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=$ROOT/build/arm64
JOBS=${JOBS:-$(nproc)}
export PATH=/usr/bin:/bin:$PATH
t0=$(date +%s)

"$ROOT/scripts/arm64_sysroot.sh" "$OUT/sysroot"

# this machine's detections, from the same sources built without ROS
cmake -S "$ROOT/cmake/arm64" -B "$OUT/host" -DCMAKE_BUILD_TYPE=Release > "$OUT/host-cmake.log"
cmake --build "$OUT/host" -j "$JOBS" --target test_golden_detections > "$OUT/host-build.log" 2>&1 ||
  { tail -n 40 "$OUT/host-build.log"; echo "test-arm64: host build FAILED"; exit 1; }
RLD_DETECTIONS_WRITE="$OUT/host_detections.txt" "$OUT/host/test_golden_detections" \
  > "$OUT/host-detections.log"

# the cross build
cmake -S "$ROOT/cmake/arm64" -B "$OUT/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_TOOLCHAIN_FILE="$ROOT/cmake/arm64/toolchain.cmake" -DRLD_SYSROOT="$OUT/sysroot" \
  > "$OUT/cmake.log"
if ! cmake --build "$OUT/build" -j "$JOBS" > "$OUT/build.log" 2>&1; then
  tail -n 60 "$OUT/build.log"
  echo "test-arm64: cross build FAILED (log: $OUT/build.log)"
  exit 1
fi
file "$OUT/build/test_lane_detector" | sed 's/^.*: /test-arm64: built /'
t1=$(date +%s)

# every gtest under qemu (ctest runs them through CMAKE_CROSSCOMPILING_EMULATOR)
rc=0
RLD_DETECTIONS_REFERENCE="$OUT/host_detections.txt" \
  ctest --test-dir "$OUT/build" --output-on-failure -j "$JOBS" > "$OUT/ctest.log" 2>&1 || rc=$?
grep -E "tests passed|Failed|\*\*\*" "$OUT/ctest.log" || true
# the detections compared, target by target
RLD_DETECTIONS_REFERENCE="$OUT/host_detections.txt" qemu-aarch64 -L "$OUT/sysroot" \
  "$OUT/build/test_golden_detections" > "$OUT/golden.log" 2>&1 || rc=1
grep -E "against|OK|FAILED" "$OUT/golden.log" || true
# one benchmark program runs too (profile_core: fixed work on generated roads)
qemu-aarch64 -L "$OUT/sysroot" "$OUT/build/profile_core" detect 640 2 > "$OUT/profile.log" 2>&1 ||
  rc=1
sed 's/^/test-arm64: (emulated, not a speed figure) /' "$OUT/profile.log" | tail -n 1

passed=$(grep -cE "^ *[0-9]+/[0-9]+ Test +#[0-9]+: .* Passed" "$OUT/ctest.log" || true)
failed=$(grep -cE "^ *[0-9]+/[0-9]+ Test +#[0-9]+: .* (Failed|\*\*\*)" "$OUT/ctest.log" || true)
echo "test-arm64: build $((t1 - t0)) s, tests $(( $(date +%s) - t1 )) s under qemu-aarch64 (logs: $OUT)"
echo "$passed passed, $failed failed"
[ "$rc" -eq 0 ] && [ "$failed" -eq 0 ]
