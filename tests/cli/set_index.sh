#!/bin/sh
# set_index.sh ARTTRACK: `run --set` takes list indices as `--grid` does.
# `--set 'encoders[0].offset_deg=5'` on the default scenario (one encoder
# group, offset 8.6 degrees) must run, be recorded as given in summary.json,
# change that element only in the resolved scenario (its joints stay) and
# reach the simulation: the true bias of left_arm_joint_1 is 5 degrees.
arttrack=$1
. "$(dirname "$0")/common.sh"
timeout 120 "$arttrack" run --runs 1 --methods encoders_only --set duration_s=1 \
  --set 'encoders[0].offset_deg=5' --out o </dev/null >out.txt 2>&1 || fail "run failed:"
grep -qF '"encoders[0].offset_deg=5"' o/summary.json ||
  fail "summary.json does not record the override 'encoders[0].offset_deg=5'"
grep -qF '{joints: [arms], offset_deg: 5}' o/summary.json ||
  fail "the resolved scenario in summary.json lacks '{joints: [arms], offset_deg: 5}'"
bias=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "left_arm_joint_1_true_bias_rad") c = i }
  NR == 2 { print $c }' o/timeseries.csv)
awk -v b="$bias" 'BEGIN { exit !(b + 0 > 0.0872664 && b + 0 < 0.0872665) }' ||
  fail "true bias of left_arm_joint_1 is '$bias' rad, not 5 degrees (0.0872665)"
exit 0
