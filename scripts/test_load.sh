#!/usr/bin/env bash
# `make test-load`: the test suites under full CPU load. stress-ng keeps every CPU busy
# (LOAD_WORKERS workers, default: one per CPU) while `make test` runs LOAD_TEST_RUNS times
# (default 5) and `make test-sanitize` LOAD_SANITIZE_RUNS times (default 3), one after the other;
# prints and writes (build/test_load/summary.md) the pass counts, the load average and the time
# of each run. Every run's output is kept in build/test_load/<suite>_<n>.log, the test results of
# a failed run in build/test_load/<suite>_<n>_results/. Exit status 0 when every run passed.
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=$ROOT/build/test_load
export PATH=/usr/bin:/bin:$PATH
TEST_RUNS=${LOAD_TEST_RUNS:-5}
SANITIZE_RUNS=${LOAD_SANITIZE_RUNS:-3}
WORKERS=${LOAD_WORKERS:-$(nproc)}
mkdir -p "$OUT"
command -v stress-ng > /dev/null || { echo "test-load: stress-ng is missing (scripts/install_deps.sh load)"; exit 1; }

# stress-ng in its own process group, ended with the script
setsid stress-ng --cpu "$WORKERS" --cpu-method all --quiet > "$OUT/stress-ng.log" 2>&1 &
STRESS=$!
stop_stress() { kill -- -"$STRESS" 2> /dev/null; wait "$STRESS" 2> /dev/null; }
trap stop_stress EXIT
trap 'exit 130' INT TERM
sleep 2
kill -0 "$STRESS" 2> /dev/null || { echo "test-load: stress-ng did not start (log: $OUT/stress-ng.log)"; exit 1; }
echo "test-load: stress-ng --cpu $WORKERS running (pid $STRESS) on $(nproc) CPUs"

# run <suite> <n> <make target> <results folder>: one run, its status in the summary
declare -A passed=([test]=0 [sanitize]=0)
rows=()
run() {
  local suite=$1 n=$2 target=$3 results=$4 log="$OUT/$1_$2.log" t0 status load0 load1
  load0=$(cut -d' ' -f1 /proc/loadavg)
  t0=$(date +%s)
  make -C "$ROOT" "$target" > "$log" 2>&1
  status=$?
  load1=$(cut -d' ' -f1 /proc/loadavg)
  local secs=$(($(date +%s) - t0)) verdict=PASS
  if [ $status -eq 0 ]; then
    passed[$suite]=$((passed[$suite] + 1))
  else
    verdict=FAIL
    rm -rf "${OUT:?}/${suite}_${n}_results"
    cp -r "$results" "$OUT/${suite}_${n}_results" 2> /dev/null || true
  fi
  local last
  last=$(grep -E "passed, .* failed|sanitize: (all clean|FAILED)" "$log" | tail -n 1)
  rows+=("| make $target | $n | $verdict | $((secs / 60)) min $((secs % 60)) s | $load0 / $load1 | $last |")
  echo "test-load: make $target run $n: $verdict in ${secs} s (load average $load0 -> $load1) $last"
}

for n in $(seq 1 "$TEST_RUNS"); do
  run test "$n" test "$ROOT/build/ws/build/test_results"
done
for n in $(seq 1 "$SANITIZE_RUNS"); do
  run sanitize "$n" test-sanitize "$ROOT/build/ws_sanitize/build/test_results"
done

summary="make test: ${passed[test]} of $TEST_RUNS passed; make test-sanitize: ${passed[sanitize]} of $SANITIZE_RUNS passed (stress-ng --cpu $WORKERS on $(nproc) CPUs)"
{
  echo "# test-load $(date -u +%Y-%m-%dT%H:%MZ)"
  echo
  echo "$summary"
  echo
  echo "| command | run | result | time | load average start / end | last line |"
  echo "| --- | ---: | --- | --- | --- | --- |"
  printf '%s\n' "${rows[@]}"
} > "$OUT/summary.md"
echo "test-load: $summary (summary: ${OUT#"$ROOT"/}/summary.md)"
[ "${passed[test]}" -eq "$TEST_RUNS" ] && [ "${passed[sanitize]}" -eq "$SANITIZE_RUNS" ]
