#!/bin/bash
# undex conform: the three structure solvers of the project conform; misbehaving ones are caught with what
# they got wrong and a non-zero exit status.
#   conform.sh UNDEX BIN_DIR CASES_DIR PYTHON_DIR TESTS_DIR
UNDEX=$1 BIN=$2 CASES=$3 PYDIR=$4 TESTS=$5
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
passed=0 failed=0
expect_ok() { # name, command...
    local name=$1; shift
    if "$UNDEX" conform -- "$@" > "$TMP/out" 2>&1 && grep -q "undex conform: conforming" "$TMP/out"; then
        echo "ok: $name conforms"; passed=$((passed + 1))
    else echo "FAIL: $name: $(cat "$TMP/out")"; failed=$((failed + 1)); fi
}
expect_fail() { # name, pattern, command...
    local name=$1 pattern=$2; shift 2
    "$UNDEX" conform --timeout 3 -- "$@" > "$TMP/out" 2>&1
    local rc=$?
    if [ $rc -ne 0 ] && grep -q -- "$pattern" "$TMP/out"; then
        echo "ok: $name caught ($(grep -c '^FAIL' "$TMP/out") failed checks)"; passed=$((passed + 1))
    else echo "FAIL: $name not caught (exit $rc): $(cat "$TMP/out")"; failed=$((failed + 1)); fi
}
expect_ok undex-solid "$BIN/undex-solid" "$CASES/sandwich_shock_1d.case" --set "output.directory=$TMP/solid"
expect_ok undex-rigid "$BIN/undex-rigid" "$CASES/taylor_plate_1d.case" --set "output.directory=$TMP/rigid"
expect_ok rigid_plate.py /usr/bin/python3 "$TESTS/coupling/rigid_plate.py" --mass 100 --proto-dir "$PYDIR"
# 2D (tests/cases): a plane-strain plate wet on both faces, clamped; the same plate axisymmetric from the axis,
# wet in front only, its rim free; a rigid axisymmetric plate of five nodes.
expect_ok "undex-solid 2D" "$BIN/undex-solid" "$TESTS/cases/plate_2d.case" --set "output.directory=$TMP/solid2d"
expect_ok "undex-solid 2D axisymmetric" "$BIN/undex-solid" "$TESTS/cases/plate_2d.case" \
    --set "output.directory=$TMP/solid2da" --set geometry=AXISYMMETRIC_2D --set structure.plate.left.type=SYMMETRY \
    --set structure.plate.right.type=FREE --set structure.back.type=FREE
expect_ok "undex-rigid 2D" "$BIN/undex-rigid" "$TESTS/cases/rigid_plate_2d.case" --set "output.directory=$TMP/rigid2d"
expect_fail "a 2D solver whose areas are not its face's" \
    "FAIL: Hello: faces.*node 0 of face 0: area 0.1, normal (0, 1), but its face's segments give 0.05, (0, 1)" \
    /usr/bin/python3 "$TESTS/coupling/bad_peer.py" --mode wrong-area-2d --proto-dir "$PYDIR"
expect_fail "a 2D solver whose steps do not start where the last ended" \
    "FAIL: Offers: each step starts where.*step 2, node 0: offered at (0, 0.002) but the Answer of step 1 ended at (0, 0)" \
    /usr/bin/python3 "$TESTS/coupling/bad_peer.py" --mode jumps-2d --proto-dir "$PYDIR"
expect_fail "a solver that ignores the interface condition and the sign" \
    "FAIL: Answers: .*step 1, node 0: p_I = 100000 Pa but p_L − Z_L (u_I − u_L) = 115000 Pa" \
    /usr/bin/python3 "$TESTS/coupling/bad_peer.py" --mode wrong-physics --proto-dir "$PYDIR"
expect_fail "a solver that answers out of turn" "FAIL: keeps to the sequence.*sent Answer of step 3 where Offer of step 3" \
    /usr/bin/python3 "$TESTS/coupling/bad_peer.py" --mode wrong-type --proto-dir "$PYDIR"
expect_fail "a command that never connects" "FAIL: sends a Hello after connecting" /bin/sh -c 'sleep 30'
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
