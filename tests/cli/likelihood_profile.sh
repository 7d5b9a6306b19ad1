#!/bin/sh
# likelihood_profile.sh ARTTRACK PROFILE SCENARIO: tools/likelihood_profile
# on a dataset exported from SCENARIO and a run of the same seed. The
# encoders-only estimate (its bias uncorrected, the camera at its nominal
# pose) must be far less likely than the truth, full fusion's much more
# likely than that; every column is 0 at the truth; a series without the
# run asked for is an error naming it, a time that is not a number a usage
# error.
arttrack=$1
profile=$2
scenario=$3
. "$(dirname "$0")/common.sh"

sets="--seed 5 --set duration_s=2 --set camera.width=160 --set camera.height=120"
# shellcheck disable=SC2086
timeout 300 "$arttrack" export "$scenario" $sets --out d </dev/null >out.txt 2>&1 ||
  fail "export failed:"
# shellcheck disable=SC2086
timeout 300 "$arttrack" run "$scenario" $sets --runs 1 --methods encoders_only,full_fusion \
  --out r </dev/null >out.txt 2>&1 || fail "run failed:"

# The "every DOF" column at alpha = ALPHA of a profile's output.
at() { awk -v a="$2" '$1 == a && NF == 4 { print $2 }' "$1"; }
for m in encoders_only full_fusion; do
  "$profile" d --series r/timeseries.csv --time 1.5 --method $m >$m.txt 2>out.txt ||
    fail "likelihood_profile --method $m failed:"
  grep -Eq '^ +0\.00 +0\.00 +0\.00 +0\.00$' $m.txt || { cp $m.txt out.txt; fail "$m: not 0 at the truth:"; }
  grep -q '^right_hand ' $m.txt || { cp $m.txt out.txt; fail "$m: no row for the right hand:"; }
done
enc=$(at encoders_only.txt 1.00) ff=$(at full_fusion.txt 1.00)
awk -v e="$enc" -v f="$ff" 'BEGIN { exit !(e < -1000 && f > e + 1000) }' ||
  fail "at the estimate: encoders only $enc, full fusion $ff nats against the truth"

"$profile" d --series r/timeseries.csv --time 1.5 --run 3 >out.txt 2>&1 &&
  fail "run 3 of a one-run series exited 0"
grep -q "no row of run 3" out.txt || fail "run 3: no message naming it:"
"$profile" d --series r/timeseries.csv --time nan >out.txt 2>&1
[ $? = 2 ] || fail "--time nan: not a usage error (exit 2):"
grep -q "time nan is not a number of seconds" out.txt || fail "--time nan: no message naming it:"
exit 0
