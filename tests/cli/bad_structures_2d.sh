#!/usr/bin/env bash
# The structure side of a 2D coupled case is checked before anything runs (issue 15, item 8): a wet face
# outside the fluid's domain, a FLUID face without a fluid, a plate in a fluid with no FLUID face, a 2D rigid
# plate without its face or with fixed edges. Each gives one line naming FILE:LINE: and the field, exit 1.
# The valid cases of tests/cases pass.
#   usage: bad_structures_2d.sh BIN_DIR TESTS_DIR
set -u
BIN=$1 TESTS=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
passed=0
failed=0

for pair in "undex-solid plate_2d" "undex-rigid rigid_plate_2d"; do
    set -- $pair
    if "$BIN/$1" --check "$TESTS/cases/$2.case" > "$TMP/out" 2>&1 && grep -q ": ok: structure" "$TMP/out"; then
        echo "ok: $2 passes $1 --check"; passed=$((passed + 1))
    else echo "FAIL: $2: $(cat "$TMP/out")"; failed=$((failed + 1)); fi
done

# bad SOLVER CASE NAME SED LINE FIELD MESSAGE: --check must fail with one line FILE:LINE:COL: FIELD: MESSAGE...
bad() {
    local solver=$1 base=$2 name=$3 expr=$4 line=$5 field=$6 message=$7 f="$TMP/$3.case"
    sed -e "$expr" "$TESTS/cases/$base.case" > "$f"
    "$BIN/$solver" --check "$f" > /dev/null 2> "$TMP/err"
    local rc=$? problems=""
    [ $rc -eq 1 ] || problems+=" exit $rc;"
    [ "$(wc -l < "$TMP/err")" -eq 1 ] || problems+=" not one stderr line;"
    grep -qF "$f:$line:" "$TMP/err" || problems+=" no '$f:$line:';"
    grep -qF "$field: $message" "$TMP/err" || problems+=" no '$field: $message';"
    if [ -z "$problems" ]; then echo "ok: $name: $(cat "$TMP/err")"; passed=$((passed + 1));
    else echo "FAIL: $name:$problems $(cat "$TMP/err")"; failed=$((failed + 1)); fi
}

# plate_2d.case: domain y from -0.1 to 0.1 m, x from 0 to 0.2 m; the plate 10 mm thick, front at -5 mm.
bad undex-solid plate_2d front-below-domain 's/y_front: -0.005/y_front: -0.1/' 19 structure.plate.y_front \
    "the plate's wet front face lies at y = -0.1 m, not inside the fluid's domain"
bad undex-solid plate_2d back-above-domain 's/y_front: -0.005/y_front: 0.095/' 19 structure.plate.y_front \
    "the plate's wet back face lies at y = 0.105 m, not inside the fluid's domain"
bad undex-solid plate_2d beyond-x-max 's/span: 0.2 element_size/span: 0.25 element_size/' 19 structure.plate.span \
    "the plate's wet face ends at x = 0.25 m, outside the fluid's domain"
bad undex-solid plate_2d before-x-min 's/span: 0.2 element_size/x_min: -0.01 span: 0.2 element_size/' 19 \
    structure.plate.x_min "the plate's wet face starts at x = -0.01 m, outside the fluid's domain"
# A dry back may lie outside (an air-backed plate against the domain's side).
sed -e 's/y_front: -0.005/y_front: 0.095/' -e 's/back { type: FLUID }/back { type: FREE }/' \
    "$TESTS/cases/plate_2d.case" > "$TMP/dry-back.case"
if "$BIN/undex-solid" --check "$TMP/dry-back.case" > /dev/null 2>&1; then
    echo "ok: a dry back face beyond the domain passes"; passed=$((passed + 1))
else echo "FAIL: dry back beyond the domain: $("$BIN/undex-solid" --check "$TMP/dry-back.case" 2>&1)"; failed=$((failed + 1)); fi
bad undex-solid plate_2d no-fluid-face 's/front { type: FLUID }/front { type: FREE }/; s/back { type: FLUID }/back { type: FREE }/' \
    20 structure.front.type "with a fluid in the case the plate is coupled to it"
bad undex-solid plate_2d fluid-face-without-fluid '9,15d' 13 structure.front.type "a FLUID face needs a fluid in the case"
# rigid_plate_2d.case: the same domain; the plate's front at y = 0.
bad undex-rigid rigid_plate_2d rigid-face-outside 's/span: 0.2 element_size: 0.05/span: 0.2 element_size: 0.05 y_front: 0.2/' \
    15 structure.plate.y_front "the plate's wet front face lies at y = 0.2 m, not inside the fluid's domain"
bad undex-rigid rigid_plate_2d rigid-without-face '/^  plate/d' 13 structure.plate "a 2D rigid plate needs 'plate'"
bad undex-rigid rigid_plate_2d rigid-clamped-edge 's/left { type: FREE }/left { type: CLAMPED }/' 15 \
    structure.plate.left.type "a rigid plate moves as one body: its edges are FREE"

# The application's cases (issue 16, item 7) through `undex check`, which reads both sides: a bubble reaching
# into the plate, a plate above the domain, a clamped edge inside the fluid, a foam curve that falls.
app() {
    local base=$1 name=$2 expr=$3 line=$4 field=$5 message=$6 f="$TMP/$2.case"
    sed -e "$expr" "$TESTS/../cases/$base.case" > "$f"
    "$BIN/undex" check "$f" > /dev/null 2> "$TMP/err"
    local rc=$? problems=""
    [ $rc -eq 1 ] || problems+=" exit $rc;"
    [ "$(wc -l < "$TMP/err")" -eq 1 ] || problems+=" not one stderr line;"
    grep -qF "$f:$line:" "$TMP/err" || problems+=" no '$f:$line:';"
    grep -qF "$field: $message" "$TMP/err" || problems+=" no '$field: $message';"
    if [ -z "$problems" ]; then echo "ok: $name: $(cat "$TMP/err")"; passed=$((passed + 1));
    else echo "FAIL: $name:$problems $(cat "$TMP/err")"; failed=$((failed + 1)); fi
}
for c in undex_steel_plate undex_sandwich_plate; do
    if "$BIN/undex" check "$TESTS/../cases/$c.case" > "$TMP/out" 2>&1; then echo "ok: $c passes undex check"; passed=$((passed + 1))
    else echo "FAIL: $c: $(cat "$TMP/out")"; failed=$((failed + 1)); fi
done
app undex_steel_plate bubble-in-plate 's/ball { x: 0 y: -2.0 radius: 0.5 }/ball { x: 0 y: -0.3 radius: 0.5 }/' 56 \
    'regions[1].ball' 'the gas region overlaps the plate (x 0 to 5, y 0 to 0.068 m)'
sed 's/ball { x: 0 y: -2.0 radius: 0.5 }/ball { x: 0 y: -0.5 radius: 0.5 }/' \
    "$TESTS/../cases/undex_steel_plate.case" > "$TMP/touching.case"   # touching is allowed (issue 15)
if "$BIN/undex" check "$TMP/touching.case" > "$TMP/out" 2>&1; then echo "ok: a bubble touching the plate passes"; passed=$((passed + 1))
else echo "FAIL: a bubble touching the plate: $(cat "$TMP/out")"; failed=$((failed + 1)); fi
app undex_steel_plate plate-above-domain 's/span: 5.0 element_size: 0.01 y_front: 0/span: 5.0 element_size: 0.01 y_front: 6.5/' 73 \
    structure.plate.y_front "the plate's wet front face lies at y = 6.5 m, not inside the fluid's domain"
app undex_steel_plate clamp-inside-fluid 's/span: 5.0 element_size: 0.01 y_front: 0/span: 4.0 element_size: 0.01 y_front: 0/' 75 \
    structure.plate.right.type 'a clamped edge of a wet plate must lie on the fluid'"'"'s side x = 5 m; this one is at x = 4 m'
app undex_sandwich_plate foam-curve-falls 's/sigma_c: \[4e6, 4.2e6, 6e6, /sigma_c: [4e6, 3.8e6, 6e6, /' 81 \
    'structure.materials[1].deshpande_fleck.sigma_c[1]' 'sigma_c must not decrease along the crushing curve'

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
