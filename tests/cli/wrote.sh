#!/bin/sh
# wrote.sh ARTTRACK: `arttrack run`'s closing line names every file the run
# wrote: each file in its output folder by path, each subfolder with the
# number of files in it ("o/frames/ (4 files)").
arttrack=$1
dir=$(mktemp -d) || exit 1
trap 'rm -rf "$dir"' EXIT
cd "$dir" || exit 1
timeout 120 "$arttrack" run --runs 1 --methods encoders_only --set duration_s=1 --out o \
  </dev/null >out.txt 2>&1 || { echo "run failed:"; cat out.txt; exit 1; }
line=$(grep '^wrote ' out.txt)
[ -n "$line" ] || { echo "no closing line 'wrote ...':"; cat out.txt; exit 1; }
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
    *) echo "the closing line does not name $named: $line"; exit 1 ;;
  esac
done
exit 0
