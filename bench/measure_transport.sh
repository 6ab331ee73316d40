#!/usr/bin/env bash
# Frames lost on the way in, and latency (issue 23, item 4): the successor of measure_nodelet.sh
# for the transport. For each size (640x480, 1280x720, 1920x1080) and rate (15, 30 Hz):
#   manager        FramePlayerNodelet (a driver-like publisher of preloaded real frames, fresh
#                  messages, zero-copy) and LaneDetectorNodelet in the same manager
#                  (launch/frame_player.launch: lane_detector.launch with config/improved.yaml,
#                  the player broadcasting base_link -> optical frame as a vehicle's tf does)
#   manager_no_tf  the same without any base_link transform (the improved preset's
#                  lane_model_frame: base_link then waits tf_timeout per frame)
#   process        the player in its manager, the detector as the standalone
#                  lane_detector_node (launch/lane_detector_node.launch): serialised, TCP
#   bag_node       rosbag play of a short bag (tools' transport_bag: the same frames) into
#                  lane_detector_node.launch
#   bag_manager    the same bag into lane_detector.launch (its own manager)
# Per run: frames published (player or bag), received by the nodelet, lost before it (seq gaps),
# not synchronised, dropped, processed, lane_plane outputs back at the player and their latency
# (now - stamp), the nodelet's callback and detect() time, and the load average.
# Output: build/measure_transport/results.md (a markdown table, for PERFORMANCE.md) and
# results.json; logs under build/measure_transport/logs.
#
# Usage: bench/measure_transport.sh            (the workspace built; sources build/ws itself)
# Environment (defaults):
#   SIZES="640x480 1280x720 1920x1080"  RATES="15 30"
#   CASES="manager manager_no_tf process bag_node bag_manager"
#   DURATION=20      s measured per player run (after WARMUP s)
#   DURATION_HD=60   s measured for the manager case at 1920x1080 30 Hz (issue 23's 60 s)
#   WARMUP=3         s published before measuring (the detector prepares on the first camera_info)
#   BAG_SECONDS=10   s of bag per size (written at 30 Hz, played at -r 1 and -r 0.5 for 15 Hz)
#   CONFIG=config/improved.yaml   WS=build/ws   OUT=build/measure_transport
#   QUICK=1          DURATION=5 DURATION_HD=10 WARMUP=2 BAG_SECONDS=4
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
export PATH=/usr/bin:/bin:$PATH
PYTHON=/usr/bin/python3
if [ "${QUICK:-0}" = 1 ]; then
  : "${DURATION:=5}" "${DURATION_HD:=10}" "${WARMUP:=2}" "${BAG_SECONDS:=4}"
fi
SIZES=${SIZES:-640x480 1280x720 1920x1080}
RATES=${RATES:-15 30}
CASES=${CASES:-manager manager_no_tf process bag_node bag_manager}
DURATION=${DURATION:-20}
DURATION_HD=${DURATION_HD:-60}
WARMUP=${WARMUP:-3}
BAG_SECONDS=${BAG_SECONDS:-10}
CONFIG=${CONFIG:-$ROOT/config/improved.yaml}
QUEUE_SIZE=${QUEUE_SIZE:-}  # set: the config with this queue_size (a copy under OUT)
WS=${WS:-$ROOT/build/ws}
OUT=${OUT:-$ROOT/build/measure_transport}

if [ -z "${CMAKE_PREFIX_PATH:-}" ] || ! echo "$CMAKE_PREFIX_PATH" | grep -q "$WS/devel"; then
  # shellcheck disable=SC1091
  set +u; source "$WS/devel/setup.bash"; set -u
fi
TOOL=$WS/devel/lib/rgbd_lane_detector/transport_bag
[ -x "$TOOL" ] || { echo "measure_transport: $TOOL not built" >&2; exit 1; }

mkdir -p "$OUT/logs" "$OUT/runs"
if [ -n "$QUEUE_SIZE" ]; then
  sed "s/^queue_size:.*/queue_size: $QUEUE_SIZE/" "$CONFIG" > "$OUT/config.yaml"
  grep -q "^queue_size:" "$OUT/config.yaml" || echo "queue_size: $QUEUE_SIZE" >> "$OUT/config.yaml"
  CONFIG=$OUT/config.yaml
fi
rm -f "$OUT"/runs/*.json

PIDS=()
kill_group() {  # INT, then KILL, of one process group we started
  kill -INT -- "-$1" 2> /dev/null || true
  for _ in $(seq 1 50); do kill -0 -- "-$1" 2> /dev/null || return 0; sleep 0.1; done
  kill -KILL -- "-$1" 2> /dev/null || true
}
cleanup() {
  local pid
  for pid in "${PIDS[@]}"; do kill_group "$pid"; done
}
trap cleanup EXIT
start() {  # start LOG CMD...: in its own process group; its pid in $STARTED
  local log=$1
  shift
  setsid "$@" > "$log" 2>&1 < /dev/null &
  STARTED=$!
  PIDS+=("$STARTED")
}
stop() {  # stop the run's processes (not roscore)
  local pid keep=()
  for pid in "${PIDS[@]}"; do
    if [ "$pid" = "$CORE" ]; then keep+=("$pid"); else kill_group "$pid"; fi
  done
  PIDS=("${keep[@]}")
}

PORT=$($PYTHON -c "import socket; s = socket.socket(); s.bind(('localhost', 0)); print(s.getsockname()[1])")
export ROS_MASTER_URI=http://localhost:$PORT ROS_HOSTNAME=localhost ROS_LOG_DIR=$OUT/logs/ros
start "$OUT/logs/roscore.log" roscore -p "$PORT"
CORE=$STARTED
until rosparam list > /dev/null 2>&1; do sleep 0.2; done

wait_subscriber() {  # wait_subscriber TOPIC TIMEOUT: until the topic has a subscriber
  local t0=$SECONDS
  until rostopic info "$1" 2> /dev/null | grep -A1 "^Subscribers:" | grep -q "^ \* "; do
    [ $((SECONDS - t0)) -lt "$2" ] || return 1
    sleep 0.3
  done
}

meta() {  # meta FILE KEY=VALUE...: the run's description beside the probe's result
  $PYTHON - "$@" <<'EOF'
import json, sys
path = sys.argv[1]
d = json.load(open(path)) if path and __import__("os").path.exists(path) else {}
for kv in sys.argv[2:]:
    k, v = kv.split("=", 1)
    d[k] = v
json.dump(d, open(path, "w"), indent=1)
EOF
}

tcp_counters() {  # the machine's TCP retransmitted segments and retransmission timeouts, "R T"
  awk '$1 == "Tcp:" && !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next }
       $1 == "Tcp:" { r = $c["RetransSegs"] } END { printf "%s ", r }' /proc/net/snmp
  awk '$1 == "TcpExt:" && !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next }
       $1 == "TcpExt:" { print $c["TCPTimeouts"] }' /proc/net/netstat
}
tcp_delta() {  # tcp_delta "R0 T0": meta arguments for the counters' growth since R0 T0
  local a b
  read -r -a a <<< "$1"
  read -r -a b <<< "$(tcp_counters)"
  echo "tcp_retransmits=$((b[0] - a[0]))" "tcp_timeouts=$((b[1] - a[1]))"
}

run_player() {  # run_player CASE W H RATE DURATION
  local case=$1 w=$2 h=$3 rate=$4 dur=$5
  local id=${case}_${w}x${h}_${rate}
  local json=$OUT/runs/$id.json
  local load
  load=$(cut -d' ' -f1-3 /proc/loadavg)
  echo "measure_transport: $id (${dur} s after ${WARMUP} s warm-up; load $load)"
  local tf=true detector=true tcp0
  tcp0=$(tcp_counters)
  [ "$case" = manager_no_tf ] && tf=false
  [ "$case" = process ] && detector=false
  start "$OUT/logs/$id.probe.log" $PYTHON "$ROOT/bench/transport_probe.py" --mode player \
    --out "$json" --timeout $((dur + WARMUP + 120))
  local probe=$STARTED
  start "$OUT/logs/$id.launch.log" roslaunch "$ROOT/launch/frame_player.launch" width:="$w" \
    height:="$h" rate:="$rate" duration:="$dur" warmup:="$WARMUP" publish_tf:="$tf" \
    detector:="$detector" config:="$CONFIG"
  if [ "$case" = process ]; then
    start "$OUT/logs/$id.node.log" roslaunch "$ROOT/launch/lane_detector_node.launch" \
      config:="$CONFIG"
  fi
  local t0=$SECONDS
  while kill -0 "$probe" 2> /dev/null; do
    if [ $((SECONDS - t0)) -gt $((dur + WARMUP + 180)) ]; then break; fi
    sleep 0.5
  done
  wait "$probe" 2> /dev/null || true
  stop
  # shellcheck disable=SC2046
  meta "$json" case="$case" size="${w}x${h}" rate="$rate" duration="$dur" load="$load" \
    $(tcp_delta "$tcp0") \
    queue_size="$(sed -n 's/^queue_size: *\([0-9]*\).*/\1/p' "$CONFIG")" \
    load_end="$(cut -d' ' -f1-3 /proc/loadavg)"
}

run_bag() {  # run_bag CASE W H RATE BAG
  local case=$1 w=$2 h=$3 rate=$4 bag=$5
  local id=${case}_${w}x${h}_${rate}
  local json=$OUT/runs/$id.json done_file=$OUT/runs/$id.done
  local load factor
  load=$(cut -d' ' -f1-3 /proc/loadavg)
  factor=$($PYTHON -c "print($rate / 30.0)")
  echo "measure_transport: $id (bag ${BAG_SECONDS} s at -r $factor; load $load)"
  rm -f "$done_file"
  start "$OUT/logs/$id.probe.log" $PYTHON "$ROOT/bench/transport_probe.py" --mode bag \
    --out "$json" --done-file "$done_file" --timeout $((BAG_SECONDS * 3 + 120)) \
    --subscribe /camera/lane_plane
  local probe=$STARTED
  if [ "$case" = bag_node ]; then
    start "$OUT/logs/$id.launch.log" roslaunch "$ROOT/launch/lane_detector_node.launch" \
      config:="$CONFIG"
  else
    start "$OUT/logs/$id.launch.log" roslaunch "$ROOT/launch/lane_detector.launch" config:="$CONFIG"
  fi
  # the probe subscribes lane_plane, so the nodelet subscribes its inputs: wait for that
  wait_subscriber /camera/rgb/image_rect_color 60 ||
    echo "measure_transport: $id: the detector did not subscribe its input" >&2
  local p0 p1 tcp0
  tcp0=$(tcp_counters)
  p0=$(date +%s.%N)
  rosbag play --quiet -r "$factor" "$bag" > "$OUT/logs/$id.play.log" 2>&1 || true
  p1=$(date +%s.%N)
  touch "$done_file"
  wait "$probe" 2> /dev/null || true
  stop
  # shellcheck disable=SC2046
  meta "$json" case="$case" size="${w}x${h}" rate="$rate" load="$load" $(tcp_delta "$tcp0") \
    queue_size="$(sed -n 's/^queue_size: *\([0-9]*\).*/\1/p' "$CONFIG")" \
    load_end="$(cut -d' ' -f1-3 /proc/loadavg)" \
    bag_frames="$((BAG_SECONDS * 30))" \
    play_seconds="$($PYTHON -c "print(round($p1 - $p0, 2))")" \
    bag_seconds="$($PYTHON -c "print(round($BAG_SECONDS * 30 / $rate, 2))")"
}

for size in $SIZES; do
  w=${size%x*}
  h=${size#*x}
  for rate in $RATES; do
    for case in $CASES; do
      case $case in
        manager|manager_no_tf|process)
          dur=$DURATION
          [ "$case" = manager ] && [ "$size" = 1920x1080 ] && [ "$rate" = 30 ] && dur=$DURATION_HD
          run_player "$case" "$w" "$h" "$rate" "$dur" ;;
      esac
    done
  done
  if echo " $CASES " | grep -q " bag_"; then
    bag=$OUT/transport_${size}.bag
    echo "measure_transport: writing $bag (${BAG_SECONDS} s at 30 Hz)"
    "$TOOL" --width "$w" --height "$h" --rate 30 --count $((BAG_SECONDS * 30)) --out "$bag" \
      > "$OUT/logs/bag_${size}.log" 2>&1
    # the bag on disk before it is played: its writeback (3 GB at 1920x1080) would otherwise run
    # during the first plays and take the cores the nodelet needs
    sync
    for rate in $RATES; do
      for case in $CASES; do
        case $case in bag_node|bag_manager) run_bag "$case" "$w" "$h" "$rate" "$bag" ;; esac
      done
    done
    rm -f "$bag"  # bags are large (10 MB a frame at 1920x1080): one on disk at a time
  fi
done

$PYTHON "$ROOT/bench/transport_report.py" "$OUT/runs" "$OUT/results.md" "$OUT/results.json" \
  "$(git -C "$ROOT" rev-parse --short HEAD 2> /dev/null || echo unknown)" "$(nproc)"
cat "$OUT/results.md"
