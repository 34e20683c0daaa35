#!/bin/bash
# Performance index of the fluid solver on the 2D Riemann problem (cases/riemann_2d.case, degree 2, the WENO
# limiter on the cells the TVB indicator marks, every cell solved: pinned, so that the figure stays
# comparable whatever the case file's defaults): PID = wall time × threads / (cells × basis functions × RK
# stages × steps).
# Usage: tests/bench/pid.sh [BUILD_DIR] [CELLS_PER_SIDE] [END_TIME] [RUNS]
# Prints the median over RUNS runs for 1 and 2 threads.
set -euo pipefail
build=${1:-build}
n=${2:-200}
t_end=${3:-0.1}
runs=${4:-5}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for threads in 1 2; do
    pids=()
    for r in $(seq "$runs"); do
        log=$("$build/bin/undex-fluid" cases/riemann_2d.case --set domain.cells_x="$n" --set domain.cells_y="$n" \
              --set end_time="$t_end" --set output.times[0]="$t_end" --set numerics.threads="$threads" \
              --set output.directory="$out/run" --set output.progress_seconds=1000 \
              --set numerics.limiter=weno --set numerics.indicator=tvb --set numerics.skip_rest=false)
        steps=$(echo "$log" | sed -n 's/.*done: \([0-9]*\) steps, wall \([0-9.]*\) s.*/\1/p')
        wall=$(echo "$log" | sed -n 's/.*done: \([0-9]*\) steps, wall \([0-9.]*\) s.*/\2/p')
        pid=$(awk -v w="$wall" -v t="$threads" -v n="$n" -v s="$steps" 'BEGIN { printf "%.3e", w * t / (n * n * 6 * 3 * s) }')
        echo "threads $threads run $r: $steps steps, wall $wall s, PID $pid s"
        pids+=("$pid")
    done
    median=$(printf '%s\n' "${pids[@]}" | sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }')
    echo "threads $threads: median PID $median s (${n}x${n} cells, degree 2, WENO limiter, TVB indicator)"
done
