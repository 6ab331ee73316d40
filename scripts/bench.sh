#!/usr/bin/env bash
# Benchmark the detector core against the straightforward OpenCV pipeline (bench/bench_core.cpp)
# and write docs/PERFORMANCE.md and docs/performance.png from the results.
# Called by `make bench` with the workspace sourced. Environment:
#   BENCH_BIN          bench_core to run (default: found on CMAKE_PREFIX_PATH)
#   BENCH_REPETITIONS  repetitions whose medians are reported (default 5)
#   BENCH_FILTER       Google Benchmark filter (default: everything)
#   BENCH_NODELET      0 skips the nodelet measurement (bench/measure_nodelet.sh, needs the tools
#                      and a ROS install; a few minutes)
#   BENCH_TRANSPORT    0 skips the frames-on-the-way-in measurement (bench/measure_transport.sh:
#                      a driver-like publisher, the standalone node and rosbag at 15 and 30 Hz,
#                      640x480 to 1920x1080; needs ROS; RADIATE frames from ../shared/realdata,
#                      a generated road without it; about 15 minutes);
#                      its own environment (SIZES, RATES, CASES, QUICK=1, ...) passes through
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
export PATH=/usr/bin:/bin:$PATH

find_bin() {
  local name=$1 p
  IFS=: read -ra prefixes <<< "${CMAKE_PREFIX_PATH:-}"
  for p in "${prefixes[@]}"; do
    if [ -x "$p/lib/rgbd_lane_detector/$name" ]; then
      echo "$p/lib/rgbd_lane_detector/$name"
      return
    fi
  done
}
BIN=${BENCH_BIN:-$(find_bin bench_core)}
PROFILE=$(dirname "${BIN:-/nonexistent}")/profile_core
if [ -z "$BIN" ] || [ ! -x "$BIN" ]; then
  echo "bench: bench_core not found (needs libbenchmark-dev and OpenCV's rgbd module at build" \
       "time; source the workspace or set BENCH_BIN)" >&2
  exit 1
fi

OUT=$ROOT/build/bench
mkdir -p "$OUT" "$ROOT/docs"
load=$(cut -d' ' -f1 /proc/loadavg)
echo "bench: $BIN (load average $load; figures are only comparable on a quiet machine)"
# repetitions interleaved at random: a shared machine's speed drifts during the run, and each
# benchmark's median then sees the same drift as the OpenCV pipeline it is compared with
"$BIN" --benchmark_repetitions="${BENCH_REPETITIONS:-5}" --benchmark_report_aggregates_only=true \
  --benchmark_enable_random_interleaving=true \
  --benchmark_filter="${BENCH_FILTER:-.}" \
  --benchmark_out="$OUT/bench.json" --benchmark_out_format=json | tee "$OUT/bench.txt"

# Peak resident memory of a process running detect() at 1280x760 (frames included).
RSS_KB=""
if [ -x "$PROFILE" ]; then
  RSS_KB=$("$PROFILE" detect 1280 50 | sed -n 's/^peak RSS \([0-9]*\) kB$/\1/p')
fi

# Each stage on each SIMD target (profile_core: CPU time of a fixed number of calls, 640x380).
STAGES_BY_TARGET=$OUT/stages_by_target.txt
: > "$STAGES_BY_TARGET"
if [ -x "$PROFILE" ]; then
  for target in $("$PROFILE" targets 640 1); do
    for stage in halfbinary points normals matching response detect; do
      "$PROFILE" "$stage" 640 200 "$target" | tail -n 1 >> "$STAGES_BY_TARGET"
    done
  done
fi

# Each frame's CPU time over the looped drive measure_transport.sh plays (profile_core sequence):
# the scene's own spread of the work, beside the stream's latency tail.
SEQUENCE_CPU=$OUT/sequence_cpu.txt
: > "$SEQUENCE_CPU"
if [ -x "$PROFILE" ]; then
  for size in 640x480 1280x720 1920x1080; do
    "$PROFILE" sequence "$size" 600 2> /dev/null | tail -n 1 >> "$SEQUENCE_CPU" || true
  done
fi

# What the nodelet adds over detect(), and its peak RSS (bench/measure_nodelet.sh).
NODELET=()
if [ "${BENCH_NODELET:-1}" != 0 ] && command -v roscore > /dev/null; then
  for size in "640 380 150" "1280 760 60"; do
    # shellcheck disable=SC2086
    line=$("$ROOT/bench/measure_nodelet.sh" $size 2> "$OUT/nodelet.err" | tail -n 1) || line=""
    [ -n "$line" ] && NODELET+=(--nodelet "$line") && echo "bench: nodelet $line"
  done
fi

# Frames lost on the way in and latency (bench/measure_transport.sh; issue 23's 30 Hz 1920x1080).
TRANSPORT=()
if [ "${BENCH_TRANSPORT:-1}" != 0 ] && command -v roscore > /dev/null; then
  echo "bench: frames on the way in (bench/measure_transport.sh, log $OUT/transport.log)"
  if OUT=$OUT/transport "$ROOT/bench/measure_transport.sh" > "$OUT/transport.log" 2>&1; then
    TRANSPORT=(--transport "$OUT/transport/results.md")
  else
    echo "bench: measure_transport failed or skipped (see $OUT/transport.log)" >&2
  fi
fi

/usr/bin/python3 "$ROOT/scripts/bench_report.py" --json "$OUT/bench.json" "${NODELET[@]}" "${TRANSPORT[@]}" \
  --rss-kb "${RSS_KB:-0}" --stages-by-target "$STAGES_BY_TARGET" --sequence-cpu "$SEQUENCE_CPU" --commit "$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo '?')" \
  --out "$ROOT/docs/PERFORMANCE.md" --plot "$ROOT/docs/performance.png"
echo "bench: wrote docs/PERFORMANCE.md and docs/performance.png"
