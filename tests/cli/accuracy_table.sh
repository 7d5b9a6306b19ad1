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
python3 "$tool" --pool a b >both.txt 2>out.txt || fail "accuracy_table.py --pool a b failed:"
[ "$(grep -c '| 4 |' both.txt)" = 2 ] || { cp both.txt out.txt; fail "--pool a b: not one row of 4 runs per method:"; }
timeout 300 "$arttrack" run "$scenario" --methods encoders_only,full_fusion --runs 1 \
  --set duration_s=2 --set scoring.converged_after_s=1 --set camera.width=80 \
  --set camera.height=60 --out c </dev/null >out.txt 2>&1 || fail "run c failed:"
python3 "$tool" --pool a c >/dev/null 2>out.txt && fail "--pool of folders scored differently exited 0"
grep -q "scored differently" out.txt || fail "--pool a c: no message naming the difference:"
exit 0
