#!/usr/bin/env bash
# Bad case files must be rejected before anything runs, with one error line that names the file, the line
# and the field:
#   undex: error: FILE:LINE:COL: FIELD.PATH: message
# For `run`, nothing may be written: the output directory must not exist afterwards.
#
#   usage: bad_cases.sh UNDEX_BINARY CASES_DIR
#
# Every broken case is generated from the valid minimal case below, in a fresh temporary directory. The
# valid case (text and JSON) and the shipped cases in CASES_DIR are checked too, so that a broken checker
# is told apart from a broken case.
set -u

if [ $# -ne 2 ]; then
    echo "usage: $0 UNDEX_BINARY CASES_DIR" >&2
    exit 2
fi
UNDEX=$1
CASES=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

passed=0
failed=0
pass() { echo "ok: $1"; passed=$((passed + 1)); }
fail() { echo "FAIL: $1"; failed=$((failed + 1)); }

# The valid minimal case. Line numbers matter: the tests below expect errors on these lines.
#  1 comment, 4 domain, 5 materials, 6 regions[0], 7 regions[1], 12 numerics, 13 end_time, 14 output.
# @OUT@ is replaced by a per-case output directory inside $TMP.
cat > "$TMP/minimal.in" <<'EOF'
# minimal valid 1D case: Sod's shock tube on 20 cells
name: "minimal"
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
output { directory: "@OUT@" }
EOF

# make_case NAME [SED_EXPRESSION]: writes $TMP/NAME.case with output directory $TMP/out-NAME.
make_case() {
    local name=$1 expr=${2:-}
    sed -e "$expr" -e "s|@OUT@|$TMP/out-$name|" "$TMP/minimal.in" > "$TMP/$name.case"
}

# expect_error LABEL OUTDIR PATTERN... -- COMMAND...
# Runs COMMAND and asserts: exit status 1, stderr is exactly one line "undex: error: ...", stderr
# contains every PATTERN (fixed strings), and OUTDIR does not exist afterwards (when OUTDIR is not "").
expect_error() {
    local label=$1 outdir=$2
    shift 2
    local patterns=()
    while [ $# -gt 0 ] && [ "$1" != "--" ]; do
        patterns+=("$1")
        shift
    done
    shift
    "$@" > "$TMP/stdout" 2> "$TMP/stderr"
    local rc=$? problems="" lines
    [ $rc -eq 1 ] || problems+=" exit status $rc (expected 1);"
    lines=$(wc -l < "$TMP/stderr")
    [ "$lines" -eq 1 ] || problems+=" stderr has $lines lines (expected 1);"
    [ "$(grep -c '^undex: error: ' "$TMP/stderr")" -eq 1 ] || problems+=" no single 'undex: error:' line;"
    local p
    for p in "${patterns[@]}"; do
        grep -qF -- "$p" "$TMP/stderr" || problems+=" message lacks '$p';"
    done
    if [ -n "$outdir" ] && [ -e "$outdir" ]; then problems+=" $outdir was created;"; fi
    if [ -z "$problems" ]; then
        pass "$label: $(head -n 1 "$TMP/stderr")"
    else
        fail "$label:$problems stderr: $(tr '\n' '|' < "$TMP/stderr") stdout: $(head -c 300 "$TMP/stdout" | tr '\n' '|')"
    fi
}

# expect_ok LABEL COMMAND...: exit status 0 and nothing on stderr.
expect_ok() {
    local label=$1
    shift
    "$@" > "$TMP/stdout" 2> "$TMP/stderr"
    local rc=$?
    if [ $rc -eq 0 ] && [ ! -s "$TMP/stderr" ]; then
        pass "$label"
    else
        fail "$label: exit status $rc, stderr: $(tr '\n' '|' < "$TMP/stderr")"
    fi
}

# bad_case NAME SED_EXPRESSION LINE FIELD [run]: the case must fail `check` (and `run`) naming FILE:LINE:
# and FIELD.
bad_case() {
    local name=$1 expr=$2 line=$3 field=$4 also_run=${5:-}
    make_case "$name" "$expr"
    local file="$TMP/$name.case" out="$TMP/out-$name"
    expect_error "check $name" "$out" "$file:$line:" "$field" -- "$UNDEX" check "$file"
    if [ "$also_run" = run ]; then
        expect_error "run $name" "$out" "$file:$line:" "$field" -- "$UNDEX" run "$file"
    fi
}

# --- The valid minimal case passes (text and JSON), and runs (so that "nothing written" means something).
make_case valid
expect_ok "check valid minimal case" "$UNDEX" check "$TMP/valid.case"
"$UNDEX" run "$TMP/valid.case" > "$TMP/run.log" 2>&1
rc=$?
if [ $rc -eq 0 ] && [ -f "$TMP/out-valid/fluid.h5" ]; then
    pass "run valid minimal case writes $TMP/out-valid/fluid.h5"
else
    fail "run valid minimal case: exit status $rc, $(tail -n 3 "$TMP/run.log" | tr '\n' '|')"
fi

cat > "$TMP/valid.json" <<EOF
{
  "name": "minimal",
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
  "output": { "directory": "$TMP/out-json" }
}
EOF
expect_ok "check valid minimal case as JSON" "$UNDEX" check "$TMP/valid.json"

# The shipped cases pass check (output redirected into $TMP so that the check does not depend on the cwd).
for c in "$CASES"/*.case; do
    [ -e "$c" ] || continue
    expect_ok "check shipped case $(basename "$c")" "$UNDEX" check "$c" --set "output.directory=$TMP/out-shipped"
done

# --- Broken cases.
# Unknown field (in domain, line 4).
bad_case unknown-field 's/cells_x: 20/cells_x: 20 nosuch: 3/' 4 nosuch run
# Wrong type: a string where a number is expected (numerics.cfl, line 12).
bad_case wrong-type 's/cfl: 0.2/cfl: "fast"/' 12 cfl run
# Negative density (regions[1], line 7).
bad_case negative-density 's/rho: 0.125/rho: -0.125/' 7 'regions[1].rho' run
# Pressure below −P∞: stiffened gas with p_inf = 1e8 and p = −2e8 (regions[1], line 7).
bad_case pressure-below-pinf 's/gamma: 1.4 }/gamma: 1.4 p_inf: 1e8 }/; s/p: 0.1 }/p: -2e8 }/' 7 'regions[1].p' run
# CFL out of range (line 12).
bad_case cfl-too-large 's/cfl: 0.2/cfl: 1.5/' 12 numerics.cfl run
bad_case cfl-zero 's/cfl: 0.2/cfl: 0/' 12 numerics.cfl
# A region naming an unknown material (regions[1], line 7).
bad_case unknown-material 's/material: "air" box/material: "steam" box/' 7 'regions[1].material' run
# A missing required field inside a message: regions[1].p (the line of regions[1], 7).
bad_case missing-region-p 's/ rho: 0.125 p: 0.1 }/ rho: 0.125 }/' 7 'regions[1].p' run
# An INCIDENT side needs its incident history (line 9), and every pressure of it must be one the water of
# regions[0] can hold (the air's lowest is 0: p_ambient + p_peak = −1 is refused, naming p_peak).
INCIDENT='s/x_min { type: TRANSMISSIVE }/x_min { type: INCIDENT pressure { p_ambient: 1 p_peak: 0.5 theta: 0.01 } }/'
make_case incident "$INCIDENT"
expect_ok "check valid INCIDENT side" "$UNDEX" check "$TMP/incident.case"
bad_case incident-without-history 's/x_min { type: TRANSMISSIVE }/x_min { type: INCIDENT }/' 9 \
    "boundaries.x_min: an INCIDENT boundary needs a 'pressure' history" run
bad_case incident-below-floor "$INCIDENT; s/p_peak: 0.5/p_peak: -2/" 9 'boundaries.x_min.pressure.p_peak' run
bad_case history-on-a-wall 's/x_min { type: TRANSMISSIVE }/x_min { type: WALL pressure { p_ambient: 1 } }/' 9 \
    'boundaries.x_min.pressure: a pressure history is only used by PRESSURE and INCIDENT boundaries'
# An ABSORBING side needs its layer, of at least 2 cells (Δx = 0.05 m here); no other side has one.
make_case absorbing 's/x_max { type: TRANSMISSIVE }/x_max { type: ABSORBING layer: 0.2 }/'
expect_ok "check valid ABSORBING side" "$UNDEX" check "$TMP/absorbing.case"
bad_case absorbing-without-layer 's/x_max { type: TRANSMISSIVE }/x_max { type: ABSORBING }/' 10 \
    "boundaries.x_max: an ABSORBING boundary needs 'layer'" run
bad_case absorbing-thin 's/x_max { type: TRANSMISSIVE }/x_max { type: ABSORBING layer: 0.07 }/' 10 \
    'boundaries.x_max.layer: the layer (0.07 m) must be at least 2 cells (0.1 m)' run
bad_case layer-on-a-wall 's/x_min { type: TRANSMISSIVE }/x_min { type: WALL strength: 2 }/' 9 \
    'boundaries.x_min.strength: only an ABSORBING boundary has a layer'

# Two materials (gas in the box): the interface fields are checked (line 12 holds numerics and interface).
TWO='s/stiffened_gas { gamma: 1.4 } }/stiffened_gas { gamma: 1.4 } } materials { name: "gas" stiffened_gas { gamma: 1.4 } }/; s/material: "air" box/material: "gas" box/'
make_case two-materials "$TWO"
expect_ok "check valid two-material case" "$UNDEX" check "$TMP/two-materials.case"
bad_case interface-method "$TWO; s/cfl: 0.2 }/cfl: 0.2 } interface { method: \"magic\" }/" 12 interface.method run
bad_case interface-riemann "$TWO; s/cfl: 0.2 }/cfl: 0.2 } interface { riemann: \"guess\" }/" 12 interface.riemann
bad_case interface-reinit "$TWO; s/cfl: 0.2 }/cfl: 0.2 } interface { reinit_every: 0 }/" 12 interface.reinit_every
# With two materials every region after the first needs a shape: it shapes the interface (line 6).
bad_case shapeless-second-material "$TWO; s/^regions { material: \"air\" rho: 1 p: 1 }/& regions { material: \"gas\" rho: 2 p: 2 }/" 6 'regions[1]' run
# A third material: steam in regions[1] and gas in regions[2] besides the air of regions[0] (line 7).
bad_case third-material "$TWO; s/^regions { material: \"air\" rho: 1 p: 1 }/& regions { material: \"steam\" box { x_max: 0.1 } rho: 2 p: 2 }/; s/stiffened_gas { gamma: 1.4 } } materials { name: \"gas\"/stiffened_gas { gamma: 1.4 } } materials { name: \"steam\" stiffened_gas { gamma: 1.3 } } materials { name: \"gas\"/" 7 'regions[2].material'

# An output directory that cannot be written (line 14).
make_case unwritable-output 's|"@OUT@"|"/proc/undex-cannot-write"|'
f="$TMP/unwritable-output.case"
expect_error "check unwritable-output" /proc/undex-cannot-write "$f:14:" output.directory -- "$UNDEX" check "$f"
expect_error "run unwritable-output" /proc/undex-cannot-write "$f:14:" output.directory -- "$UNDEX" run "$f"
# An output directory below a regular file (cannot be created by anybody, root included).
make_case output-below-file "s|\"@OUT@\"|\"$TMP/a-file/out\"|"
: > "$TMP/a-file"
f="$TMP/output-below-file.case"
expect_error "check output-below-file" "$TMP/a-file/out" "$f:14:" output.directory -- "$UNDEX" check "$f"
expect_error "run output-below-file" "$TMP/a-file/out" "$f:14:" output.directory -- "$UNDEX" run "$f"

# A missing required top-level field (end_time): there is no line to name, so the message must name the
# file and the field.
make_case missing-end-time '/^end_time:/d'
f="$TMP/missing-end-time.case"
expect_error "check missing-end-time" "$TMP/out-missing-end-time" "$f" end_time -- "$UNDEX" check "$f"
expect_error "run missing-end-time" "$TMP/out-missing-end-time" "$f" end_time -- "$UNDEX" run "$f"

# --- Bad overrides: the message names the override instead of a line.
make_case set-cfl
f="$TMP/set-cfl.case"
expect_error "check --set numerics.cfl=2" "$TMP/out-set-cfl" "--set numerics.cfl" -- \
    "$UNDEX" check "$f" --set numerics.cfl=2
expect_error "run --set numerics.cfl=2" "$TMP/out-set-cfl" "--set numerics.cfl" -- \
    "$UNDEX" run "$f" --set numerics.cfl=2
expect_error "check --set numerics.nosuch=1" "$TMP/out-set-cfl" "--set numerics.nosuch" -- \
    "$UNDEX" check "$f" --set numerics.nosuch=1
expect_error "run --set numerics.nosuch=1" "$TMP/out-set-cfl" "--set numerics.nosuch" -- \
    "$UNDEX" run "$f" --set numerics.nosuch=1

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
