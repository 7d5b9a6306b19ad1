#!/usr/bin/env bash
# Fuzzes the readers of user files (tests/fuzz/fuzz_targets.h) with libFuzzer:
#   tools/fuzz.sh [SECONDS] [TARGET...]
# builds the harnesses with clang (ASan + UBSan, -DARTTRACK_FUZZ=ON) in their
# own build folder, seeds each corpus from the shipped files and a small
# exported dataset, and runs each target SECONDS (default 60) in turn:
# urdf, mesh, yaml, dataset, png (default all). Inputs that crash, hang
# (over 10 s) or leak land in $FUZZ_DIR/findings/<target>/; keep each one as
# tests/fuzz/regressions/<target>/<name> once fixed. Exit 1 if any target
# found something. Environment: FUZZ_DIR (default build-fuzz), JOBS.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

seconds=${1:-60}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(urdf mesh yaml dataset png)
[[ $seconds =~ ^[0-9]+$ && $seconds -gt 0 ]] || {
  echo "fuzz: SECONDS must be a positive whole number, got '$seconds'" >&2
  exit 2
}
for t in "${targets[@]}"; do
  [[ $t =~ ^(urdf|mesh|yaml|dataset|png)$ ]] || {
    echo "fuzz: unknown target '$t' (urdf, mesh, yaml, dataset or png)" >&2
    exit 2
  }
done
dir=${FUZZ_DIR:-build-fuzz}
jobs=${JOBS:-$(nproc)}

EXTRA_PACKAGES="clang libclang-rt-dev" tools/setup.sh deps
cmake -S . -B "$dir" -G Ninja -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g" -DARTTRACK_FUZZ=ON >/dev/null
cmake --build "$dir" -j "$jobs" --target arttrack "${targets[@]/#/fuzz_}"
export LSAN_OPTIONS="suppressions=$root/tools/lsan.supp:print_suppressions=0"

# ---- corpus seeds from the shipped files ----
seed() {  # seed TARGET NAME [PREFIX] < file
  mkdir -p "$dir/corpus/$1"
  { printf '%s' "${3:-}"; cat; } >"$dir/corpus/$1/seed_$2"
}
for f in models/*.urdf; do seed urdf "$(basename "$f")" <"$f"; done
for f in $(find models/meshes -type f); do
  case $f in *.stl) p=s ;; *.obj) p=o ;; *.dae) p=d ;; *) continue ;; esac
  seed mesh "$(basename "$(dirname "$f")")_$(basename "$f")" $p <"$f"
done
for f in tracker/config/*.yaml; do seed yaml "tracker_$(basename "$f")" T <"$f"; done
for f in models/*.yaml; do seed yaml "scene_$(basename "$f")" S <"$f"; done
for f in $(find scenarios -name '*.yaml'); do seed yaml "scenario_${f//\//_}" C <"$f"; done
# A small exported dataset (as tests/fuzz/fuzz_regression_test.cc exports):
# its text files, an index listing the one image the input carries, the image.
ds=$dir/seed_dataset
rm -rf "$ds"
"$dir/arttrack" export scenarios/default.yaml --set duration_s=0.1 --set camera.width=32 \
  --set camera.height=24 --set joint_rate_hz=100 --out "$ds" >/dev/null
pngs=("$ds"/depth/*.png)  # no `ls | head` under pipefail (SIGPIPE)
png=${pngs[0]}
{
  for f in camera.yaml joints.csv ground_truth.csv; do cat "$ds/$f"; printf '\n@@@\n'; done
  printf 'stamp_s,arrival_s,file\n0,0,a.png\n\n@@@\n'
  cat "$ds/dataset.yaml"; printf '\n@@@\n'
  cat "$png"
} | seed dataset exported
for f in "$ds"/depth/*.png; do seed png "$(basename "$f")" <"$f"; done

# ---- fuzzing ----
# Third-party leaks on malformed input (tests/fuzz/lsan.supp) are not findings.
export LSAN_OPTIONS="suppressions=$root/tests/fuzz/lsan.supp:print_suppressions=0"
status=0
summary=()
for t in "${targets[@]}"; do
  mkdir -p "$dir/findings/$t"
  log=$dir/fuzz_$t.log
  echo "fuzz: $t for $seconds s (log: $log)"
  if "$dir/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$dir/findings/$t/" -print_final_stats=1 "$dir/corpus/$t" >"$log" 2>&1; then
    result=ok
  else
    result="FINDING (see $log and $dir/findings/$t/)"
    status=1
  fi
  last=$(grep -E '^#[0-9]+' "$log" | tail -1 || true)
  summary+=("$t: $result; last: ${last:-none}")
done
printf 'fuzz: %s\n' "${summary[@]}"
exit $status
