#!/usr/bin/env bash
# Build the core unit tests with AddressSanitizer + UndefinedBehaviorSanitizer in a separate
# workspace and run them; any report fails.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WS=$ROOT/build/ws_sanitize
export PATH=/usr/bin:/bin:$PATH
"$ROOT/scripts/make_workspace.sh" "$WS"
FLAGS="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all"
cd "$WS"
TESTS=$(sed -n '/set(CORE_TESTS/,/)/p' "$ROOT/test/CMakeLists.txt" | grep -oE 'test_[a-z_]+')
echo "sanitize: building $(echo $TESTS | wc -w) core test binaries (log: build/sanitize_build.log)"
catkin_make -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DCMAKE_CXX_FLAGS="$FLAGS" -DCMAKE_EXE_LINKER_FLAGS="$FLAGS" -DCMAKE_SHARED_LINKER_FLAGS="$FLAGS" \
  $TESTS -j"$(nproc)" > "$ROOT/build/sanitize_build.log" 2>&1 || { tail -n 40 "$ROOT/build/sanitize_build.log"; exit 1; }
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
passed=0; failed=0
for t in $TESTS; do
  if "$WS/devel/lib/rgbd_lane_detector/$t" > "$ROOT/build/sanitize_$t.log" 2>&1; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1)); echo "FAILED: $t"; tail -n 30 "$ROOT/build/sanitize_$t.log"
  fi
done
echo "sanitize: ${passed} passed, ${failed} failed"
[ "$failed" -eq 0 ]
