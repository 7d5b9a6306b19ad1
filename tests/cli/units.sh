#!/bin/sh
# units.sh ARTTRACK SCENARIO: sweep's --fail-threshold-m is in metres and
# its table and page show mm: --help says so, and a brief sweep (one cell,
# 1 s) with --fail-threshold-m 0.2 names "200 mm" and the flag's value in
# metres on stdout and in sweep.html.
arttrack=$1
scenario=$2
. "$(dirname "$0")/common.sh"
"$arttrack" sweep --help >out.txt 2>&1 || fail "sweep --help failed:"
grep -Eq -- "--fail-threshold-m .*in metres .*50 mm" out.txt ||
  fail "sweep --help does not give --fail-threshold-m's unit:"
timeout 120 "$arttrack" sweep "$scenario" --grid scoring.converged_after_s=0.5 --runs 1 \
  --methods encoders_only --set duration_s=1 --set camera.width=80 --set camera.height=60 \
  --fail-statistic p50_translation_m --fail-threshold-m 0.2 --out o </dev/null >out.txt 2>&1 ||
  fail "sweep failed:"
grep -q -- "p50_translation_m in mm (\* = above 200 mm: --fail-threshold-m 0.2, in m)" out.txt ||
  fail "the table does not give the threshold's units:"
grep -q -- "exceeds 200 mm (<code>--fail-threshold-m 0.2</code>, in m)" o/sweep.html ||
  fail "sweep.html does not give the threshold's units"
exit 0
