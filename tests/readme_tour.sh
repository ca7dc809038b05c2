#!/usr/bin/env bash
# Runs the README's quick tour (the sh block between <!-- tour:begin --> and <!-- tour:end -->)
# as written, line by line, in a scratch folder whose scenes/ is the repository's: every
# command must exit 0 and each render must leave its image. `B=build/release` becomes the build
# folder under test (the first argument), so a sanitizer or portable build checks its own foton.
# Usage: tests/readme_tour.sh BUILD_DIR [SOURCE_DIR]
set -euo pipefail
bin=$(cd "$1" && pwd)
src=$(cd "${2:-$(dirname "$0")/..}" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
ln -s "$src/scenes" "$work/scenes"
block=$(sed -n '/<!-- tour:begin -->/,/<!-- tour:end -->/p' "$src/README.md" |
  sed -n '/^```sh$/,/^```$/p' | sed '1d;$d')
[ -n "$block" ] || { echo "readme_tour: no tour block in $src/README.md" >&2; exit 1; }
cd "$work"
n=0
while IFS= read -r line; do
  [ -n "$line" ] || continue
  if [ "$line" = "B=build/release" ]; then
    B=$bin
    continue
  fi
  n=$((n + 1))
  cmd=${line%%#*}  # the comment after a command is for the reader
  start=$(date +%s%N)
  if ! eval "$cmd" >"$work/log" 2>&1; then
    echo "readme_tour: failed: $line" >&2
    cat "$work/log" >&2
    exit 1
  fi
  # Every -o FILE (and a plain render's default out/<scene>.exr) must exist afterwards.
  out=$(sed -n 's/.* -o \([^ ]*\).*/\1/p' <<<"$cmd")
  if [ -n "$out" ] && [ ! -s "$out" ]; then
    echo "readme_tour: $line: wrote no $out" >&2
    exit 1
  fi
  ms=$((($(date +%s%N) - start) / 1000000))  # bash arithmetic: no bc on a fresh machine
  printf 'readme_tour: %4d.%01d s  %s\n' $((ms / 1000)) $((ms % 1000 / 100)) "$cmd"
done <<<"$block"
[ -s out/cornell-box.exr ] || { echo "readme_tour: no out/cornell-box.exr" >&2; exit 1; }
echo "readme_tour: $n commands ran"
