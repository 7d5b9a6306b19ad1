#!/usr/bin/env bash
# The tracker as another project uses it (ctest label: install):
#   1. a tracker-only configure (-DARTTRACK_BUILD_SIM=OFF) looks for none of
#      the simulator's, tools' or tests' packages;
#   2. `cmake --install` of the build into a temporary prefix; no path of the
#      source tree in the installed libraries;
#   3. examples/ configured as its own project against the installed package
#      (find_package(arttrack)), linked shared and static, built and run;
#   4. the same example compiled with `pkg-config --cflags --libs arttrack`;
#   5. when the build has the Python module (ARTTRACK_PYTHON), the installed
#      package imports from the prefix's site folder and help() works.
# Usage: check_install.sh SOURCE_DIR BUILD_DIR [CMAKE_GENERATOR]
# (the generator of the build, so that no other build tool is needed).
set -euo pipefail
src=$(cd "$1" && pwd)
build=$(cd "$2" && pwd)
generator=${3:-Unix Makefiles}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "check_install: $*" >&2; exit 1; }

# 1. Tracker only: configure, then check what was looked for.
cmake -S "$src" -B "$tmp/tracker-only" -G "$generator" -DARTTRACK_BUILD_SIM=OFF > "$tmp/tracker-only.log" 2>&1 ||
  { cat "$tmp/tracker-only.log" >&2; fail "tracker-only configure failed"; }
# (tinyxml2 is the tracker's own: it checks COLLADA meshes before assimp reads them.)
for pkg in mujoco GTest benchmark NLopt CLI11 nlohmann_json; do
  if grep -q "^${pkg}_DIR:" "$tmp/tracker-only/CMakeCache.txt"; then
    fail "the tracker-only configure looked for $pkg"
  fi
done
if grep -qE "/(arttrack_sim[a-z_]*|arttrack|[a-z]+_tests)\.dir" \
  "$tmp/tracker-only/CMakeFiles/TargetDirectories.txt"; then
  fail "the tracker-only configure has simulator, tool or test targets"
fi

# 2. Install the full build's tracker.
prefix="$tmp/prefix"
cmake --install "$build" --prefix "$prefix" > "$tmp/install.log"
pc=$(find "$prefix" -name arttrack.pc)
[ -n "$pc" ] || fail "no arttrack.pc installed under $prefix"
libdir=$(dirname "$(dirname "$pc")")
for lib in "$libdir"/libarttrack_tracker.a "$libdir"/libarttrack_tracker.so; do
  [ -e "$lib" ] || fail "$lib not installed"
  if grep -qa "$src" "$lib"; then fail "$lib holds the source path $src"; fi
done
[ -f "$prefix/include/arttrack/tracker/tracker.h" ] || fail "tracker.h not installed"
[ -f "$prefix/include/arttrack/tracker/version.h" ] || fail "version.h not installed"
# Only the public headers are installed (tracker/include; the internal ones in
# tracker/internal are the library's own), and each compiles on its own.
public="camera.h depth_model_params.h depth_renderer.h error.h joint_filter_params.h kinematics.h
  mesh_loader.h model_limits.h particle_filter_params.h robot_model.h tracker.h tracker_config.h
  tracker_config_yaml.h units.h version.h yaml_config.h"
installed=$(cd "$prefix/include/arttrack/tracker" && find . -type f | sed 's|^\./||' | sort | tr '\n' ' ')
expected=$(tr ' ' '\n' <<< "$public" | grep . | sort | tr '\n' ' ')
[ "$installed" = "$expected" ] ||
  fail "installed headers: $installed; the public ones are: $expected"
for h in $public; do
  c++ -std=c++20 -fsyntax-only -x c++ "$prefix/include/arttrack/tracker/$h" -I"$prefix/include" \
    $(pkg-config --cflags eigen3 yaml-cpp) 2> "$tmp/header.txt" ||
    { cat "$tmp/header.txt" >&2; fail "the installed $h does not compile on its own"; }
done
# The public tracker header pulls in no yaml-cpp header (-H lists every include).
c++ -std=c++20 -fsyntax-only -H -x c++ "$prefix/include/arttrack/tracker/tracker.h" \
  -I"$prefix/include" $(pkg-config --cflags eigen3) 2> "$tmp/includes.txt" ||
  { cat "$tmp/includes.txt" >&2; fail "tracker.h does not compile on its own"; }
if grep -q "yaml" "$tmp/includes.txt"; then
  fail "the public header tracker.h includes yaml-cpp: $(grep yaml "$tmp/includes.txt" | head -1)"
fi

# 3. The example against the installed CMake package, shared and static.
for kind in shared static; do
  static=OFF
  [ "$kind" = static ] && static=ON
  cmake -S "$src/examples" -B "$tmp/example-$kind" -G "$generator" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" -DARTTRACK_EXAMPLE_STATIC=$static > "$tmp/example.log" 2>&1 ||
    { cat "$tmp/example.log" >&2; fail "examples/ ($kind) does not configure"; }
  cmake --build "$tmp/example-$kind" > "$tmp/example.log" 2>&1 ||
    { cat "$tmp/example.log" >&2; fail "examples/ ($kind) does not build"; }
  if [ "$kind" = shared ]; then
    # ldd's output is kept first: `ldd | grep -q` under pipefail fails at
    # random when grep exits early and ldd dies of SIGPIPE.
    deps=$(ldd "$tmp/example-$kind/track_arm")
    used=$(awk '/libarttrack_tracker\.so/ { print $3 }' <<< "$deps")
    [ -n "$used" ] && [ "$used" -ef "$libdir/libarttrack_tracker.so" ] ||
      fail "the shared example does not use $libdir/libarttrack_tracker.so; ldd says: $deps"
  fi
  echo "== track_arm ($kind)"
  "$tmp/example-$kind/track_arm" || fail "track_arm ($kind) failed"
done
"$tmp/example-shared/track_arm" --no-images || fail "track_arm --no-images failed"

# 4. The example with pkg-config alone.
export PKG_CONFIG_PATH="$libdir/pkgconfig"
[ "$(pkg-config --modversion arttrack)" = "$(sed -n 's/^#define ARTTRACK_VERSION "\(.*\)"/\1/p' \
  "$prefix/include/arttrack/tracker/version.h")" ] || fail "arttrack.pc has another version"
flags=$(pkg-config --cflags --libs arttrack) || fail "pkg-config --cflags --libs arttrack failed"
echo "== pkg-config --cflags --libs arttrack: $flags"
# shellcheck disable=SC2086  # the flags are words
c++ -std=c++20 -O1 "$src/examples/track_arm.cc" $flags -o "$tmp/track_arm_pc" ||
  fail "the example does not compile with pkg-config's flags"
LD_LIBRARY_PATH="$libdir" "$tmp/track_arm_pc" > /dev/null || fail "track_arm (pkg-config) failed"

# 5. The Python package in the prefix's site folder.
cache="$build/CMakeCache.txt"
if grep -q "^ARTTRACK_PYTHON:BOOL=ON" "$cache"; then
  python=$(sed -n 's/^Python3_EXECUTABLE:FILEPATH=//p' "$cache")
  site="$prefix/$(sed -n 's/^ARTTRACK_PYTHON_INSTALL_DIR:STRING=//p' "$cache")"
  [ -f "$site/arttrack/__init__.py" ] || fail "the Python package is not installed in $site"
  where=$(cd "$tmp" && PYTHONPATH="$site" "$python" -c \
    "import arttrack; help(arttrack.Tracker); print(arttrack.__file__)" | tail -1) ||
    fail "the installed Python package does not import"
  [ "$where" -ef "$site/arttrack/__init__.py" ] || fail "python imported arttrack from $where"
  echo "== python: import arttrack from $site"
fi
echo "check_install: ok"
