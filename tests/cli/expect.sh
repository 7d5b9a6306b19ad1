#!/bin/sh
# expect.sh CODE PATTERN PROGRAM ARGS...
# Runs PROGRAM ARGS in a fresh temporary folder (stdin empty, at most
# $EXPECT_TIMEOUT_S seconds, 60 unless set)
# and passes when it exits with CODE and its output (stdout and stderr)
# matches the extended regular expression PATTERN. An argument @EMPTY@ is
# passed as the empty string (CMake drops empty arguments).
code=$1 pattern=$2
shift 2
for arg; do
  shift
  [ "$arg" = @EMPTY@ ] && arg=
  set -- "$@" "$arg"
done
dir=$(mktemp -d) || exit 1
trap 'rm -rf "$dir"' EXIT
cd "$dir" || exit 1
timeout "${EXPECT_TIMEOUT_S:-60}" "$@" </dev/null >out.txt 2>&1
got=$?
if [ "$got" -ne "$code" ]; then
  echo "expected exit code $code, got $got; output:"
  cat out.txt
  exit 1
fi
if ! grep -Eq -- "$pattern" out.txt; then
  echo "output does not match '$pattern':"
  cat out.txt
  exit 1
fi
exit 0
