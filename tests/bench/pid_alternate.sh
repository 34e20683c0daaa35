#!/bin/bash
# Two or more fluid builds on the run of pid.sh (pid_run.sh), single runs alternated build by build, so that
# the host's drift (1.3x over minutes on these machines) falls on every build alike; prints each run's wall
# and each build's median wall and PID.
# Usage: tests/bench/pid_alternate.sh THREADS RUNS BUILD_DIR [BUILD_DIR ...]
#        (200 x 200 cells to t = 0.05; one thread on CPU 0, two on CPUs 0 and 1 when taskset is there)
set -euo pipefail
threads=$1 runs=$2
shift 2
n=200 t_end=0.05
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
pin=false
if command -v taskset > /dev/null && [ "$(nproc)" -ge 2 ]; then pin=true; fi
cpus=0
[ "$threads" = 2 ] && cpus=0,1
source "$(dirname "$0")/pid_run.sh"
declare -A walls steps
for r in $(seq "$runs"); do
    for build in "$@"; do
        read -r s w < <(one_run "$threads" "$cpus" a)
        echo "run $r $build: $s steps, wall $w s"
        walls[$build]+="$w " steps[$build]=$s
    done
done
for build in "$@"; do
    m=$(tr ' ' '\n' <<< "${walls[$build]}" | grep . | median)
    pid=$(awk -v w="$m" -v t="$threads" -v n="$n" -v s="${steps[$build]}" \
        'BEGIN { printf "%.3e", w * t / (n * n * 6 * 3 * s) }')
    echo "$build: $threads thread(s), median wall $m s, PID $pid s"
done
