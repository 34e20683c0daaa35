#!/usr/bin/python3
"""Case 4.3 (cases/sandwich_shock_1d.case): plots of one coupled run, and the impulse sweep of the paper.

One run (after `undex run cases/sandwich_shock_1d.case`):
    plot_sandwich_shock.py out/sandwich_shock_1d
  -> out/sandwich_shock_1d/sandwich_shock.png: the wet-face pressure p_I and velocity u_I (fluid.h5
     /interface), the front and back face velocities and the core's mean plastic compression strain
     (solid.h5), against time.

The sweep (the paper's figure: core plastic compression strain against the impulse I0 = 2 p_m θ):
    plot_sandwich_shock.py --sweep OUT_DIR [--bin build/bin] [--case cases/sandwich_shock_1d.case]
                           [--p-m 5e6,1e7,2e7] [--end-time 2.5e-3] [--jobs 2] [--cells N]
  -> runs the case for each p_m, unsupported (the case as it is: back face under the ambient air pressure)
     and supported (back face FIXED), two runs at a time, and writes OUT_DIR/core_strain.csv (support, p_m,
     I0, core strain, status) and OUT_DIR/core_strain.png.

The core strain is the mean over the core's elements of the plastic compression strain −ε_p,xx at the end
of the run (the last field of solid.h5); the core's elements are those whose centres lie in the middle layer.
"""
import argparse
import concurrent.futures
import csv
import os
import re
import subprocess
import sys

import h5py
import numpy as np


def core_strain(run_dir):
    """Mean plastic compression strain of the middle layer at the last output, and the run's status."""
    with h5py.File(os.path.join(run_dir, "solid.h5"), "r") as f:
        status = f["status"][()].decode()
        layers = (f.attrs["layers"].decode() if isinstance(f.attrs["layers"], bytes) else str(f.attrs["layers"])).split(",")
        last = f["fields"][sorted(f["fields"])[-1]]
        eps = last["plastic_strain_xx"][:]
        xe = f["element_x"][:]
        case = f["case"][()].decode()
    # Layer thicknesses from the case text, in order; the core is layer 1 of 3.
    thick = [float(t) for t in re.findall(r"layers\s*\{[^}]*thickness:\s*([0-9.eE+-]+)", case)]
    if len(thick) != 3 or len(layers) != 3:
        raise SystemExit(f"{run_dir}: expected a three-layer sandwich, got layers {layers}")
    lo, hi = thick[0], thick[0] + thick[1]
    core = (xe > lo) & (xe < hi)
    return float(-eps[core].mean()), status


def plot_run(run_dir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with h5py.File(os.path.join(run_dir, "fluid.h5"), "r") as f:
        i = f["interface"]
        t, p_I, u_I = i["t"][:], i["p_I"][:], i["u_I"][:]
    with h5py.File(os.path.join(run_dir, "solid.h5"), "r") as f:
        g = f["gauges"]
        tg = g["front"]["t"][:]
        v_front, v_back = g["front"]["v"][:], g["back"]["v"][:]
        peeq_core = g["core"]["peeq"][:]
    fig, ax = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    ax[0].plot(t * 1e3, p_I / 1e6)
    ax[0].set_ylabel("wet-face pressure p_I [MPa]")
    ax[1].plot(tg * 1e3, v_front, label="front face")
    ax[1].plot(tg * 1e3, v_back, label="back face")
    ax[1].plot(t * 1e3, u_I, ":", label="u_I (fluid's record)")
    ax[1].set_ylabel("velocity [m/s]")
    ax[1].legend()
    ax[2].plot(tg * 1e3, peeq_core)
    ax[2].set_ylabel("core PEEQ at mid-core")
    ax[2].set_xlabel("t [ms]")
    strain, status = core_strain(run_dir)
    fig.suptitle(f"case 4.3: core plastic compression strain {strain:.4f} ({status})")
    fig.tight_layout()
    out = os.path.join(run_dir, "sandwich_shock.png")
    fig.savefig(out, dpi=110)
    print(f"plot: {out}")


def variant(case_text, p_m, supported, end_time, out, cells=None):
    text = re.sub(r"p_peak:\s*[0-9.eE+-]+", f"p_peak: {p_m!r}", case_text, count=1)
    if cells:
        text = re.sub(r"cells_x:\s*\d+", f"cells_x: {cells}", text, count=1)
    if supported:
        text, n = re.subn(r"back\s*\{\s*type:\s*PRESSURE\s*pressure\s*\{[^}]*\}\s*\}", "back { type: FIXED }", text)
        if n != 1:
            raise SystemExit("the case's back face is not 'back { type: PRESSURE pressure { ... } }'")
    text = re.sub(r"^end_time:.*$", f"end_time: {end_time!r}", text, flags=re.M)
    text = re.sub(r"^output\s*\{.*\}$", f'output {{ interval: {end_time / 5!r} progress_seconds: 30 directory: "{out}" }}',
                  text, flags=re.M)
    return text


def sweep(a):
    case_text = open(a.case).read()
    theta = float(re.search(r"theta:\s*([0-9.eE+-]+)", case_text).group(1))
    runs = []
    for supported in (False, True):
        for p_m in [float(x) for x in a.p_m.split(",")]:
            name = f"{'supported' if supported else 'unsupported'}_{p_m:.3g}"
            out = os.path.abspath(os.path.join(a.sweep, name))
            os.makedirs(out, exist_ok=True)
            path = os.path.join(out, "case.case")
            open(path, "w").write(variant(case_text, p_m, supported, a.end_time, out, a.cells))
            runs.append((supported, p_m, out, path))

    def run(r):
        res = subprocess.run([os.path.join(a.bin, "undex"), "run", r[3]], capture_output=True, text=True)
        return r, res

    rows = []
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        for (supported, p_m, out, _), res in pool.map(run, runs):
            if res.returncode != 0:
                print(res.stdout[-2000:], res.stderr[-2000:], file=sys.stderr)
                raise SystemExit(f"run {out} failed with exit code {res.returncode}")
            strain, status = core_strain(out)
            rows.append(("supported" if supported else "unsupported", p_m, 2 * p_m * theta, strain, status))
            print(f"{rows[-1][0]:>11}  p_m {p_m:9.3g} Pa  I0 {rows[-1][2]:8.1f} Pa s  core strain {strain:.5f}  {status}",
                  flush=True)
    rows.sort()
    with open(os.path.join(a.sweep, "core_strain.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["support", "p_m", "I0", "core_strain", "status"])
        w.writerows(rows)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.5))
    for support, marker in (("unsupported", "o-"), ("supported", "s-")):
        r = [x for x in rows if x[0] == support]
        ax.plot([x[2] for x in r], [x[3] for x in r], marker, label=support)
    ax.set_xlabel("impulse I0 = 2 p_m θ [Pa s]")
    ax.set_ylabel("core plastic compression strain")
    ax.set_title("case 4.3: sandwich plate under a plane shock in water")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(a.sweep, "core_strain.png"), dpi=110)
    print(f"table: {os.path.join(a.sweep, 'core_strain.csv')}\nplot: {os.path.join(a.sweep, 'core_strain.png')}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run_dir", nargs="?", help="output directory of one run of the case")
    ap.add_argument("--sweep", metavar="OUT_DIR", help="run the impulse sweep into OUT_DIR")
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--bin", default=os.path.join(here, "..", "build", "bin"))
    ap.add_argument("--case", default=os.path.join(here, "sandwich_shock_1d.case"))
    ap.add_argument("--p-m", default="5e6,1e7,2e7", help="peak pressures p_m, comma-separated")
    ap.add_argument("--end-time", type=float, default=2.5e-3)
    ap.add_argument("--jobs", type=int, default=2, help="runs at a time")
    ap.add_argument("--cells", type=int, help="water cells instead of the case's")
    a = ap.parse_args()
    if a.sweep:
        sweep(a)
    elif a.run_dir:
        plot_run(a.run_dir)
    else:
        ap.error("give a run directory or --sweep OUT_DIR")


if __name__ == "__main__":
    main()
