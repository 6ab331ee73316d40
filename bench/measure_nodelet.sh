#!/usr/bin/env bash
# What the nodelet adds over detect(), and its peak memory: plays a generated sequence into
# LaneDetectorNodelet (own manager, lane_detector.launch, config/paper.yaml as bench_core: the
# improved preset waits tf_timeout per frame for a base_link nobody publishes) with lane_plane and
# lane_markings subscribed, reads the nodelet's own diagnostics ("Mean detector time",
# "Mean ROS overhead" = callback time minus detect()), the manager's peak RSS (VmHWM), and the
# first frame: LaneDetector::prepare() on the first camera_info and the first detect() after it
# (the nodelet's log lines).
# Run with the workspace sourced. Usage: bench/measure_nodelet.sh [WIDTH HEIGHT [FRAMES]]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WIDTH=${1:-640}
HEIGHT=${2:-380}
FRAMES=${3:-200}
OUT=${MEASURE_DIR:-$ROOT/build/measure_nodelet}/${WIDTH}x${HEIGHT}
export PATH=/usr/bin:/bin:$PATH
PYTHON=/usr/bin/python3

tool() {
  local d
  IFS=: read -ra dirs <<< "${CMAKE_PREFIX_PATH:-}"
  for d in "${dirs[@]}"; do
    if [ -x "$d/lib/rgbd_lane_detector/$1" ]; then echo "$d/lib/rgbd_lane_detector/$1"; return; fi
  done
  echo "measure_nodelet: $1 not found (source the workspace)" >&2
  exit 1
}
rm -rf "$OUT/logs"  # this run's logs only (the first-frame lines are read from them)
mkdir -p "$OUT/logs"
"$(tool generate_sequence)" --scenario summer --sensor clean --frames "$FRAMES" --width "$WIDTH" \
  --height "$HEIGHT" --seed 1 --out "$OUT/seq" --skip-if-same > "$OUT/logs/generate.log" 2>&1
[ -f "$OUT/seq.bag" ] || "$(tool sequence_to_bag)" --dataset "$OUT/seq" --out "$OUT/seq.bag" \
  --rate 10 > "$OUT/logs/bag.log" 2>&1

PIDS=()
cleanup() {
  local pid
  for pid in "${PIDS[@]}"; do
    kill -INT -- "-$pid" 2>/dev/null || true
  done
  sleep 1
  for pid in "${PIDS[@]}"; do
    kill -KILL -- "-$pid" 2>/dev/null || true
  done
}
trap cleanup EXIT
start() {
  local log=$1
  shift
  setsid "$@" > "$log" 2>&1 < /dev/null &
  PIDS+=("$!")
}
PORT=$($PYTHON -c "import socket; s = socket.socket(); s.bind(('localhost', 0)); print(s.getsockname()[1])")
export ROS_MASTER_URI=http://localhost:$PORT ROS_HOSTNAME=localhost ROS_LOG_DIR=$OUT/logs
start "$OUT/logs/roscore.log" roscore -p "$PORT"
until rosparam list > /dev/null 2>&1; do sleep 0.2; done
start "$OUT/logs/nodelet.log" roslaunch "$ROOT/launch/lane_detector.launch" camera:=camera \
  config:="$ROOT/config/paper.yaml"
until rostopic list 2> /dev/null | grep -q /camera/lane_plane; do sleep 0.2; done
start "$OUT/logs/plane.log" rostopic hz /camera/lane_plane
start "$OUT/logs/markings.log" rostopic hz /camera/lane_markings
start "$OUT/logs/diagnostics.log" rostopic echo /diagnostics
sleep 2
rosbag play --quiet "$OUT/seq.bag" > "$OUT/logs/play.log" 2>&1
sleep 3
PID=$(rosnode info /camera/lane_detector_manager 2> /dev/null | sed -n 's/^Pid: //p')
HWM=$(sed -n 's/^VmHWM:\s*//p' "/proc/$PID/status")
FIRST=$(grep -rhoE "Detector prepared for [0-9x]+ frames in [0-9.]+ ms|First frame after prepare: detect\(\) [0-9.]+ ms" \
  "$OUT/logs" 2> /dev/null | sort -u | tr '\n' ';' || true)
$PYTHON - "$OUT/logs/diagnostics.log" "$WIDTH" "$HEIGHT" "$HWM" "$FIRST" <<'EOF'
import re, sys
text = open(sys.argv[1]).read()
first = re.search(r"First frame after prepare: detect\(\) ([0-9.]+) ms", sys.argv[5])
prep = re.search(r"prepared for [0-9x]+ frames in ([0-9.]+) ms", sys.argv[5])
def values(key):
    return [float(v) for v in re.findall(r'key: "%s"\s+value: "([-0-9.eE+]+)"' % re.escape(key), text)]
det, ovh = values("Mean detector time (ms)"), values("Mean ROS overhead (ms)")
det, ovh = [d for d in det if d > 0], [o for o, d in zip(ovh, values("Mean detector time (ms)")) if d > 0]
if not det:
    sys.exit("measure_nodelet: no processing diagnostics (see the logs)")
print(f"{sys.argv[2]}x{sys.argv[3]}: detect() {sum(det) / len(det):.3f} ms, nodelet overhead "
      f"{sum(ovh) / len(ovh):.3f} ms (mean of {len(det)} diagnostic windows), "
      f"manager peak RSS {sys.argv[4]}"
      + (f", prepare() on the first camera_info {prep.group(1)} ms" if prep else "")
      + (f", first detect() after it {first.group(1)} ms" if first else ""))
EOF
