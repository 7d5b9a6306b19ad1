# common.sh, sourced by the CLI test scripts: the rest of the script runs in
# a fresh temporary folder, removed at exit; `fail MESSAGE` prints MESSAGE
# and out.txt (where the scripts keep a command's output) and exits 1.
dir=$(mktemp -d) || exit 1
trap 'rm -rf "$dir"' EXIT
cd "$dir" || exit 1
fail() {
  echo "$*"
  cat out.txt 2>/dev/null
  exit 1
}
