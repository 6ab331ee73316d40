#!/usr/bin/env bash
# `make test-sanitize`: the package's tests under the sanitizers, each in its own workspace.
#  1. AddressSanitizer + UndefinedBehaviorSanitizer (build/ws_sanitize): every gtest (core,
#     tools, conversions) with leak detection, then every rostest (standalone node, nodelet in
#     Debian's uninstrumented nodelet manager with the ASan runtime preloaded, concurrency,
#     short soak). Any report aborts the process and fails its test.
#  2. ThreadSanitizer (build/ws_tsan): the concurrency rostest (frames, dynamic_reconfigure
#     changes and subscriber churn at once on the nodelet) with test/sanitize/tsan.supp, which
#     names third-party (roscpp, log4cxx) reports only. Any report fails.
# SANITIZE_ONLY=asan|tsan runs one half; RLD_CONCURRENCY_SECONDS sets the TSan traffic time.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
export PATH=/usr/bin:/bin:$PATH
export PYTHONNOUSERSITE=1
ONLY=${SANITIZE_ONLY:-all}
PKG=rgbd_lane_detector
COMMON="-DCMAKE_BUILD_TYPE=RelWithDebInfo -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON"
JOBS=$(nproc)

# Configure and build a sanitizer workspace: build_ws <ws> <flags> <log> <targets...>
build_ws() {
  local ws=$1 flags=$2 log=$3
  shift 3
  "$ROOT/scripts/make_workspace.sh" "$ws" > /dev/null
  echo "sanitize: building $(basename "$ws") ($*; log: ${log#"$ROOT"/})"
  local args=($COMMON -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags"
    -DCMAKE_SHARED_LINKER_FLAGS="$flags")
  # The test targets run through build/catkin_generated/env_cached.sh, the environment catkin
  # recorded when it configured. A first configure records it before the workspace has its
  # Python messages (PYTHONPATH=''), and rostests with Python nodes (soak_short) could not
  # import them: configure once, then again with the workspace sourced, then build.
  (cd "$ws" && { [ -f devel/setup.bash ] || catkin_make "${args[@]}" cmake_check_build_system; } &&
    set +u && source devel/setup.bash && set -u &&
    catkin_make --force-cmake "${args[@]}" "$@" -j"$JOBS") > "$log" 2>&1 || { tail -n 40 "$log"; exit 1; }
  if grep -q "^export PYTHONPATH=''" "$ws/build/catkin_generated/setup_cached.sh"; then
    echo "sanitize: $ws/build/catkin_generated/setup_cached.sh has an empty PYTHONPATH"
    exit 1
  fi
}

# Run catkin test targets in a workspace; prints catkin_test_results' summary, returns its status.
run_targets() {
  local ws=$1 log=$2
  shift 2
  rm -rf "$ws/build/test_results" "$ws/ros_home/log"
  (cd "$ws" && set +u && source devel/setup.bash && export ROS_HOME="$ws/ros_home" &&
    for t in "$@"; do make -C build "$t" -j1 || true; done) > "$log" 2>&1
  local status=0
  # reports are written to stderr, which rostest keeps in the test's log: show them here
  if grep -q "ERROR: AddressSanitizer\|runtime error:\|WARNING: ThreadSanitizer\|ERROR: LeakSanitizer" \
    -r "$log" "$ws/ros_home/log" 2> /dev/null; then
    echo "sanitize: sanitizer reports in ${log#"$ROOT"/} or $ws/ros_home/log:"
    grep -h -A12 "ERROR: AddressSanitizer\|runtime error:\|WARNING: ThreadSanitizer\|ERROR: LeakSanitizer" \
      -r "$log" "$ws/ros_home/log" | head -n 60
    status=1
  fi
  catkin_test_results --verbose "$ws/build/test_results/$PKG" | grep -E "^(Summary|.*(failure|error)[^s])" || true
  catkin_test_results "$ws/build/test_results/$PKG" > /dev/null || status=1
  return $status
}

failed=0
if [ "$ONLY" = all ] || [ "$ONLY" = asan ]; then
  WS=$ROOT/build/ws_sanitize
  build_ws "$WS" "-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all" \
    "$ROOT/build/sanitize_build.log" all tests
  # gtests: leaks are errors. rostests: Debian's (uninstrumented) nodelet manager loads the
  # instrumented nodelet with the ASan runtime preloaded (RLD_MANAGER_PREFIX, the manager's
  # launch-prefix); ROS processes keep singletons alive at exit, so leak checking stays with the
  # gtests and the soak's RSS check (whose limit ASan's quarantine would break: raised here).
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  echo "sanitize: ASan+UBSan gtests"
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1 \
    run_targets "$WS" "$ROOT/build/sanitize_gtests.log" run_tests_${PKG}_gtest || failed=1
  echo "sanitize: ASan+UBSan rostests (node, nodelet in a manager, concurrency, short soak)"
  ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:strict_string_checks=1 \
    RLD_MANAGER_PREFIX="env LD_PRELOAD=$(gcc -print-file-name=libasan.so)" RLD_SOAK_RSS_LIMIT_MB=2000 \
    run_targets "$WS" "$ROOT/build/sanitize_rostests.log" run_tests_${PKG}_rostest || failed=1
  unset UBSAN_OPTIONS
fi
if [ "$ONLY" = all ] || [ "$ONLY" = tsan ]; then
  WS=$ROOT/build/ws_tsan
  build_ws "$WS" "-fsanitize=thread -fno-omit-frame-pointer" "$ROOT/build/tsan_build.log" \
    test_concurrency ${PKG}_nodelet
  echo "sanitize: ThreadSanitizer concurrency rostest (${RLD_CONCURRENCY_SECONDS:=30} s of traffic)"
  export RLD_CONCURRENCY_SECONDS
  TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$ROOT/test/sanitize/tsan.supp" \
    run_targets "$WS" "$ROOT/build/tsan_rostest.log" \
    run_tests_${PKG}_rostest_test_concurrency_concurrency.test || failed=1
  grep -h "^concurrency:" -r "$WS/ros_home/log" "$WS/build/test_results" "$ROOT/build/tsan_rostest.log" 2> /dev/null |
    tail -n 1 || true
fi
if [ "$failed" -eq 0 ]; then echo "sanitize: all clean"; else echo "sanitize: FAILED"; fi
exit "$failed"
