#!/usr/bin/env bash
# make soak: the LaneDetectorNodelet under a long run with churn (tools/soak/soak.py).
#  1. generates a synthetic 640x380 sequence and its rosbag (tools' generate_sequence) into
#     build/soak unless it is already there,
#  2. starts a master on its own port, a nodelet manager and the nodelet (config/improved.yaml)
#     with roslaunch (tools/soak/soak.launch),
#  3. runs tools/soak/soak.py: SOAK_FRAMES frames replayed in a loop at SOAK_RATE Hz, re-stamped,
#     with dynamic_reconfigure changes, output subscribers coming and going and bad frames;
#     it checks no crash, every frame accounted for, RSS growth, no NaN in the outputs,
#  4. leaves build/soak/soak_report.{json,md} and exits non-zero on FAIL.
# Run with the catkin workspace sourced (`make soak` builds and sources build/ws).
# Environment: SOAK_FRAMES (10000), SOAK_RATE (30), SOAK_BAG_FRAMES (150), SOAK_DIR (build/soak),
#   SOAK_SEED (1), SOAK_PORT (a free port), TOOLS_BIN.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${SOAK_DIR:-$ROOT/build/soak}"
FRAMES="${SOAK_FRAMES:-10000}"
RATE="${SOAK_RATE:-30}"
BAG_FRAMES="${SOAK_BAG_FRAMES:-150}"
SEED="${SOAK_SEED:-1}"
PYTHON=/usr/bin/python3
export PATH=/usr/bin:/bin:$PATH
export ROS_HOME="${ROS_HOME:-$ROOT/build/ros_home}"

# shellcheck source=find_tool.sh
source "$(dirname "${BASH_SOURCE[0]}")/find_tool.sh"
GENERATE="$(find_tool generate_sequence)"
mkdir -p "$OUT/logs" "$ROS_HOME"
BAG="$OUT/soak_${BAG_FRAMES}.bag"
if [ -f "$BAG" ] && [ "$BAG" -nt "$GENERATE" ]; then
  echo "== [1/3] bag $BAG (up to date)"
else
  echo "== [1/3] synthetic bag $BAG ($BAG_FRAMES frames 640x380)"
  rm -f "$BAG"
  "$GENERATE" --scenario summer --frames "$BAG_FRAMES" --width 640 --height 380 --seed "$SEED" \
    --out "$OUT/seq_${BAG_FRAMES}" --bag "$BAG.tmp" --quiet
  mv "$BAG.tmp" "$BAG"
fi

PORT="${SOAK_PORT:-$("$PYTHON" -c 'import socket; s = socket.socket(); s.bind(("", 0)); print(s.getsockname()[1])')}"
export ROS_MASTER_URI="http://localhost:$PORT"
LAUNCH_PID=""
cleanup() {
  if [ -n "$LAUNCH_PID" ] && kill -0 "$LAUNCH_PID" 2>/dev/null; then
    kill -INT -- "-$LAUNCH_PID" 2>/dev/null || true
    for _ in $(seq 100); do kill -0 "$LAUNCH_PID" 2>/dev/null || break; sleep 0.1; done
    kill -KILL -- "-$LAUNCH_PID" 2>/dev/null || true
  fi
}
trap cleanup EXIT

echo "== [2/3] master on port $PORT, manager + LaneDetectorNodelet (config/improved.yaml)"
setsid roslaunch -p "$PORT" "$ROOT/tools/soak/soak.launch" > "$OUT/logs/roslaunch.log" 2>&1 &
LAUNCH_PID=$!

echo "== [3/3] soak: $FRAMES frames at $RATE Hz"
set +e
"$PYTHON" "$ROOT/tools/soak/soak.py" --bag "$BAG" --frames "$FRAMES" --rate "$RATE" --seed "$SEED" \
  --report-dir "$OUT" 2>&1 | tee "$OUT/logs/soak.log"
status=${PIPESTATUS[0]}
set -e
echo "report: $OUT/soak_report.md, $OUT/soak_report.json; logs: $OUT/logs"
exit "$status"
