#!/usr/bin/env bash
# The command line of undex and of the solver executables:
#   - every command and every solver has --help: exit status 0 and a usage on stdout;
#   - an unknown option or a misspelt one (--bogus, --sett, --out) is refused with exit status 64 and a
#     message naming it, as is a missing CASE;
#   - -o/--output DIR puts the outputs in DIR: a fluid run alone, a structure run alone, and coupled runs of
#     the fluid with undex-rigid and with undex-solid (so that every solver honours it); nothing goes to the
#     case's own output directory;
#   - undex check on a good case prints each solver's summary line (the output directory of -o in it) and on
#     a bad one a single error line with exit status 1; each solver's --check prints its own summary;
#   - undex sample (undex-fluid --sample) and undex options (both solvers' --options) still work.
#   usage: command_line.sh UNDEX_BINARY BIN_DIR CASES_DIR
set -u
UNDEX=$1
BIN=$2
CASES=$3
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
cd "$TMP" || exit 2 # the cases' own output directories are relative: they would appear here
passed=0
failed=0
pass() { echo "ok: $1"; passed=$((passed + 1)); }
fail() { echo "FAIL: $1"; failed=$((failed + 1)); }

# expect_help LABEL COMMAND...: exit status 0 and "Usage:" on stdout.
expect_help() {
    local label=$1
    shift
    "$@" > "$TMP/stdout" 2> "$TMP/stderr"
    local rc=$?
    if [ $rc -eq 0 ] && grep -q "^Usage: " "$TMP/stdout"; then pass "$label --help"
    else fail "$label --help: exit $rc, $(head -c 300 "$TMP/stdout" | tr '\n' '|') $(tr '\n' '|' < "$TMP/stderr")"; fi
}

# expect_usage LABEL WORD COMMAND...: exit status 64 and WORD on stderr.
expect_usage() {
    local label=$1 word=$2
    shift 2
    "$@" > "$TMP/stdout" 2> "$TMP/stderr"
    local rc=$?
    if [ $rc -eq 64 ] && grep -qF -- "$word" "$TMP/stderr"; then pass "$label: $(head -n 1 "$TMP/stderr")"
    else fail "$label: exit $rc (expected 64), stderr: $(tr '\n' '|' < "$TMP/stderr")"; fi
}

# --- --help everywhere.
expect_help "undex" "$UNDEX" --help
for sub in check run sample gauges options conform; do
    expect_help "undex $sub" "$UNDEX" "$sub" --help
done
for solver in undex-fluid undex-solid undex-rigid; do
    expect_help "$solver" "$BIN/$solver" --help
done
"$UNDEX" run --help > "$TMP/stdout"
if grep -q -- "-o,--output DIR" "$TMP/stdout" && grep -q -- "--set KEY=VALUE" "$TMP/stdout"; then pass "undex run --help lists --set and -o"
else fail "undex run --help: $(tr '\n' '|' < "$TMP/stdout")"; fi

# --- Usage errors: exit status 64, the bad option named.
SOD="$CASES/sod_1d.case"
expect_usage "undex without a command" "subcommand" "$UNDEX"
expect_usage "undex nosuch" "'nosuch'" "$UNDEX" nosuch
expect_usage "undex check --bogus" "--bogus" "$UNDEX" check "$SOD" --bogus
expect_usage "undex check --sett" "--sett" "$UNDEX" check "$SOD" --sett end_time=1
expect_usage "undex check without CASE" "CASE" "$UNDEX" check
expect_usage "undex run --bogus" "--bogus" "$UNDEX" run "$SOD" --bogus
expect_usage "undex run --out" "--out" "$UNDEX" run "$SOD" --out "$TMP/never"
expect_usage "undex run --tcp --endpoint" "--endpoint" "$UNDEX" run "$SOD" --tcp --endpoint ipc:///tmp/x
expect_usage "undex sample --bogus" "--bogus" "$UNDEX" sample "$TMP" --time 0 --line "0,0 1,0" --points 2 --bogus
expect_usage "undex sample without --points" "--points" "$UNDEX" sample "$TMP" --time 0 --line "0,0 1,0"
expect_usage "undex gauges --bogus" "--bogus" "$UNDEX" gauges "$TMP" --bogus
expect_usage "undex options --bogus" "--bogus" "$UNDEX" options --bogus
expect_usage "undex conform --bogus" "--bogus" "$UNDEX" conform --bogus -- /bin/true
expect_usage "undex conform without COMMAND" "COMMAND" "$UNDEX" conform
for solver in undex-fluid undex-solid undex-rigid; do
    expect_usage "$solver --bogus" "--bogus" "$BIN/$solver" "$SOD" --bogus
    expect_usage "$solver --sett" "--sett" "$BIN/$solver" "$SOD" --sett end_time=1
    expect_usage "$solver --out" "--out" "$BIN/$solver" --check "$SOD" --out "$TMP/never"
    expect_usage "$solver without CASE" "CASE" "$BIN/$solver"
done
expect_usage "undex-fluid --sample without --time" "--time" "$BIN/undex-fluid" --sample "$TMP" --line "0,0 1,0" --points 2
expect_usage "undex-solid --sample (the fluid's only)" "--sample" "$BIN/undex-solid" --sample "$TMP"
[ ! -e "$TMP/never" ] && [ ! -e "$TMP/out/sod_1d" ] && pass "usage errors wrote nothing" || fail "a usage error wrote output"

# --- -o DIR: the outputs go to DIR (and nothing to the case's own directory, relative to this one).
run_to() { # LABEL CASE END_TIME FILE...: undex run CASE -o $TMP/LABEL writes every FILE there
    local label=$1 case=$2 end=$3
    shift 3
    "$UNDEX" run "$CASES/$case" --set end_time="$end" -o "$TMP/$label" > "$TMP/$label.log" 2>&1
    local rc=$? missing="" f
    for f in "$@"; do [ -f "$TMP/$label/$f" ] || missing+=" $f"; done
    if [ $rc -eq 0 ] && [ -z "$missing" ]; then pass "undex run $case -o DIR writes $* in DIR"
    else fail "undex run $case -o DIR: exit $rc, missing:$missing; $(tail -n 3 "$TMP/$label.log" | tr '\n' '|')"; fi
}
run_to fluid-alone sod_1d.case 1e-3 fluid.h5 fluid.xmf
run_to structure-alone sandwich_column_1d.case 1e-5 solid.h5
run_to fluid-rigid taylor_plate_1d.case 2e-5 fluid.h5 solid.h5 fluid.log solid.log
run_to fluid-solid sandwich_shock_1d.case 2e-5 fluid.h5 solid.h5 fluid.log solid.log
"$UNDEX" run "$CASES/sod_1d.case" --set end_time=1e-3 --output "$TMP/long-form" > /dev/null 2>&1
[ -f "$TMP/long-form/fluid.h5" ] && pass "--output DIR (long form)" || fail "--output DIR: no $TMP/long-form/fluid.h5"
"$BIN/undex-fluid" "$CASES/sod_1d.case" --set end_time=1e-3 --set output.directory="$TMP/elsewhere" -o "$TMP/fluid-o" > /dev/null 2>&1
[ -f "$TMP/fluid-o/fluid.h5" ] && [ ! -e "$TMP/elsewhere" ] && pass "undex-fluid -o DIR wins over --set output.directory" ||
    fail "undex-fluid -o DIR after --set output.directory"
[ ! -e "$TMP/out" ] && pass "-o: nothing in the cases' own output directories" || fail "-o: $TMP/out was written: $(ls -R "$TMP/out")"

# --- undex check: each solver's summary on a good case, one error line on a bad one.
"$UNDEX" check "$CASES/sandwich_shock_1d.case" -o "$TMP/checked" > "$TMP/stdout" 2> "$TMP/stderr"
rc=$?
if [ $rc -eq 0 ] && [ ! -s "$TMP/stderr" ] && grep -q "sandwich_shock_1d.case: ok: structure of 3 layer(s), 42 elements, time step" "$TMP/stdout" &&
    grep -q "sandwich_shock_1d.case: ok: PLANAR_1D, 350 cells, degree 1, .* output to $TMP/checked$" "$TMP/stdout" && [ ! -e "$TMP/checked" ]; then
    pass "undex check on a coupled case: both summaries, -o DIR in them, nothing written"
else fail "undex check sandwich_shock_1d: exit $rc $(tr '\n' '|' < "$TMP/stdout") $(tr '\n' '|' < "$TMP/stderr")"; fi
"$UNDEX" check "$SOD" --set numerics.cfl=7 > "$TMP/stdout" 2> "$TMP/stderr"
rc=$?
if [ $rc -eq 1 ] && [ "$(wc -l < "$TMP/stderr")" -eq 1 ] && grep -q "^undex: error: .*numerics.cfl" "$TMP/stderr"; then
    pass "undex check on a bad case: $(cat "$TMP/stderr")"
else fail "undex check on a bad case: exit $rc, $(tr '\n' '|' < "$TMP/stderr")"; fi
"$UNDEX" check "$TMP/nosuch.case" > "$TMP/stdout" 2> "$TMP/stderr"
[ $? -eq 1 ] && grep -q "^undex: error: .*nosuch.case" "$TMP/stderr" && pass "undex check on a missing file" ||
    fail "undex check on a missing file: $(cat "$TMP/stderr")"
for c in "undex-fluid sod_1d.case ok: PLANAR_1D, 200 cells" "undex-solid sandwich_shock_1d.case ok: structure of 3 layer(s)" \
    "undex-rigid taylor_plate_1d.case ok: structure rigid plate of 100 kg/m² (undex-rigid)"; do
    read -r solver case summary <<< "$c"
    "$BIN/$solver" --check "$CASES/$case" > "$TMP/stdout" 2> "$TMP/stderr"
    [ $? -eq 0 ] && grep -qF "$case: $summary" "$TMP/stdout" && pass "$solver --check: $(cat "$TMP/stdout")" ||
        fail "$solver --check $case: $(cat "$TMP/stdout" "$TMP/stderr")"
done
"$BIN/undex-fluid" --check "$SOD" --set numerics.cfl=7 > "$TMP/stdout" 2> "$TMP/stderr"
[ $? -eq 1 ] && grep -q "^undex-fluid: error: .*numerics.cfl" "$TMP/stderr" && pass "undex-fluid --check on a bad case: exit 1" ||
    fail "undex-fluid --check on a bad case: $(cat "$TMP/stderr")"

# --- undex sample and undex options.
"$UNDEX" sample "$TMP/fluid-alone" --time 1e-3 --line "0.1,0 0.9,0" --points 3 --fields rho,p > "$TMP/stdout" 2> "$TMP/stderr"
if [ $? -eq 0 ] && [ "$(sed -n 2p "$TMP/stdout")" = "x,y,rho,p" ] && [ "$(wc -l < "$TMP/stdout")" -eq 5 ] &&
    grep -q "^0.1,0,1,1$" "$TMP/stdout"; then pass "undex sample: header and 3 rows, the left state at x = 0.1"
else fail "undex sample: $(tr '\n' '|' < "$TMP/stdout") $(cat "$TMP/stderr")"; fi
expect_usage "undex sample --fields rho,q" "'q'" "$UNDEX" sample "$TMP/fluid-alone" --time 0 --line "0,0 1,0" --points 2 --fields rho,q
"$UNDEX" options > "$TMP/stdout" 2> "$TMP/stderr"
if [ $? -eq 0 ] && grep -q "^numerics.indicator:" "$TMP/stdout" && grep -q "^structure.kinematics:" "$TMP/stdout" &&
    grep -q "^boundary type:" "$TMP/stdout" && grep -q "^structure face type:" "$TMP/stdout"; then
    pass "undex options: the fluid's and the structure's choices"
else fail "undex options: $(tr '\n' '|' < "$TMP/stdout") $(cat "$TMP/stderr")"; fi

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
