#!/bin/bash
# The outputs of a coupled 2D run open in ParaView (tests/cli/paraview_outputs.py, run by pvbatch from Debian's
# paraview and python3-paraview): the structure deformed, displacement and velocity as point vectors that Warp
# By Vector takes back to the reference nodes, the fluid's cell fields. Skipped (exit status 77) where pvbatch
# or ParaView's Python modules are not installed.
#   paraview_outputs.sh UNDEX TESTS_DIR
set -u
undex=$1
tests=$2
if ! command -v pvbatch > /dev/null || ! pvbatch -c "import paraview.simple" > /dev/null 2>&1; then
    echo "skipped: pvbatch with ParaView's Python modules is not installed (apt-get install paraview python3-paraview)"
    exit 77
fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# tests/cases/plate_2d.case with its back face free: the water's 1e5 Pa on the front moves the plate.
if ! "$undex" run "$tests/cases/plate_2d.case" --set structure.back.type=FREE --set end_time=2e-4 -o "$dir/out" \
    > "$dir/run.log" 2>&1; then
    echo "FAIL: the run failed"; tail -n 5 "$dir/run.log"; exit 1
fi
cd "$dir" && timeout 300 pvbatch "$tests/cli/paraview_outputs.py" "$dir/out"
