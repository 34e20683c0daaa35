#!/usr/bin/python3
"""Resolution study of the paper's application (§5): per fluid resolution, the P1 peak pressure, the peak
velocities at P1 and P2 and the final displacements at P1 and P2 of both plates, and whether each quantity
converges (the change between the two finest runs under half the change between the two before).

    undex_convergence.py --steel DIR [DIR ...] --sandwich DIR [DIR ...] [--markdown FILE]

Each DIR is a run's output (fluid.h5, solid.h5) of cases/undex_steel_plate.case or
cases/undex_sandwich_plate.case, coarsest first (e.g. fluid cells 0.04, 0.02, 0.01 m); the fluid cell size
is read from fluid.h5. The P1 pressure is the structure's p_I at the wet node nearest r = 0 (every step); the
velocities and displacements the structure's gauges P1, P2.
"""
import argparse
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from undex_findings import fluid_dx, gauge, p_I_at_centre  # noqa: E402

QUANTITIES = [("P1 peak p_I (MPa)", lambda r: r["p1"].max() / 1e6),
              ("P1 peak v (m/s)", lambda r: r["g1"]["v_y"].max()),
              ("P2 peak v (m/s)", lambda r: r["g2"]["v_y"].max()),
              ("P1 u at the end (mm)", lambda r: r["g1"]["u_y"][-1] * 1e3),
              ("P2 u at the end (mm)", lambda r: r["g2"]["u_y"][-1] * 1e3)]


def load(out):
    _, p1 = p_I_at_centre(out, 0)
    with h5py.File(os.path.join(out, "solid.h5")) as s:
        end = s["gauges/P1/t"][-1]
    return {"dx": fluid_dx(out), "p1": p1, "g1": gauge(out, "P1"), "g2": gauge(out, "P2"), "end": end}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steel", nargs="+", required=True)
    ap.add_argument("--sandwich", nargs="+", required=True)
    ap.add_argument("--markdown")
    a = ap.parse_args()
    lines = []
    for name, dirs in (("steel plate", a.steel), ("sandwich plate", a.sandwich)):
        runs = [load(d) for d in dirs]
        head = "| " + name + " | " + " | ".join(f"fluid {r['dx']:g} m" for r in runs) + " | converging |"
        lines += [head, "|---" * (len(runs) + 2) + "|"]
        for label, f in QUANTITIES:
            v = [f(r) for r in runs]
            verdict = "–"
            if len(v) >= 3:
                d1, d2 = abs(v[-2] - v[-3]), abs(v[-1] - v[-2])
                verdict = f"{'yes' if d2 < 0.5 * d1 else '**no**'} ({d2:.3g} against {d1:.3g})"
            lines.append(f"| {label} | " + " | ".join(f"{x:.4g}" for x in v) + f" | {verdict} |")
        lines.append("")
        if len({round(r["end"], 9) for r in runs}) > 1:
            lines.append(f"(end times differ: {[r['end'] for r in runs]})\n")
    text = "\n".join(lines)
    print(text)
    if a.markdown:
        with open(a.markdown, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
