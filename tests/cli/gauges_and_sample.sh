#!/usr/bin/env bash
# `undex gauges` and `undex sample` on a two-fluid run (case 4.1 on 100 cells, degree 1, two gauges):
#   - gauges: CSV with time first, one row per recorded step, times increasing up to the end time; a named
#     gauge alone; an unknown name is an error (exit 1, nothing on stdout);
#   - sample: a '# time' line, a header and N rows; points outside the wave fan hold the initial states
#     (gas 1630 kg/m^3, 7.81e9 Pa at x = 0.1; water 1000 kg/m^3, 1e5 Pa at x = 0.95), so the level set picked
#     the right material on each side (the two densities differ by 630 kg/m^3). Bounds: 0.1 kg/m^3 in ρ and
#     1e-5 of the water shock pressure (4e4 Pa) in p: the numerical domain of dependence of the scheme runs
#     ahead of the physical one, and measured deviations there are about 1e-7 of the jump.
#   usage: gauges_and_sample.sh UNDEX_BINARY CASES_DIR
set -u
UNDEX=$1
CASES=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
failed=0
check() { if eval "$2"; then echo "ok: $1"; else echo "FAIL: $1"; failed=1; fi; }

sed -e 's/^output {.*/output { directory: "OUTDIR" }\ngauges { name: "gas" x: 0.1 }\ngauges { name: "water" x: 0.95 }/' \
    -e "s|OUTDIR|$TMP/run|" "$CASES/undex_1d.case" > "$TMP/g.case"
"$UNDEX" run "$TMP/g.case" --set domain.cells_x=100 --set numerics.degree=1 > "$TMP/run.log" 2>&1
check "run completes" '[ $? -eq 0 ] && [ -f "$TMP/run/fluid.h5" ]'

"$UNDEX" gauges "$TMP/run" > "$TMP/all.csv" 2> "$TMP/err"
check "gauges: header names both gauges" 'head -n 1 "$TMP/all.csv" | grep -qx "t,gas.rho,gas.u,gas.v,gas.p,water.rho,water.u,water.v,water.p"'
check "gauges: times increase and end at 1e-4" 'awk -F, "NR > 2 && \$1 <= prev { bad = 1 } NR > 1 { prev = \$1 } END { exit bad || (prev < 0.99999e-4 || prev > 1.00001e-4) }" "$TMP/all.csv"'
"$UNDEX" gauges "$TMP/run" --name gas > "$TMP/gas.csv"
check "gauges --name: one gauge, initial gas state kept" 'head -n 1 "$TMP/gas.csv" | grep -qx "t,rho,u,v,p" && awk -F, "NR > 1 && (\$2 < 1629.9 || \$2 > 1630.1 || \$5 < 7.80996e9 || \$5 > 7.81004e9) { bad = 1 } END { exit bad }" "$TMP/gas.csv"'
"$UNDEX" gauges "$TMP/run" --name nosuch > "$TMP/none.csv" 2> "$TMP/err"
rc=$?
check "gauges --name nosuch: error" '[ $rc -eq 1 ] && [ ! -s "$TMP/none.csv" ] && grep -q "nosuch" "$TMP/err"'

"$UNDEX" sample "$TMP/run" --time 1e-4 --line "0.1,0 0.95,0" --points 2 --fields rho,p > "$TMP/s.csv"
check "sample: time line, header and 2 rows" '[ "$(sed -n 2p "$TMP/s.csv")" = "x,y,rho,p" ] && [ $(wc -l < "$TMP/s.csv") -eq 4 ] && grep -q "^# time = 0.0001" "$TMP/s.csv"'
check "sample: gas and water states outside the waves" 'awk -F, "NR == 3 { g = (\$3 > 1629.9 && \$3 < 1630.1 && \$4 > 7.80996e9 && \$4 < 7.81004e9) } NR == 4 { w = (\$3 > 999.9 && \$3 < 1000.1 && \$4 > 6e4 && \$4 < 1.4e5) } END { exit !(g && w) }" "$TMP/s.csv"'
exit $failed
