#!/usr/bin/env bash
# make demo: the lane detector's real ROS graph, headless, on the built-in synthetic sequence.
#  1. generates the synthetic sequence (SYNTHIA-SEQS layout + lane ground truth) into
#     build/data/<scenario> unless it already holds exactly these settings (shared with make eval),
#  2. converts it to a rosbag with the three input topics (tools/sequence_to_bag),
#  3. runs roscore (own port), the LaneDetectorNodelet in its own manager
#     (launch/lane_detector.launch, config/synthetic.yaml = mode improved), demo_probe (latency,
#     overlay video), rosbag record of the outputs, and rosbag play --clock of the bag,
#  4. prints the report: frames in/out, TP/partial/FP against the ground truth (scoring.h),
#     latency from input to output, the same sequence offline in improved and paper mode, and
#     where the overlay video and images are.
# Exits non-zero when the graph produced no output. Every process it starts is stopped on exit.
# Run with the catkin workspace sourced (`make demo` builds and sources build/ws).
# Environment: DEMO_DIR (build/demo), DATA_DIR (build/data), DEMO_SCENARIO (summer),
#   DEMO_SENSOR (clean), FRAMES (300), WIDTH (640), HEIGHT (380), SEED (1), DEMO_RATE (10, Hz of
#   playback), DEMO_CONFIG (config/synthetic.yaml), DEMO_PORT (a free port), TOOLS_BIN.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${DEMO_DIR:-$ROOT/build/demo}"
DATA_DIR="${DATA_DIR:-$ROOT/build/data}"
SCENARIO="${DEMO_SCENARIO:-summer}"
SENSOR="${DEMO_SENSOR:-clean}"
FRAMES="${FRAMES:-300}"
WIDTH="${WIDTH:-640}"
HEIGHT="${HEIGHT:-380}"
SEED="${SEED:-1}"
RATE="${DEMO_RATE:-10}"
CONFIG="${DEMO_CONFIG:-$ROOT/config/synthetic.yaml}"
NS=/camera
PYTHON=/usr/bin/python3
export PATH=/usr/bin:/bin:$PATH

NAME="$SCENARIO"
[ "$SENSOR" != clean ] && NAME="${SCENARIO}_${SENSOR}"
SEQ="$DATA_DIR/$NAME"
BAG="$OUT/$NAME.bag"
LOGS="$OUT/logs"
t_start=$(date +%s)

# shellcheck source=find_tool.sh
source "$(dirname "${BASH_SOURCE[0]}")/find_tool.sh"
GENERATE="$(find_tool generate_sequence)"
TO_BAG="$(find_tool sequence_to_bag)"
RUN="$(find_tool run_dataset)"
PROBE="$(find_tool demo_probe)"
REPORT="$(find_tool demo_report)"
mkdir -p "$OUT" "$LOGS"

# ---------------------------------------------------------------------------------------------
echo "== [1/4] synthetic sequence $NAME ($SCENARIO/$SENSOR, $FRAMES frames ${WIDTH}x${HEIGHT}, seed $SEED) in $SEQ"
t0=$(date +%s)
"$GENERATE" --scenario "$SCENARIO" --sensor "$SENSOR" --frames "$FRAMES" --width "$WIDTH" \
  --height "$HEIGHT" --seed "$SEED" --out "$SEQ" --skip-if-same
t_generate=$(( $(date +%s) - t0 ))

echo "== [2/4] rosbag $BAG"
t0=$(date +%s)
if [ -f "$BAG" ] && [ "$BAG" -nt "$SEQ/scenario.json" ] && [ "$BAG" -nt "$TO_BAG" ]; then
  echo "up to date"
else
  # camera pose of the generator (1.5 m above the road, 3 deg down) as base_link -> optical tf
  read -r cam_height cam_pitch fps < <("$PYTHON" - "$SEQ/scenario.json" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
print(s.get("camera_height", 1.5), s.get("pitch_deg", 0.0), s.get("fps", 10.0))
EOF
)
  rm -f "$BAG"
  "$TO_BAG" --dataset "$SEQ" --out "$BAG.tmp" --rate "$fps" --tf-parent base_link \
    --tf-z "$cam_height" --tf-pitch "$cam_pitch"
  mv "$BAG.tmp" "$BAG"
fi
t_convert=$(( $(date +%s) - t0 ))
bag_fps=$("$PYTHON" -c "import json; print(json.load(open('$SEQ/scenario.json')).get('fps', 10.0))")
play_factor=$("$PYTHON" -c "print(round($RATE / $bag_fps, 4))")

# ---------------------------------------------------------------------------------------------
# The ROS graph. Every process gets its own process group (setsid) so that it and its children
# can be stopped by id; cleanup runs on every exit path.
PIDS=()
cleanup() {
  local i pid
  for (( i=${#PIDS[@]}-1; i>=0; i-- )); do
    pid=${PIDS[$i]}
    kill -0 "$pid" 2>/dev/null || continue
    kill -INT -- "-$pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -TERM -- "-$pid" 2>/dev/null || true
    for _ in $(seq 30); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL -- "-$pid" 2>/dev/null || true
  done
  PIDS=()
}
trap cleanup EXIT
trap 'exit 130' INT TERM
start() {  # start <log> <command...>: background, own process group
  local log="$1"
  shift
  setsid "$@" > "$log" 2>&1 < /dev/null &
  PIDS+=("$!")
}
stop() {  # stop <pid>: SIGINT and wait (rosbag record closes its bag, the probe its video)
  local pid="$1"
  kill -INT -- "-$pid" 2>/dev/null || return 0
  for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || return 0; sleep 0.1; done
  kill -TERM -- "-$pid" 2>/dev/null || true
}
free_port() {
  "$PYTHON" -c "import socket; s = socket.socket(); s.bind(('localhost', 0)); print(s.getsockname()[1])"
}
# wait_graph <timeout s> <python condition on pubs/subs: dicts topic -> [nodes]>
wait_graph() {
  "$PYTHON" - "$@" <<'EOF'
import sys, time
import rosgraph
timeout, condition = float(sys.argv[1]), sys.argv[2]
master = rosgraph.Master("/demo_sh")
deadline = time.time() + timeout
while time.time() < deadline:
    try:
        state = master.getSystemState()
        pubs = {t: n for t, n in state[0]}
        subs = {t: n for t, n in state[1]}
        if eval(condition):
            sys.exit(0)
    except Exception:
        pass
    time.sleep(0.2)
sys.exit(1)
EOF
}

PORT="${DEMO_PORT:-$(free_port)}"
export ROS_MASTER_URI="http://localhost:$PORT"
export ROS_HOSTNAME=localhost
unset ROS_IP
export ROS_LOG_DIR="$LOGS"
export ROSCONSOLE_FORMAT='[${severity}] [${time}] [${node}]: ${message}'

echo "== [3/4] ROS graph on $ROS_MASTER_URI: lane_detector.launch ($(basename "$CONFIG")), demo_probe, rosbag record, rosbag play at $RATE Hz"
t0=$(date +%s)
start "$LOGS/roscore.log" roscore -p "$PORT"
if ! wait_graph 30 "True"; then
  echo "demo.sh: roscore did not start on port $PORT (log: $LOGS/roscore.log)" >&2
  exit 1
fi
rosparam set /use_sim_time true

# Launch file by path: `roslaunch <pkg> <file>` would search the whole package directory.
start "$LOGS/lane_detector.log" roslaunch "$ROOT/launch/lane_detector.launch" config:="$CONFIG" camera:="${NS#/}"
if ! wait_graph 60 "'$NS/lane_plane' in pubs"; then
  tail -n 30 "$LOGS/lane_detector.log" >&2
  echo "demo.sh: the lane detector nodelet did not come up (log: $LOGS/lane_detector.log)" >&2
  exit 1
fi

rm -rf "$OUT/overlays" "$OUT/outputs.bag" "$OUT/outputs.bag.active"
mkdir -p "$OUT/overlays"
start "$LOGS/demo_probe.log" "$PROBE" __ns:="$NS" __name:=demo_probe \
  _latency_csv:="$OUT/latency.csv" _video:="$OUT/overlay.avi" _images_dir:="$OUT/overlays" \
  _image_every:=30 _video_fps:="$RATE"
PROBE_PID=${PIDS[-1]}
# the record binary itself (the rosbag wrapper script mishandles SIGINT on Debian's python 3.11)
start "$LOGS/record.log" rosrun rosbag record --tcpnodelay -O "$OUT/outputs.bag" \
  "$NS/lane_plane" "$NS/lane_markings" "$NS/lane_points" "$NS/lane_visualization" \
  "$NS/lane_model" "$NS/lane_centre_line" /tf_static
RECORD_PID=${PIDS[-1]}
inputs="['$NS/rgb/image_rect_color', '$NS/depth_registered/image_rect', '$NS/rgb/camera_info']"
if ! wait_graph 60 "all(any(n.endswith('lane_detector_manager') for n in subs.get(t, [])) for t in $inputs) and '$NS/demo_probe' in subs.get('$NS/lane_plane', []) and len(subs.get('$NS/lane_markings', [])) > 0"; then
  echo "demo.sh: the graph did not connect (logs: $LOGS)" >&2
  exit 1
fi

# progress: every 5 s of bag time
rosbag play --clock --wait-for-subscribers -r "$play_factor" "$BAG" 2>&1 | tr '\r' '\n' | sed -u 's/\x1b\[[0-9;]*m//g' | \
  awk '/Duration:/ { split($0, a, "Duration: "); split(a[2], b, " "); if (b[1] + 0 >= next_t) { printf "   played %.1f / %.1f s\n", b[1], b[3]; next_t = b[1] + 5; fflush() } next }
       NF { print "   " $0; fflush() }'
# let the last frames through the detector: until every input has an output, or 3 s of silence
"$PYTHON" - "$OUT/latency.csv" <<'EOF'
import sys, time
last, quiet_since = None, time.time()
while time.time() - quiet_since < 3.0:
    lines = open(sys.argv[1]).read().splitlines()
    n_in = sum(l.startswith("in,") for l in lines)
    n_out = sum(l.startswith("out,") for l in lines)
    if n_in > 0 and n_out >= n_in:
        break
    if (n_in, n_out) != last:
        last, quiet_since = (n_in, n_out), time.time()
    time.sleep(0.2)
EOF
stop "$RECORD_PID"
stop "$PROBE_PID"
cleanup
t_graph=$(( $(date +%s) - t0 ))

# ---------------------------------------------------------------------------------------------
echo "== [4/4] scoring"
t0=$(date +%s)
report_rc=0
report=$("$REPORT" --input "$BAG" --outputs "$OUT/outputs.bag" --truth "$SEQ/GT/LANES/ground_truth.json" \
  --latency "$OUT/latency.csv" --ns "$NS" --label improved) || report_rc=$?
offline_improved=$("$RUN" --dataset "$SEQ" --params "$CONFIG" --out "$OUT/offline_improved" --overlays 0 \
  --video none --quiet 2>/dev/null | sed -n 's/^ground truth: //p')
offline_paper=$("$RUN" --dataset "$SEQ" --mode paper --out "$OUT/offline_paper" --overlays 0 \
  --video none --quiet 2>/dev/null | sed -n 's/^ground truth: //p')
t_score=$(( $(date +%s) - t0 ))
overlays=$(find "$OUT/overlays" -name '*.png' | wc -l)
video_frames=$(grep -oE '[0-9]+ overlays' "$LOGS/demo_probe.log" | grep -oE '[0-9]+' || echo 0)

rel() { case "$1" in "$PWD"/*) echo "${1#"$PWD"/}" ;; *) echo "$1" ;; esac; }
echo
echo "================================ make demo report ================================"
echo "graph   : rosbag play --clock at $RATE Hz -> $NS/lane_detector (LaneDetectorNodelet in its own"
echo "          manager, $(rel "$CONFIG"): mode improved) -> rosbag record + demo_probe"
echo "sequence: $(rel "$SEQ") ($SCENARIO/$SENSOR, $FRAMES frames ${WIDTH}x${HEIGHT}, seed $SEED), bag $(rel "$BAG")"
echo "$report"
echo "offline, the same frames through the core without ROS (run_dataset):"
echo "  improved ($(basename "$CONFIG")): ${offline_improved:-n/a}"
echo "  paper    (Params::paper()): ${offline_paper:-n/a}"
tpfp() { echo "$1" | grep -oE 'TP [0-9.]+%  partial [0-9.]+%  FP [0-9.]+%' | head -n 1; }
graph_tpfp=$(tpfp "$report")
if [ -n "$graph_tpfp" ] && [ "$graph_tpfp" = "$(tpfp "$offline_improved")" ]; then
  echo "  check: the ROS graph scores exactly as the offline run of the same parameters"
else
  echo "  check: the ROS graph ($graph_tpfp) DIFFERS from the offline run ($(tpfp "$offline_improved")):" \
       "dropped frames, or the nodelet's parameters differ from the core's (mode preset vs cfg)"
fi
echo "outputs:"
echo "  overlay video : $(rel "$OUT/overlay.avi") ($video_frames frames of $NS/debug_image, MJPG)"
echo "  overlay images: $(rel "$OUT/overlays")/ ($overlays PNGs, every 30th overlay)"
echo "  recorded bag  : $(rel "$OUT/outputs.bag") (lane_plane, lane_markings, lane_points, lane_visualization, lane_model, lane_centre_line)"
echo "  latency CSV   : $(rel "$OUT/latency.csv"); logs: $(rel "$LOGS")"
echo "  rviz          : roslaunch $ROOT/launch/demo.launch bag:=$BAG"
echo "time: generate ${t_generate} s, bag ${t_convert} s, ROS graph ${t_graph} s, scoring ${t_score} s," \
     "total $(( $(date +%s) - t_start )) s"
echo "=================================================================================="
died=$(grep -hE "process has died" "$LOGS"/*.log 2>/dev/null | sed 's/\x1b\[[0-9;]*m//g' | cut -c1-160 || true)
[ -n "$died" ] && echo "demo: processes died during the run: $died" >&2
if [ "$report_rc" -eq 3 ]; then
  echo "demo: FAILED: the graph produced no lane_plane output (logs: $LOGS)" >&2
  exit 1
elif [ "$report_rc" -eq 4 ]; then
  echo "demo: FAILED: the graph answered fewer than 90% of the played frames (logs: $LOGS)" >&2
  exit 1
elif [ "$report_rc" -ne 0 ]; then
  echo "demo: FAILED: demo_report exit $report_rc (logs: $LOGS)" >&2
  exit 1
fi
echo "demo: ok"
