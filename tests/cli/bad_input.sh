#!/usr/bin/env bash
# Input that must be refused by `undex check` at once, with exit status 1 (base/exit_status.hpp) and one error
# line naming the field and where it is (FILE:LINE:COL: FIELD, or --set FIELD):
#   - non-finite and out-of-range numbers in every kind of message (ranges: proto/case.proto), set in a file
#     (text and JSON) or by --set, including list elements and a range through a JSON file's line:col;
#   - shapes outside the domain or inverted, a oneof choice switched by --set (as_stiffened_gas on a gas);
#   - sizes beyond memory or the solvers' int indices (cells, elements, output times), refused before
#     anything is allocated: each run under `ulimit -v` 1 GiB and `timeout` 10 s;
#   - JSON duplicate keys, trailing commas, wrong types, with line:col;
#   - malformed --set paths;
#   - case files that are directories, devices, FIFOs or too large; an empty output directory.
# And what must still pass: every shipped case, and the paper-resolution application mesh (2.4 M fluid cells,
# about 6 GiB in a run), whose check must take under 10 s and 1 GiB (measured by /usr/bin/time).
#
#   usage: bad_input.sh UNDEX_BINARY CASES_DIR
set -u

if [ $# -ne 2 ]; then
    echo "usage: $0 UNDEX_BINARY CASES_DIR" >&2
    exit 2
fi
UNDEX=$1
CASES=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
OUT=$TMP/out # the output directory of every check (never written by a check)

passed=0
failed=0
pass() { echo "ok: $1"; passed=$((passed + 1)); }
fail() { echo "FAIL: $1"; failed=$((failed + 1)); }

# Limits of a check on bad input: 10 s (the issue's bound; a good check takes 0.1 s) and 1 GiB of address
# space (ulimit -v, in KiB; undex and a solver each use about 50 MB).
LIMIT_S=10
LIMIT_KB=1048576

# refused LABEL PATTERN... -- ARGS...: `undex check ARGS` under the limits exits with STATUS (default 1)
# and one line "undex: error: ..." on stderr (two for a usage error: the hint follows) that contains every
# PATTERN (fixed strings).
refused() {
    local label=$1
    shift
    local patterns=()
    while [ $# -gt 0 ] && [ "$1" != "--" ]; do
        patterns+=("$1")
        shift
    done
    shift
    (ulimit -v $LIMIT_KB && timeout $LIMIT_S "$UNDEX" check "$@") > "$TMP/stdout" 2> "$TMP/stderr"
    local rc=$? problems="" lines p status=${STATUS:-1}
    [ $rc -eq "$status" ] || problems+=" exit status $rc (expected $status; 124: timed out);"
    lines=$(grep -c '' "$TMP/stderr")
    [ "$lines" -eq $((status == 64 ? 2 : 1)) ] || problems+=" stderr has $lines lines;"
    grep -q '^undex: error: ' "$TMP/stderr" || problems+=" no 'undex: error:' line;"
    for p in "${patterns[@]}"; do
        grep -qF -- "$p" "$TMP/stderr" || problems+=" message lacks '$p';"
    done
    if [ -z "$problems" ]; then
        pass "$label: $(head -n 1 "$TMP/stderr")"
    else
        fail "$label:$problems stderr: $(head -c 600 "$TMP/stderr" | tr '\n' '|')"
    fi
}

# admitted LABEL ARGS...: `undex check ARGS` exits 0 within LIMIT_S seconds and LIMIT_KB of resident memory
# (measured, not limited: the check of a large case must not build it).
admitted() {
    local label=$1
    shift
    /usr/bin/time -f "%e %M" -o "$TMP/time" "$UNDEX" check "$@" > "$TMP/stdout" 2> "$TMP/stderr"
    local rc=$? seconds kb
    read -r seconds kb < <(tail -n 1 "$TMP/time")
    if [ $rc -eq 0 ] && awk -v s="$seconds" -v k="$kb" -v S=$LIMIT_S -v K=$LIMIT_KB 'BEGIN { exit !(s < S && k < K) }'; then
        pass "$label ($seconds s, $kb KB): $(tr '\n' ' ' < "$TMP/stdout" | head -c 300)"
    else
        fail "$label: exit status $rc, $seconds s, $kb KB, stderr: $(head -c 400 "$TMP/stderr" | tr '\n' '|')"
    fi
}

# --- Base cases. A 1D fluid (line numbers matter: 4 domain, 5 materials, 6 regions[0], 7 regions[1],
# 12 numerics, 13 end_time, 14 output, 15 gauges[0]).
cat > "$TMP/fluid.case" <<EOF
# a 1D fluid: Sod's shock tube on 20 cells
name: "fluid"
geometry: PLANAR_1D
domain { x_min: 0 x_max: 1 cells_x: 20 }
materials { name: "air" stiffened_gas { gamma: 1.4 } }
regions { material: "air" rho: 1 p: 1 }
regions { material: "air" box { x_min: 0.5 } rho: 0.125 p: 0.1 }
boundaries {
  x_min { type: TRANSMISSIVE }
  x_max { type: TRANSMISSIVE }
}
numerics { degree: 1 cfl: 0.2 }
end_time: 0.01
output { directory: "$OUT" times: [0.002, 0.004] }
gauges { name: "g" x: 0.5 }
EOF
F=$TMP/fluid.case
# The same as JSON (lines: 4 domain, 8 regions[1], 11 numerics, 13 output).
cat > "$TMP/fluid.json" <<EOF
{
  "name": "fluid",
  "geometry": "PLANAR_1D",
  "domain": { "x_min": 0, "x_max": 1, "cells_x": 20 },
  "materials": [ { "name": "air", "stiffened_gas": { "gamma": 1.4 } } ],
  "regions": [
    { "material": "air", "rho": 1, "p": 1 },
    { "material": "air", "box": { "x_min": 0.5 }, "rho": 0.125, "p": 0.1 }
  ],
  "boundaries": { "x_min": { "type": "TRANSMISSIVE" }, "x_max": { "type": "TRANSMISSIVE" } },
  "numerics": { "degree": 1, "cfl": 0.2 },
  "end_time": 0.01,
  "output": { "directory": "$OUT", "times": [0.002, 0.004] }
}
EOF
J=$TMP/fluid.json
# A 2D fluid with two materials, the coupled 1D case, the axisymmetric plate, the rigid plate (shipped).
TWO_D=$CASES/free_field_2d.case
COUPLED=$CASES/sandwich_shock_1d.case
PLATE=$CASES/sandwich_plate_axisymmetric.case
RIGID=$CASES/taylor_plate_1d.case
TWO=$CASES/undex_1d.case
O=(-o "$OUT")

# edit NAME SED_EXPRESSION: $TMP/NAME.case from the 1D fluid case.
edit() { sed -e "$2" "$F" > "$TMP/$1.case"; }
jedit() { sed -e "$2" "$J" > "$TMP/$1.json"; }

# --- What must pass.
admitted "the 1D fluid case" "$F"
admitted "the 1D fluid case as JSON" "$J"
for c in "$CASES"/*.case; do
    admitted "shipped case $(basename "$c")" "$c" "${O[@]}"
done
# The application of the paper (physics.md §8, case 5): 5 m x 12 m at 5 mm, 1000 x 2400 cells of degree 2
# with two fluids; and a plate of a million elements (checked without building it).
admitted "paper-resolution fluid mesh" "$TWO_D" "${O[@]}" --set domain.cells_x=1000 --set domain.cells_y=2400
admitted "a plate of 1.05 M elements" "$PLATE" "${O[@]}" --set structure.plate.element_size=1e-4

# --- Non-finite and out-of-range numbers: in the file (text format: FILE:LINE:COL: FIELD).
edit end-inf 's/end_time: 0.01/end_time: inf/'
refused "end_time inf" "$TMP/end-inf.case:13:1: end_time" "must be a finite number" "(0, 1e+06]" -- "$TMP/end-inf.case"
edit end-huge 's/end_time: 0.01/end_time: 1e400/'
refused "end_time 1e400" "$TMP/end-huge.case:13:1: end_time" "must be a finite number" -- "$TMP/end-huge.case"
edit rho-inf 's/rho: 0.125/rho: inf/'
refused "density inf" "$TMP/rho-inf.case:7:" "regions[1].rho" "must be a finite number" -- "$TMP/rho-inf.case"
edit u-nan 's/rho: 0.125 p/rho: 0.125 u: nan p/'
refused "velocity nan" "$TMP/u-nan.case:7:" "regions[1].u" "nan" -- "$TMP/u-nan.case"
edit gamma-inf 's/gamma: 1.4/gamma: inf/'
refused "gamma inf" "$TMP/gamma-inf.case:5:" "materials[0].stiffened_gas.gamma" "(1, 100]" -- "$TMP/gamma-inf.case"
edit p-huge 's/p: 0.1 }/p: 1e300 }/'
refused "pressure 1e300" "$TMP/p-huge.case:7:" "regions[1].p" "[-1e+12, 1e+12]" -- "$TMP/p-huge.case"
edit gauge-nan 's/x: 0.5 }$/x: nan }/'
refused "gauge position nan" "$TMP/gauge-nan.case:15:" "gauges[0].x" "nan" -- "$TMP/gauge-nan.case"
edit time-inf 's/times: \[0.002, 0.004\]/times: [0.002, inf]/'
refused "output time inf (a list element)" "$TMP/time-inf.case:14:" "output.times[1]" -- "$TMP/time-inf.case"
edit cells-zero 's/cells_x: 20/cells_x: 0/'
refused "cells_x 0" "$TMP/cells-zero.case:4:" "domain.cells_x" "[1, 1e+09]" -- "$TMP/cells-zero.case"
edit cfl-big 's/cfl: 0.2/cfl: 1.5/'
refused "cfl 1.5" "$TMP/cfl-big.case:12:" "numerics.cfl" "(0, 1]" -- "$TMP/cfl-big.case"
# By --set, in the other messages: the message names the override.
refused "Young's modulus inf" "--set structure.materials[0].elastic.E" "must be a finite number" -- \
    "$COUPLED" "${O[@]}" --set structure.materials[0].elastic.E=inf
refused "plate mass 1e400" "--set structure.rigid_plate.mass_per_area" "must be a finite number" -- \
    "$RIGID" "${O[@]}" --set structure.rigid_plate.mass_per_area=1e400
refused "Tait B inf" "--set materials[1].tait.B" -- "$TWO" "${O[@]}" --set materials[1].tait.B=inf
refused "foam curve element inf" "--set structure.materials[1].deshpande_fleck.sigma_c[2]" -- \
    "$PLATE" "${O[@]}" --set "structure.materials[1].deshpande_fleck.sigma_c[2]=inf"
refused "pressure history -inf" "--set boundaries.x_min.pressure.p_peak" -- \
    "$COUPLED" "${O[@]}" --set boundaries.x_min.pressure.p_peak=-inf
refused "cavitation alpha0 1" "--set cavitation.alpha0" "(0, 1)" -- "$COUPLED" "${O[@]}" --set cavitation.alpha0=1
refused "coupling timeout nan" "--set coupling.timeout" -- "$COUPLED" "${O[@]}" --set coupling.timeout=nan
refused "structure dt inf" "--set structure.dt" -- "$COUPLED" "${O[@]}" --set structure.dt=inf
refused "solid gauge nan" "--set structure.gauges[0].y" -- "$PLATE" "${O[@]}" --set "structure.gauges[0].y=nan"
refused "ball radius -1" "--set regions[1].ball.radius" -- "$TWO_D" "${O[@]}" --set regions[1].ball.radius=-1

# --- Shapes and choices.
edit box-out 's/box { x_min: 0.5 }/box { x_min: 5 }/'
refused "box outside the domain" "$TMP/box-out.case:7:" "regions[1].box" "outside the domain" -- "$TMP/box-out.case"
edit box-inverted 's/box { x_min: 0.5 }/box { x_min: 0.5 x_max: 0.2 }/'
refused "inverted box" "$TMP/box-inverted.case:7:" "regions[1].box.x_max" -- "$TMP/box-inverted.case"
refused "ball outside the domain" "regions[1].ball" "outside the domain" -- "$TWO_D" "${O[@]}" --set regions[1].ball.x=5
refused "as_stiffened_gas on a gas (--set)" "--set materials[0].tait.as_stiffened_gas" "stiffened_gas" -- \
    "$F" --set materials[0].tait.as_stiffened_gas=true
edit two-models 's/gamma: 1.4 }/gamma: 1.4 } tait { as_stiffened_gas: true }/'
refused "as_stiffened_gas on a gas (file)" "$TMP/two-models.case:5:" "oneof" -- "$TMP/two-models.case"

# --- Sizes: refused before anything is allocated (under the 1 GiB address-space limit).
refused "cells_x = 2147483647" "--set domain.cells_x" -- "$F" --set domain.cells_x=2147483647
refused "a billion 1D cells" "--set domain.cells_x" "fluid cells need about" "GiB" -- "$F" --set domain.cells_x=1000000000
refused "a 30000 x 30000 2D mesh" "--set domain.cells_" "fluid cells need about" -- \
    "$TWO_D" "${O[@]}" --set domain.cells_x=30000 --set domain.cells_y=30000
refused "a 100000 x 100000 2D mesh" "--set domain.cells_" "beyond the solver's cell numbers" -- \
    "$TWO_D" "${O[@]}" --set domain.cells_x=100000 --set domain.cells_y=100000
refused "output.interval 1e-20" "--set output.interval" "output times" -- "$F" --set output.interval=1e-20
refused "layer element size 1e-12" "--set structure.layers[0].element_size" "elements" -- \
    "$COUPLED" "${O[@]}" --set structure.layers[0].element_size=1e-12
refused "plate element size 1e-12" "--set structure.plate.element_size" "elements" -- \
    "$PLATE" "${O[@]}" --set structure.plate.element_size=1e-12
refused "plate of 1e8 elements" "--set structure.plate.element_size" "structure elements need about" -- \
    "$PLATE" "${O[@]}" --set structure.plate.element_size=1e-5 --set structure.layers[1].element_size=1e-3
/usr/bin/python3 -c "print('{\"end_time\": 1, \"output\": {\"times\": [' + ','.join(['0.5'] * 1000001) + ']}}')" \
    > "$TMP/long-list.json"
refused "a list of 1000001 numbers" "$TMP/long-list.json:1:" "output.times" "at most 1000000" -- "$TMP/long-list.json"

# A text case on one 6 MB line with an error at its end (the column is found by a linear scan).
/usr/bin/python3 -c "print('geometry: PLANAR_1D end_time: 1 output { times: [' + ','.join(['1'] * 3000000) + ', x] }')" \
    > "$TMP/long-line.case"
refused "an error at column 6000051" "$TMP/long-line.case:1:6000051:" "times" -- "$TMP/long-line.case"

# --- JSON: strict, with line:col.
jedit duplicate 's/"rho": 0.125/"rho": 0.125, "rho": 2/'
refused "JSON duplicate key" "$TMP/duplicate.json:8:" "duplicate key 'rho'" -- "$TMP/duplicate.json"
jedit trailing-object 's/"cfl": 0.2 }/"cfl": 0.2, }/'
refused "JSON trailing comma in an object" "$TMP/trailing-object.json:11:" "trailing comma" -- "$TMP/trailing-object.json"
jedit trailing-array 's/0.002, 0.004\]/0.002, 0.004,]/'
refused "JSON trailing comma in a list" "$TMP/trailing-array.json:13:" "trailing comma" -- "$TMP/trailing-array.json"
jedit json-range 's/"rho": 0.125/"rho": 1e400/'
refused "JSON density 1e400" "$TMP/json-range.json:8:" "regions[1].rho" "must be a finite number" -- "$TMP/json-range.json"
jedit json-type 's/"cfl": 0.2/"cfl": "fast"/'
refused "JSON wrong type" "$TMP/json-type.json:11:" "numerics.cfl" "a number is expected" -- "$TMP/json-type.json"
jedit json-unknown 's/"degree": 1/"nosuch": 1/'
refused "JSON unknown field" "$TMP/json-unknown.json:11:" "no field 'nosuch'" -- "$TMP/json-unknown.json"
jedit json-comment 's|^  "name": "fluid",|  // a comment\n  "name": "fluid",|'
refused "JSON comment" "$TMP/json-comment.json:2:" -- "$TMP/json-comment.json"
jedit json-int 's/"cells_x": 20/"cells_x": 20.5/'
refused "JSON fractional integer" "$TMP/json-int.json:4:" "domain.cells_x" -- "$TMP/json-int.json"
/usr/bin/python3 -c "print('{\"name\": ' + '[' * 100000)" > "$TMP/deep.json"
refused "JSON nested 100000 deep" "$TMP/deep.json:1:" "nested deeper" -- "$TMP/deep.json"

# --- Malformed --set paths and values.
for key in 'regions[1.p' 'regions[x].p' 'regions[-1].p' 'regions[].p' 'a..b' 'regions[1]x.p' 'numerics.cfl.' \
    '.numerics.cfl' 'regions[1].p junk' 'regions[99999999999].p'; do
    refused "--set '$key=0.2'" "--set $key" -- "$F" --set "$key=0.2"
done
refused "--set value with trailing garbage" "--set regions[1].p" "0.2x" -- "$F" --set "regions[1].p=0.2x"
refused "--set list element with trailing garbage" "--set output.times[0]" -- "$F" --set "output.times[0]=1e-3s"
refused "--set index on a non-list" "--set numerics[0].cfl" "not a list" -- "$F" --set "numerics[0].cfl=0.3"
refused "--set without =" "--set numerics.cfl" "key=value" -- "$F" --set "numerics.cfl"

# --- Case files that are no case files, and the output directory.
refused "a directory" "$TMP: is a directory" -- "$TMP"
refused "/dev/zero" "/dev/zero: is not a regular file" -- /dev/zero
mkfifo "$TMP/fifo"
refused "a FIFO" "$TMP/fifo: is not a regular file" -- "$TMP/fifo"
truncate -s 9M "$TMP/huge.case"
refused "a 9 MiB file" "$TMP/huge.case: the case file is larger than 8 MiB" -- "$TMP/huge.case"
refused "a missing file" "$TMP/nosuch.case: cannot open" -- "$TMP/nosuch.case"
edit empty-directory "s|directory: \"$OUT\"|directory: \"\"|"
refused "empty output.directory" "$TMP/empty-directory.case:14:" "output.directory" "empty" -- "$TMP/empty-directory.case"
STATUS=64 refused "empty -o (a usage error)" "--output" "empty" -- "$F" -o ""

# --- Numbers of `undex sample`, read whole and finite (usage errors, status 64).
"$UNDEX" run "$F" > "$TMP/run.log" 2>&1 || fail "run the 1D fluid case: $(tail -n 2 "$TMP/run.log" | tr '\n' '|')"
for line in "0,0 1x,0" "0,nan 1,0" "0,0 1,0 junk" "0,0" "0,0 1,0,"; do
    "$UNDEX" sample "$OUT" --time 0.01 --line "$line" --points 2 > "$TMP/stdout" 2> "$TMP/stderr"
    rc=$?
    if [ $rc -eq 64 ] && grep -qE -- "a point is x,y|--line is two points" "$TMP/stderr"; then
        pass "sample --line '$line': $(head -n 1 "$TMP/stderr")"
    else
        fail "sample --line '$line': exit status $rc, $(tr '\n' '|' < "$TMP/stderr")"
    fi
done

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
