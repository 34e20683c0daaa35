#!/usr/bin/python3
"""Water on both faces of a plate thinner than the ghost band (issue 15, item 2): a fixed plate 1.5 cells
thick spans a 2D channel with different still-water pressures below and above it. Every cell of the plate
is a ghost cell of both faces, so one shared ghost state per cell would let the two pressures leak through
the plate; with one ghost state per face each side keeps its own pressure.

Set-up: Tait water, [-0.5, 0.5] x [0, 1] m in 50 x 50 cells (dx = 0.02 m), walls all round; the plate (a
prescribed-motion solver at rest, tests/coupling/moving_plate.py --speed 0) from x = -0.5 to 0.5, faces at
y = 0.575 and 0.605 (1.5 cells; the cell of y in [0.58, 0.60] lies inside it, the cells below and above
are real for one face each and ghost cells of the other). Below: p0 = 1e5 Pa; above: p1 = 1.0478 MPa
(rho 1000.4 on the Tait curve). Degree 1, 2e-4 s (about 80 steps: a sound wave crosses 0.31 m).

Checks: every water cell keeps its side's pressure to 1e-9 of p1 - p0 (the states are uniform and at rest,
so the only change would be a leak, of order 1e-2 or more; measured 5.4e-13, rounding) and both sides took the same steps
with dt = min(dt_f, dt_s) (tests/support/checks.py coupled_steps).

    thin_plate_2d.py [--build DIR] [--work DIR]
"""
import argparse
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "support"))
from checks import check, coupled_steps, finish  # noqa: E402

P0, RHO1 = 1e5, 1000.4


def main():
    root = os.path.normpath(os.path.join(HERE, "..", ".."))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(root, "build"))
    ap.add_argument("--work")
    a = ap.parse_args()
    import h5py
    import numpy as np

    work = a.work or os.path.join(a.build, "tests", "coupled", "thin_plate_2d")
    os.makedirs(work, exist_ok=True)
    B, A, G = 3.31e8, 1e5, 7.15
    p1 = A + B * ((RHO1 / 1000.0) ** G - 1)
    solver = (f"/usr/bin/python3 {HERE}/moving_plate.py --faces 2 --nodes 51 --xc 0 --yc 0.59 --length 1.0 "
              f"--thickness 0.03 --speed 0 --history {work}/moving_plate.h5 --proto-dir {a.build}/python")
    case = f"""name: "thin_plate_2d"
geometry: PLANAR_2D
domain {{ x_min: -0.5 x_max: 0.5 cells_x: 50 y_min: 0 y_max: 1 cells_y: 50 }}
materials {{ name: "water" tait {{ gamma: {G!r} B: {B!r} A: {A!r} rho0: 1000 }} }}
regions {{ material: "water" rho: 1000 p: {P0!r} }}
regions {{ material: "water" box {{ x_min: -1 x_max: 1 y_min: 0.59 y_max: 2 }} rho: {RHO1!r} p: {p1!r} }}
boundaries {{ x_min {{ type: WALL }} x_max {{ type: WALL }} y_min {{ type: WALL }} y_max {{ type: WALL }} }}
numerics {{ degree: 1 threads: 1 }}
structure {{ command: "{solver}" front {{ type: FLUID }} back {{ type: FLUID }} }}
end_time: 2e-4
output {{ times: [1e-4] directory: "{work}" }}
"""
    path = os.path.join(work, "case.case")
    with open(path, "w") as f:
        f.write(case)
    r = subprocess.run([os.path.join(a.build, "bin", "undex"), "run", path], capture_output=True, text=True)
    check(r.returncode == 0, "the run completes", r.stdout[-2000:] + r.stderr[-2000:])
    if r.returncode != 0:
        finish()
    with h5py.File(os.path.join(work, "fluid.h5")) as f:
        y = f["y"][:]
        for g in f["fields"]:
            p, phi = f["fields"][g]["p"][:], f["fields"][g]["phi_s"][:]
            water = phi < 0
            below = water & (y[:, None] < 0.59)
            above = water & (y[:, None] > 0.59)
            err = max(np.abs(p[below] - P0).max(), np.abs(p[above] - p1).max()) / (p1 - P0)
            check(below.sum() == 50 * 29 and above.sum() == 50 * 20,
                  f"t = {f['fields'][g].attrs['time']:.3g} s: 29 rows of water below the plate, 20 above",
                  f"{below.sum()} cells below, {above.sum()} above")
            check(err <= 1e-9, f"t = {f['fields'][g].attrs['time']:.3g} s: each side keeps its pressure: "
                  f"{err:.2e} of p1 - p0 <= 1e-9")
    problems, summary = coupled_steps(work, os.path.join(work, "moving_plate.h5"), 2e-4, [1e-4, 2e-4])
    check(not problems, "both sides took the same steps, dt = min(dt_f, dt_s): " + summary, "\n".join(problems))
    finish()


if __name__ == "__main__":
    main()
