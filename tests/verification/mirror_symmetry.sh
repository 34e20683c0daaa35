#!/bin/bash
# Symmetric problems stay symmetric: each run's p, ρ and DG coefficients at every output equal their mirror
# image (tests/tools/mirror_error.py: max-norm difference relative to the largest value).
#   riemann_2d at 64², degree 2, limiter active, to t = 0.4: mirror about x = y;
#   free_field_2d (case 4.4, two fluids with a level set, degree 1 as written) at 64² and 100², to t = 1e-4:
#     mirrors about x = 0, y = 0 and x = y (100 cells: dx = 0.02 is not a binary fraction);
#   cavitation_tube_1d (case 4.2), 400 cells, to t = 1e-4: mirror about x = 0.5;
#   the case files use the minmod limiter and the modified GFM; the paper's WENO limiter, and its real GFM
#   at degree 2, and the original GFM are run as well; an axisymmetric blast about z = 0; waves entering by
#   four INCIDENT sides.
# One thread per run (CTest runs two tests at once on the two cores), but free_field_100 on two.
# Bound 1e-10 (issue 13); every operator is written so that mirror-image cells round alike, and the runs
# are exact mirror images today (difference 0), so any operator that breaks the symmetry, even by one
# rounding, is caught: the WENO limiter amplifies a 1e-16 asymmetry to 1e-2 by t = 0.4 (riemann_2d).
set -u
undex=$1
cases=$2
tools=$3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
pass=0 fail=0
run() { # NAME CASE MIRRORS [--set ...]
    local name=$1 case=$2 mirrors=$3
    shift 3
    if ! "$undex" run "$cases/$case.case" -o "$dir/$name" --set numerics.threads=1 "$@" >"$dir/$name.log" 2>&1; then
        cat "$dir/$name.log"
        echo "FAIL: $name: run failed"
        fail=$((fail + 1))
        return
    fi
    /usr/bin/python3 "$tools/mirror_error.py" "$dir/$name" --mirrors "$mirrors" --coefficients
    local worst
    worst=$(/usr/bin/python3 "$tools/mirror_error.py" "$dir/$name" --mirrors "$mirrors" --coefficients --max)
    if /usr/bin/python3 -c "import sys; sys.exit(0 if float('$worst') <= 1e-10 else 1)"; then
        echo "ok: $name: mirror error $worst <= 1e-10"
        pass=$((pass + 1))
    else
        echo "FAIL: $name: mirror error $worst > 1e-10"
        fail=$((fail + 1))
    fi
}
run riemann_2d riemann_2d diag --set domain.cells_x=64 --set domain.cells_y=64 --set end_time=0.4
run free_field_64 free_field_2d diag,x,y --set domain.cells_x=64 --set domain.cells_y=64
run free_field_100 free_field_2d diag,x,y --set domain.cells_x=100 --set domain.cells_y=100 --set numerics.threads=2
run cavitation_tube cavitation_tube_1d x
# The other limiter and interface methods.
run riemann_2d_weno riemann_2d diag --set domain.cells_x=64 --set domain.cells_y=64 --set end_time=0.4 \
    --set numerics.limiter=weno
run free_field_real free_field_2d diag,x,y --set domain.cells_x=64 --set domain.cells_y=64 \
    --set interface.method=real_gfm --set numerics.limiter=weno --set numerics.degree=2 --set numerics.cfl=0.2
run free_field_original free_field_2d diag,x,y --set domain.cells_x=64 --set domain.cells_y=64 \
    --set interface.method=original_gfm
# Axisymmetric geometry (the geometric source): a blast at the origin (tests/cases), mirror about z = 0.
cases=$tools/../cases run axisymmetric_blast axisymmetric_blast y
# INCIDENT sides (fluid/boundary.hpp incident_ghost): a 50 MPa wave enters by all four sides, the waves
# cross (corners, 2D interaction) and leave through the opposite sides; mirrors about x = 0, y = 0, x = y.
cat >"$dir/incident.case" <<'CASE'
name: "incident" geometry: PLANAR_2D
domain { x_min: -1 x_max: 1 cells_x: 40 y_min: -1 y_max: 1 cells_y: 40 }
materials { name: "water" tait { } }
regions { material: "water" rho: 1000 p: 1e5 }
boundaries { x_min { type: INCIDENT pressure { p_peak: 5e7 theta: 2e-4 } }
             x_max { type: INCIDENT pressure { p_peak: 5e7 theta: 2e-4 } }
             y_min { type: INCIDENT pressure { p_peak: 5e7 theta: 2e-4 } }
             y_max { type: INCIDENT pressure { p_peak: 5e7 theta: 2e-4 } } }
end_time: 1.5e-3
output { times: [5e-4, 1e-3] }
CASE
cases=$dir run incident_sides incident diag,x,y
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
