#!/bin/sh
# wrote.sh ARTTRACK: `arttrack run`'s closing line names every file the run
# wrote: each file in its output folder by path, each subfolder with the
# number of files in it ("o/frames/ (4 files)").
arttrack=$1
. "$(dirname "$0")/common.sh"
timeout 120 "$arttrack" run --runs 1 --methods encoders_only --set duration_s=1 --out o \
  </dev/null >out.txt 2>&1 || fail "run failed:"
line=$(grep '^wrote ' out.txt)
[ -n "$line" ] || fail "no closing line 'wrote ...':"
for path in o/*; do
  if [ -d "$path" ]; then
    n=$(find "$path" -type f | wc -l)
    s=s
    [ "$n" -eq 1 ] && s=
    named="$path/ ($n file$s)"
  else
    named=$path
  fi
  case "$line" in
    *"$named"*) ;;
    *) fail "the closing line does not name $named:" ;;
  esac
done
exit 0
