#!/usr/bin/env bash
# Install the Debian packages rgbd_lane_detector needs to build, test and demo.
# Idempotent: only missing packages are installed, so a second run is quick and silent.
# With a group name (fuzz, load), installs that group's packages only.
set -euo pipefail

PACKAGES=(
  build-essential cmake git
  catkin catkin-lint ros-base-dev python3-catkin-pkg
  libnodeletlib-dev libnodeletlib-tools libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  libimage-transport-dev image-transport-tools libcv-bridge-dev python3-cv-bridge libimage-geometry-dev
  libmessage-filters-dev libtf2-ros-dev libtf2-eigen-dev libtf2-geometry-msgs-dev python3-tf2-ros
  libdiagnostic-updater-dev libcamera-calibration-parsers-dev libyaml-cpp-dev libvisualization-msgs-dev libnav-msgs-dev python3-nav-msgs
  libstereo-msgs-dev ros-stereo-image-proc libstereo-image-proc-dev ros-image-proc libimage-proc-dev
  librosbag-dev python3-rosbag librostest-dev python3-rostest rosbash python3-sensor-msgs
  libopencv-dev libopencv-contrib-dev libeigen3-dev libgtest-dev libbenchmark-dev libhwy-dev
  python3-opencv python3-numpy python3-matplotlib
  rviz xvfb xauth x11-utils libx11-dev libgl1-mesa-dri python3-roslaunch python3-rosgraph python3-rosparam
)
# Optional groups, installed only when named: `install_deps.sh fuzz` (make fuzz),
# `install_deps.sh load` (make test-load) and `install_deps.sh arm64` (make test-arm64: the cross
# compiler and qemu; the arm64 libraries go into a sysroot under build/, see arm64_sysroot.sh).
FUZZ_PACKAGES=(clang-14 libclang-rt-14-dev)
LOAD_PACKAGES=(stress-ng)
ARM64_PACKAGES=(g++-aarch64-linux-gnu qemu-user cmake file)
for group in "$@"; do
  case "$group" in
    fuzz) PACKAGES=("${FUZZ_PACKAGES[@]}") ;;
    load) PACKAGES=("${LOAD_PACKAGES[@]}") ;;
    arm64) PACKAGES=("${ARM64_PACKAGES[@]}") ;;
    *) echo "install_deps: unknown package group '$group' (known: fuzz, load, arm64)" >&2; exit 1 ;;
  esac
done

missing=()
for pkg in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$pkg")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install_deps: need root (or sudo) to install: ${missing[*]}" >&2
    exit 1
  fi
fi
echo "install_deps: installing ${#missing[@]} package(s): ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q "${missing[@]}"
