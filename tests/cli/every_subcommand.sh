#!/bin/sh
# every_subcommand.sh ARTTRACK SCENARIO: a user's robot must run every
# subcommand, not only `run`. Each is called briefly (1 s of simulation, a
# small camera) on SCENARIO, in a fresh folder, and must exit 0 and write its
# outputs: render, run, rerun, export, track (of the export), sweep (two
# cells), merge is covered by the sweep tests, tune (two evaluations), bench.
arttrack=$1
scenario=$2
dir=$(mktemp -d) || exit 1
trap 'rm -rf "$dir"' EXIT
cd "$dir" || exit 1
short="duration_s=1"
small="camera.width=80"
small_h="camera.height=60"
step() {  # step NAME OUTPUT COMMAND...: run, then check OUTPUT exists
  name=$1
  output=$2
  shift 2
  if ! timeout 240 "$arttrack" "$@" </dev/null >out.txt 2>&1; then
    echo "$name failed (exit $?): $arttrack $*"
    cat out.txt
    exit 1
  fi
  [ -e "$output" ] || { echo "$name: no $output"; cat out.txt; exit 1; }
}
step render render/sim_depth.png render "$scenario" --out render
step run run/summary.json run "$scenario" --runs 1 --methods encoders_only,full_fusion \
  --set $short --set $small --set $small_h --out run
step rerun rerun/timeseries.csv rerun run --out rerun
cmp run/timeseries.csv rerun/timeseries.csv || { echo "rerun differs from run"; exit 1; }
step export dataset/joints.csv export "$scenario" --set $short --set $small --set $small_h \
  --out dataset
step track track/summary.json track dataset --methods encoders_only,full_fusion --out track
step sweep sweep/sweep.csv sweep "$scenario" --grid "duration_s=1,1.5" --runs 1 \
  --methods full_fusion --set $small --set $small_h --out sweep
step tune tune/tuned.yaml tune "$scenario" --params particle_filter.bandwidth_factor=0.5:1.5 \
  --budget 2 --runs 1 --set $short --set $small --set $small_h --out tune
step bench bench.json bench "$scenario" --set $short --json bench.json
exit 0
