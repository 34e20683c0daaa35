#!/bin/bash
# Cost of a cavitating cell against a plain one, per cell-step (issue 17 item 2): two columns of 20 000 cells
# of water at rest, every cell solved (skip_rest off), one thread, degree DEGREE: one in the cavitating
# mixture (ρ = 999.9 kg/m³, below the saturated mixture's 999.949: p = 200.4 Pa, void fraction 5.8e-5), one
# in plain water (ρ = 1000, p = 1e5 Pa). Each column's cost per cell-step is the difference of the wall times
# of runs of 150 and 50 steps over 100 steps × 20 000 cells (start-up and output cancel); median of RUNS
# runs, the two columns alternating.
# Usage: tests/bench/cavitation_cost.sh BIN_DIR [RUNS] [DEGREE]
set -euo pipefail
bin=$1 runs=${2:-3} degree=${3:-1}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
column() { # NAME RHO P STEPS
    cat > "$tmp/$1.case" <<CASE
name: "$1" geometry: PLANAR_1D
domain { x_min: 0 x_max: 1 cells_x: 20000 }
materials { name: "water" tait { gamma: 7.15 B: 3.31e8 A: 1e5 rho0: 1000 } }
regions { material: "water" rho: $2 p: $3 }
boundaries { x_min { type: WALL } x_max { type: WALL } }
cavitation { enabled: true }
numerics { degree: $degree cfl: 0.2 skip_rest: false threads: 1 max_steps: $4 }
end_time: 1
output { times: [] }
CASE
}
wall() { # CASE: seconds of a run stopped by max_steps
    local t0 t1
    t0=$(date +%s.%N)
    "$bin/undex-fluid" "$1" -o "$tmp/out" > /dev/null 2>&1 || true
    t1=$(date +%s.%N)
    echo "$t1 - $t0" | bc -l
}
median() { sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
# The mixture's p(ρ) at 999.9 is below p_cav; the case check compares p with pure Tait (ρ < ρ_l,cav there),
# so the region gives Tait's value, which the mixture branch replaces.
for n in 50 150; do
    column mixture_$n 999.9 -136592.238 $n
    column plain_$n 1000 1e5 $n
done
for r in $(seq "$runs"); do
    for kind in mixture plain; do
        a=$(wall "$tmp/${kind}_50.case")
        b=$(wall "$tmp/${kind}_150.case")
        c=$(echo "($b - $a) / (100 * 20000) * 1000000000" | bc -l)
        printf '%s run %s: %.1f ns per cell-step\n' "$kind" "$r" "$c"
        echo "$kind $c" >> "$tmp/costs"
    done
done
m=$(awk '$1 == "mixture" { print $2 }' "$tmp/costs" | median)
p=$(awk '$1 == "plain" { print $2 }' "$tmp/costs" | median)
printf 'degree %s: cavitating %.1f ns, plain %.1f ns per cell-step: %.2fx\n' "$degree" "$m" "$p" "$(echo "$m / $p" | bc -l)"
