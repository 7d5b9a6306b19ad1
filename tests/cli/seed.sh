#!/bin/sh
# seed.sh ARTTRACK SCENARIO: --seed of sweep and tune reaches their runs and
# is recorded. Each command runs briefly (1 s of simulation, a small camera,
# encoders only) three times: --seed 7 twice must give the same numbers,
# --seed 8 other numbers; sweep.json and tuned.yaml name the seed.
arttrack=$1
scenario=$2
. "$(dirname "$0")/common.sh"

# run COMMAND ARGS...: COMMAND with --seed 7 (into COMMAND_a and COMMAND_b)
# and --seed 8 (COMMAND_c).
run() {
  command=$1
  shift
  for out in a:7 b:7 c:8; do
    timeout 120 "$arttrack" "$command" "$scenario" "$@" --set duration_s=1 \
      --set camera.width=80 --set camera.height=60 --seed "${out#*:}" \
      --out "${command}_${out%:*}" </dev/null >out.txt 2>&1 ||
      fail "$command --seed ${out#*:} failed:"
  done
}
# compare COMMAND FILE FIELD: column FIELD of FILE the same for a and b,
# another for c.
compare() {
  for out in a b c; do cut -d, -f"$3" "$1_$out/$2" >"$out.txt"; done
  cmp -s a.txt b.txt || fail "$1: the same --seed gave other numbers"
  cmp -s a.txt c.txt && fail "$1: --seed 8 gave the numbers of --seed 7"
}

# sweep.csv: cell,<one axis>,method,statistic,value,seed,...
run sweep --grid scoring.converged_after_s=0.5 --runs 1 --methods encoders_only
compare sweep sweep.csv 5
grep -q '"scenario_seed": 7' sweep_a/sweep.json || fail "sweep.json does not record --seed 7"

# search.csv: evaluation,<one parameter>,objective,...
run tune --params particle_filter.bandwidth_factor=0.5:1.5 --objective mean_p50_translation_m \
  --tracker-method encoders_only --budget 1 --runs 1
compare tune search.csv 3
grep -q "scenario seeds (--seed): default 7" tune_a/tuned.yaml ||
  fail "tuned.yaml does not record --seed 7"
exit 0
