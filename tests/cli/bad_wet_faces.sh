#!/usr/bin/env bash
# The fluid's side of bad 2D wet faces (issue 15, item 8), against prescribed-motion plates that send them
# (tests/coupling/moving_plate.py): a wet node outside the fluid's domain (refused at the handshake: a
# coupling failure, exit 3), a plate across a gas bubble at the start (refused at the handshake: exit 3)
# and a wet face with no water next to it (the fluid's sample fails: exit 2); case 4.5 (coarse) under a
# 300 MPa wave, which turns a core element inside out (the structure fails: exit 2, the fluid 3);
# and a 2D case with a structure at degree 2 and CFL above 0.15 (refused at --check). Each: both
# processes stop, the message names what and where, and fluid.h5 stays readable with its status.
#   usage: bad_wet_faces.sh BIN_DIR PYTHON_DIR SOURCE_DIR
set -u
BIN=$1 PY=$2 SRC=$3
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
passed=0
failed=0

# run NAME PLATE_ARGS EXIT MESSAGE [MORE_CASE_TEXT]
run() {
    local name=$1 args=$2 want=$3 message=$4 more=${5:-} out="$TMP/$1"
    mkdir -p "$out"
    cat > "$out/case.case" <<CASE
name: "$name"
geometry: PLANAR_2D
domain { x_min: -0.5 x_max: 0.5 cells_x: 20 y_min: 0 y_max: 1 cells_y: 20 }
materials { name: "water" tait { } }
regions { material: "water" rho: 1000 p: 1e5 }
$more
boundaries { x_min { type: WALL } x_max { type: WALL } y_min { type: WALL } y_max { type: WALL } }
numerics { degree: 1 threads: 1 }
structure { command: "/usr/bin/python3 $SRC/tests/coupling/moving_plate.py $args --speed 0 --proto-dir $PY" front { type: FLUID } back { type: FLUID } }
end_time: 1e-4
output { directory: "$out" }
CASE
    "$BIN/undex" run "$out/case.case" > "$out/log" 2>&1
    local rc=$? problems=""
    [ $rc -ne 0 ] || problems+=" the run succeeded;"
    grep -q "fluid ended with exit code $want" "$out/log" || problems+=" no 'fluid ended with exit code $want';"
    grep -qF "$message" "$out/fluid.log" || problems+=" fluid.log lacks '$message';"
    # A refusal at the handshake comes before the first output: then no fluid.h5 at all; after it, fluid.h5
    # is readable and says why it failed.
    if [ -e "$out/fluid.h5" ]; then
        /usr/bin/python3 -c "
import h5py, sys
with h5py.File('$out/fluid.h5') as f:
    s = f['status'][()].decode()
    sys.exit(0 if s.startswith('failed') else 1)" 2> /dev/null || problems+=" fluid.h5 not readable with a failed status;"
    elif [ "$want" -ne 3 ]; then problems+=" no fluid.h5;"; fi
    if [ -z "$problems" ]; then echo "ok: $name: $(grep -m1 'error' "$out/fluid.log")"; passed=$((passed + 1));
    else echo "FAIL: $name:$problems"; cat "$out/log"; failed=$((failed + 1)); fi
}

run outside "--faces 1 --nodes 11 --xc 0 --yc 1.2 --length 0.5" 3 "lies outside the fluid domain"
# A plate across a gas bubble at the start: refused at the handshake, naming the cell.
run crosses-gas "--faces 2 --nodes 21 --xc 0 --yc 0.5 --length 1.0 --thickness 0.1" 3 \
    "the structure crosses the gas in cell" \
    'materials { name: "gas" stiffened_gas { gamma: 1.4 } } regions { material: "gas" ball { x: 0 y: 0.45 radius: 0.2 } rho: 10 p: 1e6 }'
# Face 0 on the domain's lower edge with the structure above it: no water below it in the domain.
run no-water "--faces 1 --nodes 21 --xc 0 --yc 0 --length 1.0" 2 "has no fluid within 3 cells along its normal"

# An element turned inside out by the load: case 4.5 at 0.04 m under 300 MPa in place of 2 MPa. Both
# processes stop, both logs name the element, both outputs are readable with a failed status.
out="$TMP/inverted"
"$BIN/undex" run "$SRC/cases/sandwich_plate_water_backed_2d.case" --set domain.cells_x=50 --set domain.cells_y=58 \
    --set boundaries.y_min.pressure.p_peak=3e8 --set end_time=1.5e-3 --set numerics.threads=1 \
    --set output.directory="$out" > "$TMP/inverted.log" 2>&1
rc=$? problems=""
[ $rc -ne 0 ] || problems+=" the run succeeded;"
grep -q "solid ended with exit code 2" "$TMP/inverted.log" || problems+=" no 'solid ended with exit code 2';"
grep -q "fluid ended with exit code 3" "$TMP/inverted.log" || problems+=" no 'fluid ended with exit code 3';"
for side in fluid solid; do
    grep -q "element [0-9]* (layer [0-9], centre x = .*) inverted at t = " "$out/$side.log" ||
        problems+=" $side.log does not name the element;"
    /usr/bin/python3 -c "
import h5py, sys
with h5py.File('$out/$side.h5') as f:
    sys.exit(0 if f['status'][()].decode().startswith('failed') and len(f['fields']) > 1 else 1)" 2> /dev/null ||
        problems+=" $side.h5 not readable with a failed status and its outputs;"
done
if [ -z "$problems" ]; then echo "ok: inverted: $(grep -m1 'error' "$out/solid.log")"; passed=$((passed + 1));
else echo "FAIL: inverted:$problems"; cat "$TMP/inverted.log"; failed=$((failed + 1)); fi

# Degree 2 at the default CFL 0.2 next to a structure in 2D: refused at --check, naming numerics.cfl.
sed -e 's/numerics { degree: 1 threads: 1 }/numerics { degree: 2 }/' "$TMP/outside/case.case" > "$TMP/p2.case"
if ! "$BIN/undex-fluid" --check "$TMP/p2.case" > /dev/null 2> "$TMP/p2.err" &&
    grep -q "numerics.cfl: degree 2 next to a structure in 2D is unstable above CFL 0.15" "$TMP/p2.err"; then
    echo "ok: degree 2 at CFL 0.2: $(cat "$TMP/p2.err")"; passed=$((passed + 1))
else echo "FAIL: degree 2 at CFL 0.2 not refused: $(cat "$TMP/p2.err")"; failed=$((failed + 1)); fi

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
