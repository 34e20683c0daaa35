#!/bin/bash
# Two or more fluid builds on the run of pid.sh (cases/riemann_2d.case, degree 2, the WENO limiter on the
# cells the TVB indicator marks, every cell solved), single runs alternated build by build, so that the
# host's drift (1.3x over minutes on these machines) falls on every build alike; prints each run's wall and
# each build's median wall and PID.
# Usage: tests/bench/pid_alternate.sh THREADS RUNS BUILD_DIR [BUILD_DIR ...]
#        (200 x 200 cells to t = 0.05; one thread on CPU 0, two on CPUs 0 and 1 when taskset is there)
set -euo pipefail
threads=$1 runs=$2
shift 2
n=200 t_end=0.05
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
pin=()
if command -v taskset > /dev/null && [ "$(nproc)" -ge 2 ]; then
    pin=(taskset -c 0)
    [ "$threads" = 2 ] && pin=(taskset -c 0,1)
fi
declare -A walls steps
for r in $(seq "$runs"); do
    for b in "$@"; do
        read -r s w < <("${pin[@]}" "$b/bin/undex-fluid" cases/riemann_2d.case --set domain.cells_x="$n" \
            --set domain.cells_y="$n" --set end_time="$t_end" --set output.times[0]="$t_end" \
            --set numerics.threads="$threads" --set output.directory="$out/run" \
            --set output.progress_seconds=1000 --set numerics.limiter=weno --set numerics.indicator=tvb \
            --set numerics.skip_rest=false --force |
            sed -n 's/.*done: \([0-9]*\) steps, wall \([0-9.]*\) s.*/\1 \2/p')
        echo "run $r $b: $s steps, wall $w s"
        walls[$b]+="$w " steps[$b]=$s
    done
done
for b in "$@"; do
    m=$(tr ' ' '\n' <<< "${walls[$b]}" | grep . | sort -g |
        awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }')
    pid=$(awk -v w="$m" -v t="$threads" -v n="$n" -v s="${steps[$b]}" \
        'BEGIN { printf "%.3e", w * t / (n * n * 6 * 3 * s) }')
    echo "$b: $threads thread(s), median wall $m s, PID $pid s"
done
