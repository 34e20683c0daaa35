#!/usr/bin/env bash
# Structure parts of a case are checked in full before anything runs (issue "Structure solver", item 5):
# each bad input gives one line "undex: error: FILE:LINE:COL: FIELD: message", exit status 1, and nothing
# is written. A valid structure passes `check` and runs alone; a fluid with a structure waits for the coupler.
#   usage: bad_structures.sh UNDEX_BINARY
set -u
UNDEX=$1
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
passed=0
failed=0

# The valid base case: the sandwich of case 4.3 (lines: 5 steel, 6 foam, 7-9 layers, 10 front, 11 back).
cat > "$TMP/base.in" <<'CASE'
# minimal valid structure: the sandwich of case 4.3 under a pressure pulse
name: "sandwich"
geometry: PLANAR_1D
structure {
  materials { name: "steel" elastic { rho: 8000 E: 210e9 nu: 0.3 } }
  materials { name: "foam" foam_1d { rho: 236 E: 1e9 sigma_pl: 1.5e6 eta: 100 eps_d: 0.8 E_lock: 2e11 } }
  layers { material: "steel" thickness: 0.012 element_size: 0.002 }
  layers { material: "foam" thickness: 0.025 element_size: 0.000833333333333 }
  layers { material: "steel" thickness: 0.012 element_size: 0.002 }
  front { type: PRESSURE pressure { p_ambient: 0 p_peak: 1e7 theta: 2.4e-4 } }
  back { type: FREE } gauges { name: "back" x: 0.049 }
}
end_time: 1e-3
output { directory: "@OUT@" }
CASE

# The valid 2D base case: an axisymmetric sandwich plate, clamped at r = 0.5 m (lines: 4 steel, 5 foam,
# 6-8 layers, 9 plate, 10 front, 11 back and gauge).
cat > "$TMP/plate.in" <<'CASE'
name: "plate"
geometry: AXISYMMETRIC_2D
structure {
  materials { name: "steel" johnson_cook { rho: 8000 E: 210e9 nu: 0.28 A: 950e6 B: 560e6 n: 0.26 C: 0.014 } }
  materials { name: "foam" deshpande_fleck { rho: 430 E: 1e9 nu: 0.3 eps_p: [0, 0.5, 0.75] sigma_c: [4e6, 4.2e6, 40e6] } }
  layers { material: "steel" thickness: 0.01 element_size: 0.005 }
  layers { material: "foam" thickness: 0.03 element_size: 0.005 }
  layers { material: "steel" thickness: 0.01 element_size: 0.005 }
  plate { span: 0.5 element_size: 0.01 left { type: SYMMETRY } right { type: CLAMPED } }
  front { type: PRESSURE pressure { p_ambient: 0 p_peak: 2e7 theta: 1e-4 } }
  back { type: FREE } gauges { name: "P2" x: 0 y: 0.05 }
}
end_time: 5e-4
output { directory: "@OUT@" }
CASE

# bad NAME SED LINE FIELD: check must fail naming FILE:LINE: and FIELD, exit 1, one stderr line, no output.
# The base case is $TMP/base.in unless BASE names another.
bad() {
    local name=$1 expr=$2 line=$3 field=$4 f="$TMP/$1.case" out="$TMP/out-$1"
    sed -e "$expr" -e "s|@OUT@|$out|" "$TMP/${BASE:-base.in}" > "$f"
    "$UNDEX" check "$f" > /dev/null 2> "$TMP/err"
    local rc=$? problems=""
    [ $rc -eq 1 ] || problems+=" exit $rc;"
    [ "$(wc -l < "$TMP/err")" -eq 1 ] || problems+=" not one stderr line;"
    grep -qF "$f:$line:" "$TMP/err" || problems+=" no '$f:$line:';"
    grep -qF "$field" "$TMP/err" || problems+=" no '$field';"
    [ ! -e "$out" ] || problems+=" $out written;"
    if [ -z "$problems" ]; then echo "ok: $name: $(cat "$TMP/err")"; passed=$((passed + 1));
    else echo "FAIL: $name:$problems $(cat "$TMP/err")"; failed=$((failed + 1)); fi
}

sed -e "s|@OUT@|$TMP/out-valid|" "$TMP/base.in" > "$TMP/valid.case"
if "$UNDEX" check "$TMP/valid.case" | grep -q "ok: structure of 3 layer(s), 42 elements"; then
    echo "ok: valid structure"; passed=$((passed + 1))
else echo "FAIL: valid structure"; failed=$((failed + 1)); fi
# A valid structure runs alone (undex-solid): complete status, energy balance closed to 2e-5 of the external
# work, the core crushed plastically. The discrete balance of central differences falls as Δt²: measured
# 6.5e-6 at the step of each element's present modulus (3 303 steps), 4.7e-8 at the 11.8 times smaller step
# of the foam's lock-up modulus everywhere (38 815 steps, the step before issue 17); the bound is 3 times the
# measured value.
"$UNDEX" run "$TMP/valid.case" > "$TMP/run.log" 2> "$TMP/err"
rc=$?
if [ $rc -eq 0 ] && /usr/bin/python3 - "$TMP/out-valid/solid.h5" <<'PY'
import sys
import h5py
f = h5py.File(sys.argv[1], "r")
e = f["energies"]
last = f["fields"][sorted(f["fields"])[-1]]
ok = (f["status"][()] == b"complete" and abs(e["balance_error"][-1]) < 2e-5 * e["external"][-1]
      and e["plastic"][-1] > 0.1 * e["external"][-1] and last["peeq"][:].max() > 0.1)
sys.exit(0 if ok else 1)
PY
then echo "ok: a structure runs alone and closes its energy balance"; passed=$((passed + 1))
else echo "FAIL: structure run: exit $rc $(cat "$TMP/err") $(tail -n 2 "$TMP/run.log")"; failed=$((failed + 1)); fi

# The gauge of the run prints as CSV, time first.
"$UNDEX" gauges "$TMP/out-valid" --name back > "$TMP/g.csv" 2> "$TMP/err"
if [ "$(head -n 1 "$TMP/g.csv")" = "t,u,v,a,stress_xx,peeq" ] && [ "$(wc -l < "$TMP/g.csv")" -gt 10 ]; then
    echo "ok: structure gauge as CSV"; passed=$((passed + 1))
else echo "FAIL: structure gauge: $(head -n 2 "$TMP/g.csv") $(cat "$TMP/err")"; failed=$((failed + 1)); fi

# An element that inverts stops the run (exit 2) naming it, and the last good state is kept.
sed -e 's/sigma_pl: 1.5e6 eta: 100 eps_d: 0.8 E_lock: 2e11/sigma_pl: 1.5e6 eta: 0 eps_d: 0.99 E_lock: 1e9/' \
    -e 's/p_peak: 1e7/p_peak: 1e9/' -e "s|@OUT@|$TMP/out-invert|" "$TMP/base.in" > "$TMP/invert.case"
"$UNDEX" run "$TMP/invert.case" > "$TMP/run.log" 2>&1
rc=$?
if [ $rc -eq 2 ] && grep -q "undex-solid: error: element .* inverted at t = .* in step" "$TMP/run.log" &&
    /usr/bin/python3 -c "import h5py,sys; f=h5py.File(sys.argv[1]); g=f['fields'][sorted(f['fields'])[-1]]; sys.exit(0 if f['status'][()].decode().startswith('failed') and g.attrs['last_good'] == 1 else 1)" "$TMP/out-invert/solid.h5"
then echo "ok: inversion stops with the element named and the last good state kept"; passed=$((passed + 1))
else echo "FAIL: inversion: exit $rc $(tail -n 3 "$TMP/run.log")"; failed=$((failed + 1)); fi

# A fluid with a structure must meet it at its x_max side (STRUCTURE): refused clearly, nothing written.
sed -e "s|@OUT@|$TMP/out-both|" -e 's/^structure {/domain { x_min: 0 x_max: 1 cells_x: 10 }\nmaterials { name: "air" stiffened_gas { gamma: 1.4 } }\nregions { material: "air" rho: 1 p: 1 }\nboundaries { x_min { type: WALL } x_max { type: WALL } }\nstructure {/' "$TMP/base.in" > "$TMP/both.case"
"$UNDEX" run "$TMP/both.case" > /dev/null 2> "$TMP/err"
if [ $? -eq 1 ] && grep -q "boundaries.x_max: with a structure in the case, the fluid's x_max side is its wet face: STRUCTURE" "$TMP/err" && [ ! -e "$TMP/out-both" ]; then
    echo "ok: fluid with structure but no STRUCTURE boundary refused"; passed=$((passed + 1))
else echo "FAIL: fluid with structure: $(cat "$TMP/err")"; failed=$((failed + 1)); fi

bad missing-constant 's/ E: 210e9//' 5 'structure.materials[0].elastic.E'
bad constant-out-of-range 's/nu: 0.3/nu: 0.6/' 5 'structure.materials[0].elastic'
bad missing-lock-modulus 's/ E_lock: 2e11//' 6 'structure.materials[1].foam_1d.E_lock'
bad zero-element '0,/element_size: 0.002/s//element_size: 0/' 7 'structure.layers[0].element_size'
bad negative-element '0,/element_size: 0.002/s//element_size: -0.002/' 7 'structure.layers[0].element_size'
bad layer-thinner-than-element '0,/element_size: 0.002/s//element_size: 0.02/' 7 'structure.layers[0].thickness'
bad unknown-material 's/material: "foam"/material: "cork"/' 8 'structure.layers[1].material'
bad dt-above-stable 's/back { type: FREE }/back { type: FREE } dt: 1e-6/' 11 'structure.dt'
bad pressure-without-history 's/front { type: PRESSURE pressure {[^}]*} }/front { type: PRESSURE }/' 10 'structure.front'
bad unwritable-output 's|"@OUT@"|"/proc/undex-cannot-write"|' 14 'output.directory'
bad gauge-outside 's/x: 0.049/x: 0.06/' 11 'structure.gauges[0].x'
bad unknown-kinematics 's/back { type: FREE }/back { type: FREE } kinematics: "bent"/' 11 'structure.kinematics'
# What every solver's run reads (base/run_plan.cpp validate_plan), checked for a structure alone too.
bad zero-gauge-every 's|output { directory: "@OUT@" }|output { directory: "@OUT@" gauge_every: 0 }|' 14 'output.gauge_every'
bad zero-progress 's|output { directory: "@OUT@" }|output { directory: "@OUT@" progress_seconds: 0 }|' 14 'output.progress_seconds'
bad output-after-end 's|output { directory: "@OUT@" }|output { directory: "@OUT@" times: [2e-3] }|' 14 'output.times'
bad zero-max-steps 's|output { directory: "@OUT@" }|output { directory: "@OUT@" } numerics { max_steps: 0 }|' 14 'numerics.max_steps'

bad plate-in-1d 's/back { type: FREE }/back { type: FREE } plate { span: 1 element_size: 0.1 left { type: FREE } right { type: FREE } }/' 11 'structure.plate'
bad bulk-viscosity-in-1d 's/back { type: FREE }/back { type: FREE } bulk_viscosity_linear: 0.06/' 11 'structure.bulk_viscosity_linear'

# 2D plates: a valid plate passes check, runs alone, closes its energy balance (bound 1e-3 of the external
# work: the O(Δt²) error of central differences under a sudden load, as in test_plate_2d), writes an XDMF
# file whose every dataset is in solid.h5, and prints its gauges as CSV.
sed -e "s|@OUT@|$TMP/out-plate|" "$TMP/plate.in" > "$TMP/plate.case"
if "$UNDEX" check "$TMP/plate.case" | grep -q "ok: structure of 3 layer(s), 500 elements (axisymmetric)"; then
    echo "ok: valid plate"; passed=$((passed + 1))
else echo "FAIL: valid plate: $("$UNDEX" check "$TMP/plate.case" 2>&1)"; failed=$((failed + 1)); fi
"$UNDEX" run "$TMP/plate.case" > "$TMP/run.log" 2> "$TMP/err"
rc=$?
if [ $rc -eq 0 ] && /usr/bin/python3 - "$TMP/out-plate" <<'PY'
import re
import sys
import xml.etree.ElementTree as ET
import h5py
d = sys.argv[1]
f = h5py.File(d + "/solid.h5", "r")
e = f["energies"]
ok = (f["status"][()] == b"complete"
      and max(abs(e["balance_error"][:])) < 1e-3 * e["external"][-1]
      and f["nodes"].shape == (51 * 11, 2) and f["quads"].shape == (500, 4))
items = [i.text.split(":", 1)[1] for i in ET.parse(d + "/solid.xmf").iter("DataItem")]
grids = list(ET.parse(d + "/solid.xmf").iter("Grid"))
ok = ok and len(grids) == len(f["fields"]) + 1 and all(i in f for i in items)
# Displacement and velocity as vectors of three components (ParaView's Warp By Vector): the attribute's type
# and dimensions, and its values (x, y, 0) against the scalar fields, in every snapshot.
n = f["nodes"].shape[0]
for g in grids[1:]:
    for name, (cx, cy) in (("displacement", ("u_x", "u_y")), ("velocity", ("v_x", "v_y"))):
        a = [t for t in g.iter("Attribute") if t.get("Name") == name]
        ok = ok and len(a) == 1 and a[0].get("AttributeType") == "Vector" and a[0].get("Center") == "Node"
        item = a[0].find("DataItem") if a else None
        ok = ok and item is not None and item.get("Dimensions") == f"{n} 3"
        if ok:
            v = f[item.text.split(":", 1)[1]][...]
            group = item.text.split(":", 1)[1].rsplit("/", 1)[0]
            ok = (v.shape == (n, 3) and (v[:, 0] == f[group + "/" + cx][...]).all()
                  and (v[:, 1] == f[group + "/" + cy][...]).all() and (v[:, 2] == 0).all())
ok = ok and abs(f[grids[-1].find("Attribute[@Name='displacement']/DataItem").text.split(":", 1)[1]][:, 1]).max() > 0
sys.exit(0 if ok else 1)
PY
then echo "ok: a plate runs alone, closes its energy balance and writes XDMF (displacement, velocity as vectors)"; passed=$((passed + 1))
else echo "FAIL: plate run: exit $rc $(cat "$TMP/err") $(tail -n 2 "$TMP/run.log")"; failed=$((failed + 1)); fi
"$UNDEX" gauges "$TMP/out-plate" --name P2 > "$TMP/g.csv" 2> "$TMP/err"
if [ "$(head -n 1 "$TMP/g.csv")" = "t,u_x,u_y,v_x,v_y,a_x,a_y,stress_xx,stress_yy,stress_zz,stress_xy,peeq" ] &&
    [ "$(wc -l < "$TMP/g.csv")" -gt 10 ]; then
    echo "ok: plate gauge as CSV"; passed=$((passed + 1))
else echo "FAIL: plate gauge: $(head -n 2 "$TMP/g.csv") $(cat "$TMP/err")"; failed=$((failed + 1)); fi

if /usr/bin/python3 "$(dirname "$0")/../../cases/plot_structure.py" "$TMP/out-plate" > /dev/null 2> "$TMP/err" &&
    [ -s "$TMP/out-plate/structure.png" ]; then
    echo "ok: plot_structure.py draws the plate run"; passed=$((passed + 1))
else echo "FAIL: plot_structure.py: $(cat "$TMP/err")"; failed=$((failed + 1)); fi

BASE=plate.in bad plate-missing '/^  plate/d' 3 'structure.plate'
BASE=plate.in bad foam-1d-in-2d 's/deshpande_fleck { rho: 430 E: 1e9 nu: 0.3 eps_p: \[0, 0.5, 0.75\] sigma_c: \[4e6, 4.2e6, 40e6\] }/foam_1d { rho: 236 E: 1e9 sigma_pl: 1.5e6 eps_d: 0.8 E_lock: 2e11 }/' 7 'structure.layers[1].material'
BASE=plate.in bad plate-zero-element 's/span: 0.5 element_size: 0.01/span: 0.5 element_size: 0/' 9 'structure.plate.element_size'
BASE=plate.in bad plate-span-below-element 's/span: 0.5 element_size: 0.01/span: 0.005 element_size: 0.01/' 9 'structure.plate.span'
BASE=plate.in bad axis-not-symmetry 's/left { type: SYMMETRY }/left { type: FREE }/' 9 'structure.plate.left.type'
BASE=plate.in bad gauge-outside-plate 's/x: 0 y: 0.05/x: 0.6 y: 0.05/' 11 'structure.gauges[0].x'
BASE=plate.in bad gauge-below-plate 's/x: 0 y: 0.05/x: 0 y: 0.06/' 11 'structure.gauges[0].y'
BASE=plate.in bad kinematics-in-2d 's/back { type: FREE }/back { type: FREE } kinematics: "uniaxial_strain"/' 11 'structure.kinematics'
BASE=plate.in bad plate-dt-above-stable 's/back { type: FREE }/back { type: FREE } dt: 1e-5/' 11 'structure.dt'

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
