#!/bin/sh
# accuracy_table.sh ARTTRACK SCENARIO TOOL: tools/accuracy_table.py --pool
# against the scorer. Pooling one output folder must give the row the
# scorer's summary.json gives (percentiles recomputed from timeseries.csv);
# pooling two folders of the same scenario sums their runs; folders scored
# differently are refused.
arttrack=$1
scenario=$2
tool=$3
. "$(dirname "$0")/common.sh"

for out in a:7 b:8; do
  timeout 300 "$arttrack" run "$scenario" --methods encoders_only,full_fusion --runs 2 \
    --set duration_s=2 --set scoring.converged_after_s=0.5 --set camera.width=80 \
    --set camera.height=60 --seed "${out#*:}" --out "${out%:*}" </dev/null >out.txt 2>&1 ||
    fail "run --seed ${out#*:} failed:"
done
python3 "$tool" a >plain.txt 2>out.txt || fail "accuracy_table.py a failed:"
python3 "$tool" --pool a >pooled.txt 2>out.txt || fail "accuracy_table.py --pool a failed:"
cmp -s plain.txt pooled.txt || { diff plain.txt pooled.txt >out.txt; fail "--pool of one folder differs from its summary:"; }
grep -q "| full_fusion | 2 |" plain.txt || { cp plain.txt out.txt; fail "no full_fusion row of 2 runs:"; }
# Nine columns: consistency over all samples and from converged_after_s on,
# then the end effectors' (position / rotation, all samples and converged).
# Shares to a tenth of a percent (99.4% is over the band's top, not 99%).
[ "$(awk -F'|' '/\| full_fusion \|/ { print NF }' plain.txt)" = 11 ] &&
  grep -q "| full_fusion | 2 |.*[0-9]\.[0-9]% / .*% | .*% / .*% | .*% / .*%, .*% / .*% |$" plain.txt ||
  { cp plain.txt out.txt; fail "the full_fusion row has not both consistencies and the end effectors':"; }
# The camera per axis: six shares, all samples and converged, per method.
python3 "$tool" --camera-axes a >axes.txt 2>out.txt || fail "accuracy_table.py --camera-axes a failed:"
grep -q "| full_fusion | 2 | \([0-9.]*% / \)\{5\}[0-9.]*% | \([0-9.]*% / \)\{5\}[0-9.]*% |$" axes.txt ||
  { cp axes.txt out.txt; fail "--camera-axes: no full_fusion row with six shares twice:"; }
# How wide the reported sds are against the errors: a row per method.
python3 "$tool" --error-over-sd a >ratio.txt 2>out.txt || fail "accuracy_table.py --error-over-sd a failed:"
grep -q "| full_fusion | 2 | [0-9]*, [0-9.]*, [0-9.]*, [0-9]*, [0-9.]* | [0-9]*, [0-9.]*, [0-9.]*, [0-9]*, [0-9.]* |$" ratio.txt ||
  { cp ratio.txt out.txt; fail "--error-over-sd: no full_fusion row of joints and camera axes:"; }
# The same on a hand-made folder whose answer is known: joint j's error is
# 1 sd in run 0 and 3 sd in run 1 from 1 s on (RMS sqrt(5), largest 3, one
# pair beyond 2; over the samples 1, 3 and 3: RMS sqrt(19 / 3)); before 1 s
# it is 100 sd, and an empty estimate or a negative sd is skipped.
mkdir -p made
cat >made/summary.json <<'JSON'
{"scenario": "made", "scoring": {"converged_after_s": 1.0},
 "methods": {"full_fusion": {"lost": {"of": 2, "runs": 0}}}}
JSON
cat >made/timeseries.csv <<'CSV'
time_s,run,method,j_true_rad,j_est_rad,j_std_rad
0.5,0,full_fusion,0,10,0.1
1.0,0,full_fusion,0,0.1,0.1
1.5,0,full_fusion,0,-0.2,-0.2
2.0,0,full_fusion,0,,0.1
0.5,1,full_fusion,0,10,0.1
1.0,1,full_fusion,1,1.6,0.2
2.0,1,full_fusion,1,1.6,0.2
CSV
python3 "$tool" --error-over-sd made >made.txt 2>out.txt || fail "--error-over-sd made failed:"
grep -qx "| made | full_fusion | 2 | 2, 2.24, 3.00, 1, 2.52 | - |" made.txt ||
  { cp made.txt out.txt; fail "--error-over-sd made: not RMS 2.24, largest 3.00, 1 beyond 2, 2.52 over samples:"; }
python3 "$tool" --pool a b >both.txt 2>out.txt || fail "accuracy_table.py --pool a b failed:"
[ "$(grep -c '| 4 |' both.txt)" = 2 ] || { cp both.txt out.txt; fail "--pool a b: not one row of 4 runs per method:"; }
timeout 300 "$arttrack" run "$scenario" --methods encoders_only,full_fusion --runs 1 \
  --set duration_s=2 --set scoring.converged_after_s=1 --set camera.width=80 \
  --set camera.height=60 --out c </dev/null >out.txt 2>&1 || fail "run c failed:"
python3 "$tool" --pool a c >/dev/null 2>out.txt && fail "--pool of folders scored differently exited 0"
grep -q "scored differently" out.txt || fail "--pool a c: no message naming the difference:"
exit 0
