#!/usr/bin/env bash
# Build the libFuzzer targets of fuzz/ with clang-14 (ASan + UBSan + libFuzzer) in a separate
# workspace (build/ws_fuzz) and run each for FUZZ_SECONDS (default 60) from its seed corpus in
# fuzz/corpus/<target>. New corpus entries and crash artifacts go under build/fuzz (never into
# the repository). Prints runs, exec/s and corpus size per target; any crash, leak, timeout or
# sanitizer report fails.
#   FUZZ_SECONDS=600 scripts/fuzz.sh              # longer runs
#   FUZZ_TARGETS="fuzz_readers" scripts/fuzz.sh   # a subset
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WS=$ROOT/build/ws_fuzz
OUT=$ROOT/build/fuzz
SECONDS_PER_TARGET=${FUZZ_SECONDS:-60}
TARGETS=${FUZZ_TARGETS:-fuzz_detect fuzz_conversions fuzz_readers}
export PATH=/usr/bin:/bin:$PATH
export PYTHONNOUSERSITE=1

mkdir -p "$OUT"
"$ROOT/scripts/make_workspace.sh" "$WS"
FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -g"
LINK="-fsanitize=address,undefined"
echo "fuzz: building $TARGETS with clang-14 (log: build/fuzz/build.log)"
(
  cd "$WS"
  catkin_make -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPYTHON_EXECUTABLE=/usr/bin/python3 \
    -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 -DCATKIN_ENABLE_TESTING=OFF \
    -DRGBD_LANE_DETECTOR_FUZZ=ON -DCMAKE_C_FLAGS="$FLAGS" -DCMAKE_CXX_FLAGS="$FLAGS" \
    -DCMAKE_EXE_LINKER_FLAGS="$LINK" -DCMAKE_SHARED_LINKER_FLAGS="$LINK" \
    $TARGETS -j"${FUZZ_JOBS:-2}"
) > "$OUT/build.log" 2>&1 || { tail -n 40 "$OUT/build.log"; exit 1; }

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:allocator_may_return_null=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
failed=0
summary=()
for t in $TARGETS; do
  bin=$WS/devel/lib/rgbd_lane_detector/$t
  corpus=$OUT/corpus/$t
  artifacts=$OUT/artifacts/$t/
  mkdir -p "$corpus" "$artifacts"
  dict=()
  [ -f "$ROOT/fuzz/$t.dict" ] && dict=(-dict="$ROOT/fuzz/$t.dict")
  # structured inputs (FuzzedDataProvider): long ones from the start; text: grow gradually
  case "$t" in
    fuzz_readers) len=(-max_len=65536) ;;
    *) len=(-max_len=4096 -len_control=0) ;;
  esac
  log=$OUT/$t.log
  echo "fuzz: $t for ${SECONDS_PER_TARGET}s (log: build/fuzz/$t.log)"
  rc=0
  # new entries go to the first corpus folder (build/), the committed seeds are only read
  "$bin" "$corpus" "$ROOT/fuzz/corpus/$t" "${dict[@]}" -max_total_time="$SECONDS_PER_TARGET" \
    -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 -detect_leaks=1 "${len[@]}" \
    -print_final_stats=1 -artifact_prefix="$artifacts" > "$log" 2>&1 || rc=$?
  runs=$(grep -oE '^stat::number_of_executed_units: *[0-9]+' "$log" | grep -oE '[0-9]+$' || echo 0)
  speed=$(grep -oE '^stat::average_exec_per_sec: *[0-9]+' "$log" | grep -oE '[0-9]+$' || echo 0)
  entries=$(find "$corpus" -type f | wc -l)
  cov=$(grep -oE 'cov: [0-9]+' "$log" | tail -n 1 | grep -oE '[0-9]+' || echo 0)
  findings=$(find "$artifacts" -type f | wc -l)
  line=$(printf '%-17s %4ss  runs %9s  exec/s %6s  corpus %5s  cov %5s  findings %s' \
    "$t" "$SECONDS_PER_TARGET" "$runs" "$speed" "$entries" "$cov" "$findings")
  summary+=("$line")
  if [ "$rc" -ne 0 ] || [ "$findings" -ne 0 ]; then
    failed=$((failed + 1))
    echo "FAILED: $t (exit $rc); artifacts in build/fuzz/artifacts/$t"
    grep -E 'ERROR|runtime error|SUMMARY|==[0-9]+==|Test unit written' "$log" | head -n 20 || true
  fi
done
echo "fuzz: results"
printf '  %s\n' "${summary[@]}"
echo "fuzz: $(( $(echo $TARGETS | wc -w) - failed )) clean, ${failed} failed"
[ "$failed" -eq 0 ]
