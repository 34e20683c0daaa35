#!/bin/bash
# Performance index of the fluid solver on the 2D Riemann problem (cases/riemann_2d.case, degree 2, the WENO
# limiter on the cells the TVB indicator marks, every cell solved: pinned, so that the figure stays
# comparable whatever the case file's defaults): PID = wall time × threads / (cells × basis functions × RK
# stages × steps).
# Usage: tests/bench/pid.sh [BUILD_DIR] [CELLS_PER_SIDE] [END_TIME] [RUNS]
# Prints the median over RUNS runs for 1 and 2 threads (one thread on CPU 0, two on CPUs 0 and 1, when
# taskset and two CPUs are there), then what two CPUs can give at all on this machine: two one-thread runs
# at once, one on each CPU, RUNS times; their combined rate against one run alone on CPU 0 is the ceiling
# of the two-thread speed-up (below 2 when the CPUs share a core or memory bandwidth on the host).
set -euo pipefail
build=${1:-build}
n=${2:-200}
t_end=${3:-0.1}
runs=${4:-5}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
pin=false
if command -v taskset > /dev/null && [ "$(nproc)" -ge 2 ]; then pin=true; fi

source "$(dirname "$0")/pid_run.sh"

declare -A median_wall
for threads in 1 2; do
    cpus=0
    [ "$threads" = 2 ] && cpus=0,1
    pids=() walls=()
    for r in $(seq "$runs"); do
        read -r steps wall < <(one_run "$threads" "$cpus" a)
        pid=$(awk -v w="$wall" -v t="$threads" -v n="$n" -v s="$steps" 'BEGIN { printf "%.3e", w * t / (n * n * 6 * 3 * s) }')
        echo "threads $threads run $r: $steps steps, wall $wall s, PID $pid s"
        pids+=("$pid") walls+=("$wall")
    done
    median_wall[$threads]=$(printf '%s\n' "${walls[@]}" | median)
    echo "threads $threads: median PID $(printf '%s\n' "${pids[@]}" | median) s (${n}x${n} cells, degree 2, WENO limiter, TVB indicator)"
done
echo "2 threads against 1: $(awk -v a="${median_wall[1]}" -v b="${median_wall[2]}" 'BEGIN { printf "%.2f", a / b }')x (median walls)"

if $pin; then
    rates=()
    for r in $(seq "$runs"); do
        one_run 1 0 p0 > "$out/p0" &
        one_run 1 1 p1 > "$out/p1"
        wait
        read -r _ w0 < "$out/p0"
        read -r _ w1 < "$out/p1"
        rate=$(awk -v a="${median_wall[1]}" -v w0="$w0" -v w1="$w1" 'BEGIN { printf "%.2f", a / w0 + a / w1 }')
        echo "pair run $r: CPU 0 $w0 s, CPU 1 $w1 s at once: ${rate}x one run alone"
        rates+=("$rate")
    done
    echo "ceiling of 2 threads on this machine: median $(printf '%s\n' "${rates[@]}" | median)x (two 1-thread runs at once)"
fi
