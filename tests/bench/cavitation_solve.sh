#!/bin/bash
# Cost of one mixture pressure solve p(ρ) of the cavitation model (tests/bench/cavitation_solve.cpp), median
# of RUNS runs, with this tree's fluid/cavitation.hpp and, if REV is given, with that commit's (the same
# program and compiler for both, -O3 -march=native as the Release build, without its -ffp-contract=off).
# Usage: tests/bench/cavitation_solve.sh [RUNS] [REV]
#   e.g. tests/bench/cavitation_solve.sh 5 f47085b     (against the Newton solve before the closed-form start)
set -euo pipefail
runs=${1:-5}
rev=${2:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bench() { # label include_dir
    g++ -std=c++20 -O3 -march=native -I"$2" tests/bench/cavitation_solve.cpp -o "$tmp/bench"
    local times=()
    for r in $(seq "$runs"); do
        line=$("$tmp/bench")
        echo "$1 run $r: $line"
        times+=("${line%% ns*}")
    done
    echo "$1: median $(printf '%s\n' "${times[@]}" | sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }') ns per solve"
}
bench "this tree" .
if [ -n "$rev" ]; then
    mkdir -p "$tmp/old/fluid"
    git show "$rev:fluid/cavitation.hpp" > "$tmp/old/fluid/cavitation.hpp"
    bench "$rev" "$tmp/old"
fi
