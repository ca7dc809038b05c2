#!/usr/bin/env bash
# Runs every command of the docs' sh blocks (docs/*.md; the README's tour has readme_tour.sh)
# the way a reader would type it, made small: the sizes, sample counts, times and photon counts
# a command names are cut down (64 x 64 pixels, 1 sample, 0.3 s, ...) and nothing else is
# changed, so a renamed flag, a removed scene or a changed output path fails here. The scratch
# folder has the repository's scenes/ and ../shared beside it, as a clone has.
#
# What cannot run on one machine in a test is said, not hidden: a line needing a cluster's
# hostfile or the tev viewer is listed as skipped with the reason; bench/ scripts (benchmarks
# of minutes) are run with --help, which checks that they exist and parse their options.
# `foton serve` is started, asked for its page, and stopped.
# Usage: tests/docs_commands.sh BUILD_DIR [SOURCE_DIR [MPI]]  (MPI: ON when foton has MPI)
set -euo pipefail
bin=$(cd "$1" && pwd)
src=$(cd "${2:-$(dirname "$0")/..}" && pwd)
has_mpi=0
[[ ${3:-OFF} =~ ^(ON|on|1|TRUE|true|YES|yes)$ ]] && command -v mpirun >/dev/null && has_mpi=1
shared=$(cd "$src/../shared" 2>/dev/null && pwd || true)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/clone"
ln -s "$src/scenes" "$work/clone/scenes"
[ -n "$shared" ] && ln -s "$shared" "$work/shared"

# The sh blocks of every docs page, continuation lines joined, comments and blanks dropped.
commands=$(for f in "$src"/docs/*.md; do
  awk '/^```sh$/{f=1;next} /^```$/{f=0} f' "$f"
done | sed -e ':a' -e '/\\$/N; s/\\\n[[:space:]]*/ /; ta' | sed 's/[[:space:]]#.*$//' |
  grep -v '^[[:space:]]*\(#\|$\)' || true)
[ -n "$commands" ] || { echo "docs_commands: no sh blocks in $src/docs" >&2; exit 1; }

# The small version of a command: numbers that set the work made small, a size added to
# renders that set none.
small() {
  local c=$1
  c=$(sed -E -e 's/--spp [0-9]+/--spp 1/g' -e 's/--time [0-9.]+/--time 0.3/g' \
    -e 's/--snapshots [0-9.]+/--snapshots 0.1/g' -e 's/--passes [0-9]+/--passes 2/g' \
    -e 's/--repeats [0-9]+/--repeats 1/g' -e 's/--adaptive-max [0-9]+/--adaptive-max 4/g' \
    -e 's/--threads 1,2,4,8/--threads 1,2/g' -e 's/(--width|--height) [0-9]+/\1 64/g' \
    -e 's/global_photons=[0-9]+/global_photons=20000/g' -e 's/-np [0-9]+/-np 2/g' <<<"$c")
  if [[ $c == *"foton render "* && $c != *"--width"* ]]; then c="$c --width 64 --height 64"; fi
  # A render that names no amount of work gets one sample per pixel: the scene's own count
  # (64 final-gathered samples of the photon map) took 16 s of this test per command.
  if [[ $c == *"foton render "* && ! $c =~ --(spp|time|passes|reference) ]]; then c="$c --spp 1"; fi
  if [[ $c == *"foton scale "* && $c != *"--width"* ]]; then c="$c --width 32 --height 32"; fi
  printf '%s' "$c"
}

cd "$work/clone"
B=$bin
ran=0
skipped=0
run() {  # run LINE COMMAND: the command must exit 0
  local start ms
  start=$(date +%s%N)
  if ! eval "$2" </dev/null >"$work/log" 2>&1; then
    echo "docs_commands: failed: $1" >&2
    echo "  ran: $2" >&2
    cat "$work/log" >&2
    exit 1
  fi
  ms=$((($(date +%s%N) - start) / 1000000))
  printf 'docs_commands: %4d.%01d s  %s\n' $((ms / 1000)) $((ms % 1000 / 100)) "$2"
  ran=$((ran + 1))
}
skip() {
  echo "docs_commands: skipped ($2): $1"
  skipped=$((skipped + 1))
}
while IFS= read -r line; do
  [ "$line" = "B=build/release" ] && continue
  cmd=$(small "$line")
  case "$line" in
    tev\ *) skip "$line" "the tev viewer is not installed by bootstrap" ;;
    *--hostfile*) skip "$line" "needs a cluster's nodes" ;;
    mpirun\ *)
      if [ $has_mpi = 1 ]; then
        run "$line" "$cmd"
      else
        skip "$line" "this build has no MPI"
      fi
      ;;
    bench/*) run "$line" "$src/${cmd%% *} --help" ;;
    *"foton serve"*)
      port=$((20000 + RANDOM % 20000))
      serve=${cmd//--port 8080/--port $port}
      eval "exec $serve" </dev/null >"$work/serve.log" 2>&1 &  # $! is foton itself
      pid=$!
      ok=0
      for _ in $(seq 50); do
        if curl -sf "http://127.0.0.1:$port/" -o "$work/page.html"; then ok=1; break; fi
        sleep 0.1
      done
      kill "$pid" 2>/dev/null || true
      wait "$pid" 2>/dev/null || true
      if [ $ok = 1 ] && grep -qi '<html' "$work/page.html"; then
        echo "docs_commands: served its page: $serve"
        ran=$((ran + 1))
      else
        echo "docs_commands: failed: $line (no page on port $port)" >&2
        cat "$work/serve.log" >&2
        exit 1
      fi
      ;;
    *../shared/*)
      if [ -n "$shared" ]; then run "$line" "$cmd"; else skip "$line" "no ../shared beside"; fi
      ;;
    *) run "$line" "$cmd" ;;
  esac
  # Every -o FILE the command names must exist afterwards.
  out=$(sed -n 's/.* -o \([^ ]*\).*/\1/p' <<<"$cmd")
  if [[ $line != bench/* && $line != tev* && $line != *--hostfile* && -n $out && ! -s $out ]]; then
    if [[ $line != mpirun* ]] || [ $has_mpi = 1 ]; then
      echo "docs_commands: $line: wrote no $out" >&2
      exit 1
    fi
  fi
done <<<"$commands"
echo "docs_commands: $ran commands ran, $skipped skipped"
