#!/bin/sh
# check_pages.sh ARTTRACK SCREENSHOT_CHECK [DIR]: makes a tiny run report,
# sweep page and tuning page (0.6 s runs at 40x30, converged window from
# 0.3 s), opens each in headless Chromium (Debian's chromium), and fails if a
# page's DOM lacks its charts' axes, tick labels or legends, holds a NaN, or
# if its screenshot is blank (SCREENSHOT_CHECK: tests/pages/screenshot_check).
# Screenshots go to DIR if given (to look at), else to a temporary folder
# removed at exit; never into the repository. About 20 s on an idle machine.
set -u
# Absolute paths: the script works in a temporary folder.
absolute() { echo "$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"; }
arttrack=$(absolute "$1")
check=$(absolute "$2")
keep=${3:-}
src=$(cd "$(dirname "$0")/.." && pwd)
dir=$(mktemp -d) || exit 1
trap 'rm -rf "$dir"' EXIT
cd "$dir" || exit 1
shots=$dir/shots
if [ -n "$keep" ]; then
  mkdir -p "$keep" && shots=$(cd "$keep" && pwd) || exit 1
fi
mkdir -p "$shots"

fail() {
  echo "check_pages: $*"
  exit 1
}

small="--set duration_s=0.6 --set camera.width=40 --set camera.height=30
  --set scoring.converged_after_s=0.3"
scenario=$src/scenarios/default.yaml
# shellcheck disable=SC2086
timeout 120 "$arttrack" run "$scenario" --runs 1 --methods encoders_only,full_fusion $small \
  --out run </dev/null >run.log 2>&1 || { cat run.log; fail "arttrack run failed"; }
# shellcheck disable=SC2086
timeout 120 "$arttrack" sweep "$scenario" --grid 'encoders[0].offset_deg=0,5' \
  --grid camera.latency_s=0,0.05 --runs 1 --methods full_fusion $small \
  --out sweep </dev/null >sweep.log 2>&1 || { cat sweep.log; fail "arttrack sweep failed"; }
# shellcheck disable=SC2086
timeout 120 "$arttrack" tune "$scenario" --params particle_filter.bandwidth_factor=0.5:1.5 \
  --tracker-method full_fusion --budget 2 --runs 1 $small \
  --out tune </dev/null >tune.log 2>&1 || { cat tune.log; fail "arttrack tune failed"; }

browser() {
  timeout 60 chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
    --disable-background-networking --disable-component-update --disable-sync \
    --disable-dev-shm-usage --user-data-dir="$(mktemp -d -p "$dir")" "$@" 2>>chromium.log
}

# page NAME HTML WIDTH,HEIGHT MIN_COLOURFUL_PERCENT: NAME.dom and the
# screenshot NAME.png; no NaN, no non-finite number, not blank.
page() {
  [ -s "$2" ] || fail "$1: $2 was not written"
  browser --dump-dom "file://$2" >"$1.dom" || fail "$1: chromium --dump-dom failed (chromium.log)"
  grep -q '</svg>' "$1.dom" || fail "$1: no SVG in the DOM Chromium built"
  browser --screenshot="$shots/$1.png" --window-size="$3" "file://$2" >/dev/null ||
    fail "$1: chromium --screenshot failed"
  "$check" "$shots/$1.png" "$4" || fail "$1: the screenshot shows no page"
  ! grep -q 'NaN\|Infinity\|undefined' "$1.dom" || fail "$1: NaN, Infinity or undefined in the page"
  ! grep -Eq '="-?(nan|inf)' "$1.dom" || fail "$1: a non-finite number in an SVG attribute"
}

# chart NAME ID: the <svg> element of the page whose data-chart is ID.
chart() {
  awk -v id="data-chart=\"$2\"" 'index($0, id) { on = 1 } on { print } on && /<\/svg>/ { exit }' \
    "$1.dom"
}

# has NAME ID TEXT...: the chart holds each TEXT (fixed strings).
has() {
  name=$1
  id=$2
  shift 2
  svg=$(chart "$name" "$id")
  [ -n "$svg" ] || fail "$name: no chart '$id'"
  for t in "$@"; do
    printf '%s' "$svg" | grep -qF -- "$t" || fail "$name: chart '$id' lacks '$t'"
  done
}

# ticks NAME ID N: the chart has at least N tick labels.
ticks() {
  n=$(chart "$1" "$2" | grep -o 'class="tl"' | wc -l)
  [ "$n" -ge "$3" ] || fail "$1: chart '$2' has $n tick labels, fewer than $3"
}

page report "$dir/run/report.html" 1280,2400 0.2
grep -qF '<h2>Verdict</h2>' report.dom || fail "report: no verdict"
for id in box-translation-all box-translation-converged box-rotation-all error-time; do
  ticks report "$id" 4
done
has report error-time '>time, s</text>' '>translation error, mm' '>encoders_only</text>' \
  '>full_fusion</text>' '>0.0</text>' '>0.5</text>'
has report bias-legend '>true bias</text>' 'stroke-dasharray'
has report bias-left_arm_joint_1 'stroke="#000"' 'stroke-dasharray' '>bias, deg</text>'
has report camera-legend '>true offset</text>' '>full_fusion</text>'
has report camera-x '>offset, mm</text>' 'stroke="#000"'
has report colours-0 '>depth, m (black: no return)</text>'
ticks report colours-0 3

page sweep "$dir/sweep/sweep.html" 1280,1600 0.5
n=$(grep -o 'class="heat"' sweep.dom | wc -l)
[ "$n" -ge 21 ] || fail "sweep: $n heat maps, fewer than one per statistic"
has sweep p50_translation_m-full_fusion-0 '>encoders[0].offset_deg</text>' \
  '>camera.latency_s</text>' 'class="hv"' 'class="hk"'
has sweep cell-key '>method fails</text>' '>run failed</text>'
has sweep colours-p50_translation_m '>p50_translation_m, mm'
ticks sweep colours-p50_translation_m 2

page tuning "$dir/tune/tuning.html" 1100,1400 0.2
has tuning search '>evaluation</text>' '>objective, mm</text>' '>1</text>' '>2</text>' \
  '>best so far</text>'
ticks tuning search 5
has tuning bars-0 '>default</text>' '>tuned</text>' '>translation error, mm</text>'
! grep -q 'class="n \(better\|worse\)">[^<]*(wall time)' tuning.dom ||
  fail "tuning: a wall time marked better or worse"
grep -qF '(wall time)' tuning.dom || fail "tuning: the image update time is not marked a wall time"

echo "check_pages: the run report, sweep and tuning pages render in Chromium with their charts" \
  "(screenshots: $shots)"
exit 0
