#!/bin/bash
# Case 4.3 (cases/sandwich_shock_1d.case, as shipped, one fluid thread): steps, wall time (median of RUNS
# runs), the core's plastic compression strain at the end and the structure's energy balance error, with
# this build's executables and, if OTHER_BIN is given, with another build's (e.g. one made from an earlier
# commit), runs of the two alternating so that both see the same machine load.
# Usage: tests/bench/structure_step.sh [RUNS] [OTHER_BIN]
#   e.g. tests/bench/structure_step.sh 3 /tmp/old/build/bin
set -euo pipefail
runs=${1:-3}
other=${2:-}
here=$(cd "$(dirname "$0")/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bins=("$here/build/bin")
[ -n "$other" ] && bins+=("$other")
for r in $(seq "$runs"); do
    for k in "${!bins[@]}"; do
        out="$tmp/run_${k}_$r"
        "${bins[$k]}/undex" run "$here/cases/sandwich_shock_1d.case" --set numerics.threads=1 -o "$out" \
            --force > "$out.log" 2>&1
        wall=$(grep -o 'undex-fluid: done: [0-9]* steps, wall [0-9.]*' "$out.log" | awk '{ print $3, $6 }')
        balance=$(grep -o 'energy balance error [-0-9.e+]*' "$out.log" | tail -n 1 | awk '{ print $4 }')
        strain=$(/usr/bin/python3 -c "import sys; sys.path.insert(0, '$here/cases')
from plot_sandwich_shock import core_strain
print('%.5f' % core_strain('$out')[0])")
        echo "${bins[$k]} run $r: steps, wall $wall s; core strain $strain; energy balance error $balance"
        echo "$k $wall" >> "$tmp/walls"
    done
done
for k in "${!bins[@]}"; do
    med=$(awk -v k="$k" '$1 == k { print $3 }' "$tmp/walls" | sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }')
    echo "${bins[$k]}: median wall $med s over $runs runs"
done
