#!/usr/bin/env bash
# Create the catkin workspace (the repository linked into its src, see make_workspace.sh) and
# build it with catkin_make.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WS=$(realpath -m "${1:-$ROOT/build/ws}")
shift || true
export PATH=/usr/bin:/bin:$PATH
"$ROOT/scripts/make_workspace.sh" "$WS"
LOG=$(dirname "$WS")/catkin_make.log
cd "$WS"
t0=$(date +%s)
if ! catkin_make -j"$(nproc)" -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
     -DCATKIN_ENABLE_TESTING=ON "$@" > "$LOG" 2>&1; then
  tail -n 60 "$LOG"
  echo "build: FAILED (log: $LOG)"
  exit 1
fi
# warnings in the package's own code (not in system headers)
warnings=$(grep -E "warning:" "$LOG" | grep -v "^/usr/" | sort -u || true)
if [ -n "$warnings" ]; then
  echo "$warnings" | head -20
fi
echo "build: ok in $(( $(date +%s) - t0 )) s (log: $LOG)"
