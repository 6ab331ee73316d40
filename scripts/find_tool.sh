# Sourced by the driver scripts: find_tool NAME prints the path of one of the package's
# executables, from $TOOLS_BIN or the sourced workspace's CMAKE_PREFIX_PATH.
find_tool() {
  local name="$1" dir
  if [ -n "${TOOLS_BIN:-}" ] && [ -x "$TOOLS_BIN/$name" ]; then
    echo "$TOOLS_BIN/$name"
    return 0
  fi
  local IFS=:
  for dir in ${CMAKE_PREFIX_PATH:-}; do
    if [ -x "$dir/lib/rgbd_lane_detector/$name" ]; then
      echo "$dir/lib/rgbd_lane_detector/$name"
      return 0
    fi
  done
  echo "$(basename "$0"): '$name' not found; build the workspace and source its setup.bash" \
       "(make does both) or set TOOLS_BIN" >&2
  return 1
}
