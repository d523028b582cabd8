#!/usr/bin/env bash
# Prints the final state hash of every example experiment (and the small
# benchmark scenes), run for a fixed length: run it before and after a change
# that must not change results, and diff the two outputs.
#   tools/state_hashes.sh [BUILD_DIR] [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
seconds=${2:-20}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for file in experiments/*.xml experiments/benchmarks/*_100.xml experiments/benchmarks/dynamics3d_10.xml; do
  for threads in 1 2; do
    dir="$out/$(basename "$file" .xml)_$threads"
    "$build/bin/colony" run "$file" --quiet --threads "$threads" --out "$dir" \
      --set framework.experiment.length="$seconds" >/dev/null 2>"$dir.err" || { echo "$file: failed"; cat "$dir.err"; continue; }
    hash=$(sed -n 's/.*"final_state_hash": "\([0-9a-f]*\)".*/\1/p' "$dir/summary.json")
    printf '%-40s threads=%s %s\n' "$file" "$threads" "$hash"
  done
done
