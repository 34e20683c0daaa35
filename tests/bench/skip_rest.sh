#!/bin/bash
# Still water skipped (numerics.skip_rest) against every cell solved: the fluid's wall time (median of RUNS
# runs of each, the two settings alternating so that both see the same machine load), the fraction of cell
# updates skipped and the speed-up, for one case file with any --set options after it.
# Usage: tests/bench/skip_rest.sh BIN_DIR RUNS CASE [--set ...]
#   tests/bench/skip_rest.sh build/bin 3 cases/free_field_2d.case                       (case 4.4, 400 x 400)
#   tests/bench/skip_rest.sh build/bin 3 cases/undex_steel_plate.case --set domain.cells_x=125 \
#       --set domain.cells_y=300 --set numerics.threads=2 --set structure.threads=1   (the application, 0.04 m)
set -euo pipefail
bin=$1 runs=$2 case=$3
shift 3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for r in $(seq "$runs"); do
    for skip in true false; do
        "$bin/undex" run "$case" "$@" --set numerics.skip_rest=$skip -o "$tmp/run" --force > "$tmp/log" 2>&1
        line=$(grep 'undex-fluid: done:' "$tmp/log")
        wall=$(echo "$line" | sed -E 's/.*wall ([0-9.]+) s.*/\1/')
        skipped=$(echo "$line" | grep -oE '[0-9.]+ % of [0-9.e+]+ cell updates skipped' | awk '{ print $1 }' || true)
        echo "run $r, skip_rest $skip: fluid wall $wall s${skipped:+, $skipped % of the cell updates skipped}"
        echo "$skip $wall" >> "$tmp/walls"
    done
done
median() { sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
on=$(awk '$1 == "true" { print $2 }' "$tmp/walls" | median)
off=$(awk '$1 == "false" { print $2 }' "$tmp/walls" | median)
echo "median fluid wall: $on s skipping, $off s solving every cell: $(awk -v a="$off" -v b="$on" 'BEGIN { printf "%.2f", a / b }')x"
