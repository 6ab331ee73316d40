#!/usr/bin/env bash
# Build and run every test of the workspace (gtest, rostest, roslaunch checks), then
# catkin_lint; print one summary line and exit non-zero on any failure.
set -uo pipefail
WS=${1:?usage: run_tests.sh <catkin workspace>}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
LOG=$WS/../test_logs
mkdir -p "$LOG"
export PATH=/usr/bin:/bin:$PATH
export ROS_HOME=${ROS_HOME:-$WS/../ros_home}
set +u  # ROS setup files read unset variables
# shellcheck disable=SC1091
source "$WS/devel/setup.bash"
set -u
cd "$WS"

t0=$(date +%s)
echo "test: building tests"
if ! catkin_make -j"$(nproc)" tests > "$LOG/build_tests.log" 2>&1; then
  tail -n 60 "$LOG/build_tests.log"
  echo "test: building the tests failed (log: $LOG/build_tests.log)"
  exit 1
fi
t1=$(date +%s)
rm -rf build/test_results/rgbd_lane_detector
echo "test: running gtests and rostests"
catkin_make run_tests -j1 > "$LOG/run_tests.log" 2>&1
t2=$(date +%s)

results=$(catkin_test_results build/test_results/rgbd_lane_detector 2>&1)
echo "$results" | grep -vE "^Summary" | grep -E "errors|failures|Failure|Error" | head -40
summary=$(echo "$results" | grep -E "^Summary:" | tail -n 1)
tests=$(echo "$summary" | sed -nE 's/.* ([0-9]+) tests.*/\1/p')
errors=$(echo "$summary" | sed -nE 's/.* ([0-9]+) errors.*/\1/p')
failures=$(echo "$summary" | sed -nE 's/.* ([0-9]+) failures.*/\1/p')
skipped=$(echo "$summary" | sed -nE 's/.* ([0-9]+) skipped.*/\1/p')
tests=${tests:-0}; errors=${errors:-0}; failures=${failures:-0}; skipped=${skipped:-0}
# test binaries that crashed leave no XML result: catkin_make run_tests logs them
missing=$(grep -cE "^-- run_tests.py: verify result .* missing|Cannot find results|No result file" "$LOG/run_tests.log" || true)

echo "test: catkin_lint"
lint_failed=0
if ! catkin_lint --offline -W1 "$ROOT" > "$LOG/catkin_lint.log" 2>&1; then
  lint_failed=1
  cat "$LOG/catkin_lint.log"
fi
grep -E "error:" "$LOG/catkin_lint.log" >/dev/null && lint_failed=1

failed=$((errors + failures + missing + lint_failed))
passed=$((tests - errors - failures - skipped))
echo "$summary"
echo "catkin_lint: $([ $lint_failed -eq 0 ] && echo ok || echo FAILED)  (log: $LOG/catkin_lint.log)"
echo "times: build tests $((t1 - t0)) s, run tests $((t2 - t1)) s"
echo "${passed} passed, ${failed} failed, ${skipped} skipped"
[ "$failed" -eq 0 ] && [ "$tests" -gt 0 ]
