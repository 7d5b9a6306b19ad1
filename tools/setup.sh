#!/usr/bin/env bash
# One entry point on a fresh Debian 12 machine:
#   tools/setup.sh run   install what is missing, build, run the main job
#   tools/setup.sh test  install what is missing, build, run the whole test suite
#   tools/setup.sh build install what is missing and build
# Environment: BUILD_DIR (default build), JOBS (default: number of cores).
set -euo pipefail
cd "$(dirname "$0")/.."

mode=${1:-build}
shift || true
build_dir=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc)}

packages=(cmake g++ ninja-build pkg-config
  libmujoco-dev libqhull-dev libeigen3-dev liburdfdom-dev libassimp-dev
  libosmesa6-dev libegl-dev libyaml-cpp-dev libpng-dev libcli11-dev
  libgtest-dev libbenchmark-dev libnlopt-cxx-dev libtinyxml2-dev nlohmann-json3-dev)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" -j "$jobs"

case "$mode" in
  build) ;;
  run) "$build_dir/arttrack" run "$@" ;;
  test) ctest --test-dir "$build_dir" --output-on-failure -j "$jobs" "$@" ;;
  *) echo "setup: unknown mode '$mode' (use run, test or build)" >&2; exit 2 ;;
esac
