#!/bin/bash
# Cost of the paper's case 4.5 (cases/sandwich_plate_water_backed_2d.case) coupled at the paper's resolution
# (fluid 0.01 m: 200 x 232 cells of degree 1; structure 0.02 m: 100 x 15 elements; 6 000 steps of 5e-7 s),
# and where the time goes:
#   fluid      the fluid's wall time (undex-fluid's closing line), the run's length;
#   coupling   the fluid's time inside the coupling library (waiting for the Offer and the Answer);
#   structure  the structure's own steps (undex-solid's closing line), which the fluid waits for;
#   overhead   coupling − structure: messages, (de)serialisation and the wait itself, the coupling's own cost.
# Usage: tests/bench/sandwich_plate_2d.sh [BUILD_DIR] [RUNS] [extra --set ...]
# Prints every run and, per thread count (1 and 2, both sides), the medians over RUNS runs.
set -euo pipefail
build=${1:-build}
runs=${2:-3}
shift $(( $# > 2 ? 2 : $# ))
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for threads in 1 2; do
    rows=()
    for r in $(seq "$runs"); do
        "$build/bin/undex" run cases/sandwich_plate_water_backed_2d.case --set numerics.threads="$threads" \
            --set structure.threads="$threads" --set output.progress_seconds=1000 -o "$out/run" "$@" > /dev/null
        fluid=$(sed -n 's/.*undex-fluid: done: [0-9]* steps, wall \([0-9.]*\) s (coupling \([0-9.]*\) s.*/\1 \2/p' "$out/run/fluid.log")
        solid=$(sed -n 's/.*undex-solid: done: .*(structure steps \([0-9.]*\) s.*/\1/p' "$out/run/solid.log")
        row=$(echo "$fluid $solid" | awk '{ printf "%.2f %.2f %.2f %.2f %.2f", $1, $2, $3, $2 - $3, 100 * ($2 - $3) / $1 }')
        echo "threads $threads run $r: fluid wall, coupling, structure steps, overhead (s), overhead (% of wall): $row"
        rows+=("$row")
    done
    med() { printf '%s\n' "${rows[@]}" | cut -d' ' -f"$1" | sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
    echo "threads $threads: medians: fluid wall $(med 1) s, coupling $(med 2) s, structure steps $(med 3) s," \
         "overhead $(med 4) s ($(med 5) % of the wall)"
done
