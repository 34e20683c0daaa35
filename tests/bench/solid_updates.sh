#!/bin/bash
# Element updates per second of the structure solver on the axisymmetric sandwich plate of the paper's
# case 5 (cases/sandwich_plate_axisymmetric.case: 0.01 m elements, 500 x 21 quadrilaterals, Johnson-Cook
# faces, Deshpande-Fleck foam core), run on its own under its prescribed pressure to 3.2 ms.
# One update is one element's stress update and force evaluation in one step; the wall time is that of the
# whole run, output (9 snapshots, gauges every 10 steps) included.
# Usage: tests/bench/solid_updates.sh [BUILD_DIR] [RUNS]
# Prints every run and the median over RUNS runs for 1 and 2 threads.
set -euo pipefail
build=${1:-build}
runs=${2:-5}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for threads in 1 2; do
    rates=()
    for r in $(seq "$runs"); do
        log=$("$build/bin/undex-solid" cases/sandwich_plate_axisymmetric.case --set structure.threads="$threads" \
              --set output.directory="$out/run" --set output.progress_seconds=1000)
        elements=$(echo "$log" | sed -n 's/.*plate, \([0-9]*\) x \([0-9]*\) elements.*/\1 \2/p' | awk '{ print $1 * $2 }')
        steps=$(echo "$log" | sed -n 's/.*done: \([0-9]*\) steps, wall \([0-9.]*\) s.*/\1/p')
        wall=$(echo "$log" | sed -n 's/.*done: \([0-9]*\) steps, wall \([0-9.]*\) s.*/\2/p')
        rate=$(awk -v w="$wall" -v e="$elements" -v s="$steps" 'BEGIN { printf "%.3e", e * s / w }')
        echo "threads $threads run $r: $elements elements, $steps steps, wall $wall s, $rate element updates/s"
        rates+=("$rate")
    done
    median=$(printf '%s\n' "${rates[@]}" | sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }')
    echo "threads $threads: median $median element updates/s"
done
