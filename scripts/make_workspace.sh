#!/usr/bin/env bash
# Create or refresh a catkin workspace whose src/rgbd_lane_detector mirrors the repository entry
# by entry (one symlink per top-level entry), leaving out build/ and .git.
# Why not one symlink to the repository: roslaunch, rostest and rosrun find a package's files
# by walking its folder and following symlinks; a link to the repository would lead the walk into
# build/<workspace>/src/rgbd_lane_detector and back into the repository, without end.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WS=$(realpath -m "${1:?usage: make_workspace.sh <workspace>}")
PKG=$WS/src/rgbd_lane_detector
mkdir -p "$WS/src"
if [ -L "$PKG" ]; then rm "$PKG"; fi  # a single link made by an older version of this script
mkdir -p "$PKG"
find "$PKG" -maxdepth 1 -type l ! -exec test -e {} \; -delete  # entries removed from the repo
shopt -s dotglob nullglob
for entry in "$ROOT"/*; do
  name=$(basename "$entry")
  case "$name" in build|.git) continue ;; esac
  ln -sfn "$entry" "$PKG/$name"
done
# build/demo alone (make demo's bag): demo.launch's default bag is
# $(find rgbd_lane_detector)/build/demo/summer.bag, in the repository and in this mirror alike
mkdir -p "$PKG/build"
ln -sfn "$ROOT/build/demo" "$PKG/build/demo"
