#!/usr/bin/env bash
# One entry point on a fresh Debian 12 machine:
#   tools/setup.sh run   install what is missing, build, run the main job
#   tools/setup.sh test  install what is missing, build, run the whole test suite
#   tools/setup.sh build install what is missing and build
#   tools/setup.sh deps  install what is missing only
# `test` runs the suite: the unit and sim tests under ASan + UBSan (a second
# build in $BUILD_DIR-sanitize), the rest in the main build; SANITIZE=0 runs
# them all in the main build, without sanitizers.
# Environment: BUILD_DIR (default build), JOBS (default: number of cores),
# EXTRA_PACKAGES (more Debian packages to install, e.g. clang for tools/fuzz.sh).
set -euo pipefail
cd "$(dirname "$0")/.."

mode=${1:-build}
shift || true
build_dir=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc)}

packages=(cmake g++ ninja-build pkg-config
  libmujoco-dev libqhull-dev libeigen3-dev liburdfdom-dev libassimp-dev libmeshoptimizer-dev
  libosmesa6-dev libegl-dev libyaml-cpp-dev libpng-dev libcli11-dev
  libgtest-dev libbenchmark-dev libnlopt-cxx-dev libtinyxml2-dev nlohmann-json3-dev
  parallel
  pybind11-dev python3-dev python3-numpy python3-pytest
  slurm-wlm munge
  chromium
  ${EXTRA_PACKAGES:-})

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

[ "$mode" = deps ] && exit 0

# A unity build (each library's and program's sources compiled eight to a
# file): compile CPU 864 s -> 551 s on 2 cores, the same binaries' outputs
# (timeseries.csv byte for byte). An edited source recompiles its batch; a
# developer who edits often configures a folder of their own without it.
# `test` compiles and runs the unit and sim tests once, in the sanitizer
# build, which is where a memory error or undefined behaviour shows; the main
# build (-O3) runs the slow, program, page, Python, install and Slurm tests.
# Both builds compiling them was 3.4 minutes of CPU more in the main build and
# 1.3 more running them (fresh clone, 2 cores).
sanitize=${SANITIZE:-1}
quick_tests=ON
if [ "$mode" = test ] && [ "$sanitize" != 0 ]; then quick_tests=OFF; fi
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON \
  -DARTTRACK_QUICK_TESTS=$quick_tests
cmake --build "$build_dir" -j "$jobs"

case "$mode" in
  build) ;;
  # --force: the main job rewrites out/<scenario> on every call.
  run) "$build_dir/arttrack" run --force "$@" ;;
  test)
    ctest --test-dir "$build_dir" --output-on-failure -j "$jobs" "$@"
    # Then the unit and sim tests under AddressSanitizer + UBSan, built in a
    # second folder (their programs only), unity too (the libraries' compile
    # CPU 269 s -> 203 s there). SANITIZE=0 skips this.
    if [ "$sanitize" != 0 ]; then
      san_dir=${build_dir}-sanitize
      cmake -S . -B "$san_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DARTTRACK_SANITIZE=ON \
        -DCMAKE_UNITY_BUILD=ON -DARTTRACK_QUICK_TESTS=ON
      cmake --build "$san_dir" -j "$jobs" --target unit_sim_tests
      LSAN_OPTIONS="suppressions=$PWD/tools/lsan.supp:print_suppressions=0" \
        UBSAN_OPTIONS=print_stacktrace=1 \
        ctest --test-dir "$san_dir" --output-on-failure -j "$jobs" -L '^(unit|sim)$'
    fi
    ;;
  *) echo "setup: unknown mode '$mode' (use run, test, build or deps)" >&2; exit 2 ;;
esac
