#!/bin/sh
# rerun.sh ARTTRACK: a short run, `arttrack rerun` of its folder, and the two
# timeseries.csv compared byte for byte; another run into the same folder is
# a usage error (exit 2) naming --force, and goes through with --force.
arttrack=$1
dir=$(mktemp -d) || exit 1
trap 'rm -rf "$dir"' EXIT
cd "$dir" || exit 1
run() { timeout 120 "$arttrack" "$@" </dev/null >out.txt 2>&1; }
run run --runs 1 --methods full_fusion --set duration_s=1 --out first ||
  { echo "run failed:"; cat out.txt; exit 1; }
run rerun first --out again || { echo "rerun failed:"; cat out.txt; exit 1; }
cmp first/timeseries.csv again/timeseries.csv || exit 1
run run --runs 1 --methods encoders_only --set duration_s=1 --out first
got=$?
if [ "$got" -ne 2 ] || ! grep -q -- "--force" out.txt; then
  echo "a second run into first/: expected exit 2 naming --force, got $got:"
  cat out.txt
  exit 1
fi
cmp first/timeseries.csv again/timeseries.csv || { echo "first/ was changed"; exit 1; }
run rerun first --out again --force || { echo "rerun --force failed:"; cat out.txt; exit 1; }
cmp first/timeseries.csv again/timeseries.csv || exit 1
exit 0
