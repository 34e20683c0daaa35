#!/bin/bash
# Wall time per step of a coupled two-fluid 2D run: cases/undex_sandwich_plate.case (gas bubble in water, the
# sandwich plate, cavitation on) at fluid cells of 0.02 m (250 x 600 cells plus the layers) to END_TIME, the
# fluid on 1 and on 2 threads, the structure on one. The gas, the shock and later the cavitating water lie
# in some rows of the mesh only, so this measures how well the rows are shared between the threads, and the
# share of the step that runs on one thread (the interface treatment, the level set).
# Usage (from the source directory): tests/bench/two_fluid_step.sh [BIN_DIR] [END_TIME] [RUNS]
#   (default build/bin, 6e-5 s: about 70 steps, the shock still in the water; 3 runs)
# Prints each run's fluid wall time per step (from the fluid's closing line), the median per thread count and
# the ratio of the medians.
set -euo pipefail
bin=${1:-build/bin}
t_end=${2:-6e-5}
runs=${3:-3}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# The case's picture times lie after END_TIME: all moved to END_TIME.
times=()
for k in $(seq 0 8); do times+=(--set "output.times[$k]=$t_end"); done
declare -A median
for threads in 1 2; do
    per=()
    for r in $(seq "$runs"); do
        log=$("$bin/undex" run cases/undex_sandwich_plate.case --set domain.cells_x=250 --set domain.cells_y=600 \
              --set end_time="$t_end" --set numerics.threads="$threads" --set structure.threads=1 \
              --set output.checkpoint_seconds=0 --set output.progress_seconds=1000 "${times[@]}" \
              -o "$out/run" --force 2>&1) || { echo "$log" | tail -20; exit 1; }
        line=$(echo "$log" | grep "undex-fluid: done:" | tail -1 || true)
        steps=$(echo "$line" | sed -n 's/.*done: \([0-9]*\) steps, wall \([0-9.]*\) s.*/\1/p')
        wall=$(echo "$line" | sed -n 's/.*done: \([0-9]*\) steps, wall \([0-9.]*\) s.*/\2/p')
        [ -n "$steps" ] || { echo "$log" | tail -20; exit 1; }
        s=$(awk -v w="$wall" -v n="$steps" 'BEGIN { printf "%.4f", w / n }')
        echo "threads $threads run $r: $steps steps, fluid wall $wall s, $s s per step"
        per+=("$s")
    done
    median[$threads]=$(printf '%s\n' "${per[@]}" | sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }')
    echo "threads $threads: median ${median[$threads]} s per step"
done
awk -v a="${median[1]}" -v b="${median[2]}" 'BEGIN { printf "two threads: %.2fx one thread (ratio of the medians)\n", a / b }'
