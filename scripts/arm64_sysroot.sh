#!/usr/bin/env bash
# Debian 12 arm64 libraries for the aarch64 cross build (make test-arm64), unpacked into a sysroot
# under build/: apt resolves and downloads the arm64 packages with a private state (this machine's
# sources, APT::Architecture=arm64, an empty dpkg status), and dpkg -x unpacks them. Nothing is
# installed on the machine: installing libopencv-dev:arm64 would remove the amd64 OpenCV (it is
# not Multi-Arch), and `dpkg --add-architecture` is not needed at all.
# Idempotent: a sysroot made from the same package list is kept.
# Usage: scripts/arm64_sysroot.sh [SYSROOT]   (default build/arm64/sysroot)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
SYSROOT=$(realpath -m "${1:-$ROOT/build/arm64/sysroot}")
APTDIR=$(dirname "$SYSROOT")/apt
# what the core, its gtests and the benchmarks link (Eigen is header-only: the host's is used)
PACKAGES=(libopencv-core-dev libopencv-imgproc-dev libhwy-dev libgtest-dev libbenchmark-dev libyaml-cpp-dev)

STAMP=$SYSROOT/.packages
if [ -f "$STAMP" ] && [ "$(cat "$STAMP")" = "${PACKAGES[*]}" ]; then
  exit 0
fi
mkdir -p "$APTDIR/state/lists/partial" "$APTDIR/cache/archives/partial" "$APTDIR/etc/preferences.d"
: > "$APTDIR/state/status"
APT_OPTS=(
  -o "APT::Architecture=arm64" -o "APT::Architectures::=arm64"
  -o "Dir::State=$APTDIR/state" -o "Dir::State::status=$APTDIR/state/status"
  -o "Dir::Cache=$APTDIR/cache" -o "Dir::Etc::preferencesparts=$APTDIR/etc/preferences.d"
  -o "pkgCacheGen::Essential=none" -o "APT::Install-Recommends=false"
  -o "Debug::NoLocking=true" -o "APT::Sandbox::User=root"
)
echo "arm64 sysroot: resolving and downloading ${PACKAGES[*]} (and what they depend on)"
apt-get "${APT_OPTS[@]}" -q update > "$APTDIR/update.log"
apt-get "${APT_OPTS[@]}" -q -y --download-only install "${PACKAGES[@]}" > "$APTDIR/download.log"

rm -rf "$SYSROOT"
mkdir -p "$SYSROOT"
n=0
for deb in "$APTDIR"/cache/archives/*_arm64.deb "$APTDIR"/cache/archives/*_all.deb; do
  [ -f "$deb" ] || continue
  dpkg -x "$deb" "$SYSROOT"
  n=$((n + 1))
done
# BLAS and LAPACK are reached through update-alternatives links, which dpkg -x does not make
LIB=$SYSROOT/usr/lib/aarch64-linux-gnu
for lib in blas/libblas.so.3 lapack/liblapack.so.3; do
  if [ -e "$LIB/$lib" ] && [ ! -e "$LIB/$(basename "$lib")" ]; then
    ln -s "$lib" "$LIB/$(basename "$lib")"
  fi
done
# absolute symlinks inside the packages point at the host: make them relative to the sysroot
find "$SYSROOT" -type l | while read -r link; do
  target=$(readlink "$link")
  case "$target" in
    /*) ln -sfn "$(realpath -m --relative-to="$(dirname "$link")" "$SYSROOT$target")" "$link" ;;
  esac
done
echo "${PACKAGES[*]}" > "$STAMP"
echo "arm64 sysroot: $n packages unpacked into $SYSROOT"
