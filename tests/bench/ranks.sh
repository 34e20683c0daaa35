#!/bin/bash
# Strong scaling of the fluid on MPI ranks (docs/scale_out.md): a case at n × n cells to t_end on
#   1 rank × 1 thread, 2 ranks × 1 thread, 1 rank × 2 threads,
# alternated, `runs` times each; prints each run's wall time (the fluid's own "done" line: the run loop,
# without MPI's start-up), the medians, the ratios against one rank and the load of the host before each
# run (the figure counts only on an otherwise idle machine), and per round the host's own two-core ceiling:
# a fixed CPU-bound loop alone and two copies at once (this VM's second core has phases in which it gives far
# less than a core; a speed-up is read against that ceiling). Every run's fields are compared with the first
# one-rank run's, bit for bit (the scaling of a wrong answer is worth nothing).
#   bash tests/bench/ranks.sh [BUILD] [CASE] [n | NXxNY] [t_end] [runs] [--set ...]
# Defaults: build, cases/riemann_2d.case, 400, 0.02, 3. A case with a structure runs coupled (undex run
# --ranks), the fluid's wall time counted.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build} case=${2:-cases/riemann_2d.case} n=${3:-400} t_end=${4:-0.02} runs=${5:-3}
shift $(( $# < 5 ? $# : 5 ))
extra=("$@")
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
root=()
[ "$(id -u)" -eq 0 ] && root=(--allow-run-as-root)
nx=${n%x*} ny=${n#*x} # n or NXxNY cells
one() { # RANKS THREADS TAG: prints the fluid's wall time
    local sets=(--set domain.cells_x="$nx" --set domain.cells_y="$ny" --set end_time="$t_end"
                --set output.times[0]="$t_end" --set numerics.threads="$2" --set output.progress_seconds=1000
                "${extra[@]}")
    local cmd=("$build/bin/undex-fluid" "$case" --set output.directory="$out/$3" "${sets[@]}")
    # A case with a structure: both sides through undex run (the fluid's ranks under mpirun).
    if grep -q '^structure' "$case"; then
        cmd=("$build/bin/undex" run "$case" -o "$out/$3" --ranks "$1" "${sets[@]}")
    elif [ "$1" -gt 1 ]; then cmd=(mpirun "${root[@]}" -n "$1" "${cmd[@]}"); fi
    if [ "$2" -gt 1 ]; then cmd=(env OMP_PROC_BIND=false "${cmd[@]}"); fi
    "${cmd[@]}" | sed -n 's/.*undex-fluid: done: \([0-9]*\) steps, wall \([0-9.]*\) s.*/\2/p'
}
ceiling() { # the work of two copies of a CPU-bound loop run at once over the work of one, in the same time
    local spin='import time
t = time.time()
s = 0
for i in range(20_000_000): s += i
print(time.time() - t)'
    local one two
    one=$(/usr/bin/python3 -c "$spin")
    two=$( (/usr/bin/python3 -c "$spin" & /usr/bin/python3 -c "$spin"; wait) | sort -g | tail -1)
    awk -v a="$one" -v b="$two" 'BEGIN { printf "%.2f", 2 * a / b }'
}
declare -A wall
for k in $(seq "$runs"); do
    echo "round $k: host ceiling $(ceiling)x (two CPU-bound loops at once against one)"
    for config in "1 1" "2 1" "1 2"; do
        set -- $config
        load=$(cut -d' ' -f1 /proc/loadavg)
        w=$(one "$1" "$2" "r$1t$2k$k")
        wall["$1 $2"]+="$w "
        echo "run $k: $1 rank(s) x $2 thread(s): $w s (load before $load)"
        /usr/bin/python3 - "$out/r1t1k1/fluid.h5" "$out/r$1t$2k$k/fluid.h5" <<'PY'
import sys, h5py, numpy as np
a, b = h5py.File(sys.argv[1], "r"), h5py.File(sys.argv[2], "r")
g = sorted(a["fields"])[-1]
for k in a["fields"][g]:
    if not np.array_equal(a["fields"][g][k][()], b["fields"][g][k][()]):
        sys.exit("fields/%s/%s differ from the first one-rank run" % (g, k))
PY
    done
done
median() { tr ' ' '\n' | grep . | sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
m11=$(echo "${wall["1 1"]}" | median) m21=$(echo "${wall["2 1"]}" | median) m12=$(echo "${wall["1 2"]}" | median)
echo "medians: 1x1 $m11 s, 2 ranks x 1 thread $m21 s, 1 rank x 2 threads $m12 s"
awk -v a="$m11" -v b="$m21" -v c="$m12" \
    'BEGIN { printf "speed-up against 1x1: 2 ranks %.2fx, 2 threads %.2fx; ranks against threads %.3f\n", a / b, a / c, c / b }'
