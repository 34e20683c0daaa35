#!/usr/bin/python3
"""Stability map of the gas–water interface treatment, in 1D (case 4.1) and 2D (case 4.4 and a bubble near a wall).

    /usr/bin/python3 tests/bench/stability_map.py [--build build] [--out out/bench] [--cells 400] [--only 1d|2d]
                                                  [--degree 1|2]

Degree 2 (the paper's) unless --degree 1 (CFL 0.4 in 2D, the case files' setting; outputs named *_k1.*).

1D, cases/undex_1d.case: sweeps the gas pressure (1e6 … 1e11 Pa) and the gas density (16.3, 163, 1630 kg/m^3:
density ratios 0.0163 … 1.63 against water), for the real, the modified and the original ghost fluid method,
with and without the limiter (WENO or minmod on TVB-troubled cells, or none; the positivity scaling stays on),
at CFL 0.1, 0.2, 0.3, 0.4; degree 2 (or --degree), Tait water, one thread. Each run is classified against
the exact solution of its own states
(build/bin/undex_1d_error); the run ends at 1e-4 s or earlier, when the fastest exact wave has covered 80 %
of the way to the boundary (strong gas pressures drive the shock out of [0, 1] before 1e-4 s):
    ok       completed, shock and interface within 5 cells of the exact positions;
    wrong    completed, but the shock or the interface is off by more than 5 cells;
    stopped  the solver stopped with its clear error (the message is kept in the CSV);
    crash    anything else (a signal, no output) -- there should be none.
Writes OUT/stability_map.csv and OUT/stability_map.png, and prints a summary table.

2D, cases/free_field_2d.case at 100 x 100 (degree 2 and CFL 0.2, or degree 1 and CFL 0.4; one thread): the gas pressure
1e8 … 6e9 Pa (density 1630 kg/m^3), for each method and limiter, in two scenes:
    free  the bubble alone, to 1e-4 s; "ok" when the relative L1 of p along the positive x axis against the
          1D cylindrical bubble of the same states (cases/bubble_1d_cylindrical.case, 4000 cells) is at most
          10 % (twice the largest error of any setting at the paper's pressure, 5 % at 100 x 100), "wrong"
          above;
    wall  the same bubble one radius from a rigid wall (x_max a WALL, 0.5 m from the bubble's surface), to
          6e-4 s: the shock reflects from the wall and the reflection reaches the bubble. No reference: "ok"
          when the run completes; the peak pressure at the wall's centre (a gauge at x = 0.995, y = 0,
          recorded every step) is kept in the CSV to compare the settings.
Writes OUT/stability_map_2d.csv and OUT/stability_map_2d.png and prints its table.
"""
import argparse
import csv
import itertools
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

PRESSURES = [1e6, 1e7, 1e8, 1e9, 1e10, 1e11]
DENSITIES = [16.3, 163.0, 1630.0]
METHODS = ["real_gfm", "modified_gfm", "original_gfm"]
LIMITERS = ["weno", "minmod", "none"]
CFLS = [0.1, 0.2, 0.3, 0.4]
OUTCOMES = ["ok", "wrong", "stopped", "crash"]
COLOURS = {"ok": "#4caf50", "wrong": "#ff9800", "stopped": "#2196f3", "crash": "#000000"}
PRESSURES_2D = [1e8, 3e8, 1e9, 3e9, 6e9]
SCENES_2D = {"free": 1e-4, "wall": 6e-4}  # scene: end time
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


CFL_2D = {1: 0.4, 2: 0.2}


def suffix(args):
    return "" if args.degree == 2 else f"_k{args.degree}"


def run(tool, case, cells, degree, p, rho, method, limiter, cfl):
    sets = {"numerics.degree": degree, "domain.cells_x": cells, "regions[1].p": p, "regions[1].rho": rho,
            "interface.method": method,
            "numerics.limiter": limiter, "numerics.indicator": "none" if limiter == "none" else "tvb",
            "numerics.cfl": cfl, "numerics.threads": 1}
    cmd = [tool, case, "--fit-time"]
    for k, v in sets.items():
        cmd += ["--set", f"{k}={v}"]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    line = proc.stdout.strip().splitlines()[-1] if proc.stdout.strip() else ""
    fields = next(csv.reader([line])) if line else []
    if proc.returncode == 0 and len(fields) >= 12:
        shock, interface = float(fields[9]), float(fields[10])
        outcome = "ok" if abs(shock) <= 5 and abs(interface) <= 5 else "wrong"
        detail = f"L1(p)/p* {float(fields[7]):.2e}, shock {shock:+.2f} cells, interface {interface:+.2f} cells"
    elif proc.returncode == 2 and len(fields) >= 5 and fields[3] == "stopped":
        outcome, detail = "stopped", fields[4]
    else:
        outcome, detail = "crash", f"exit {proc.returncode}: {proc.stderr.strip()[-300:]}"
    return outcome, detail


def map_1d(args):
    tool = os.path.join(args.build, "bin", "undex_1d_error")
    case = os.path.join(ROOT, "cases", "undex_1d.case")
    rows = []
    combos = list(itertools.product(METHODS, LIMITERS, CFLS, DENSITIES, PRESSURES))
    path = os.path.join(args.out, f"stability_map{suffix(args)}.csv")
    if args.replot:
        with open(path) as f:
            rows = [dict(r, cfl=float(r["cfl"]), rho_gas=float(r["rho_gas"]), p_gas=float(r["p_gas"]))
                    for r in csv.DictReader(f)]
        combos = []
    for n, (method, limiter, cfl, rho, p) in enumerate(combos, 1):
        outcome, detail = run(tool, case, args.cells, args.degree, p, rho, method, limiter, cfl)
        rows.append(dict(method=method, limiter=limiter, cfl=cfl, rho_gas=rho, p_gas=p, outcome=outcome,
                         detail=detail))
        print(f"[{n}/{len(combos)}] {method:12s} limiter {limiter:4s} CFL {cfl:.1f} rho {rho:7.1f} p {p:.0e}: "
              f"{outcome:7s} {detail}", flush=True)
    if not args.replot:
        write_csv(path, rows)

    # Map: one panel per (method, limiter); x: gas pressure, y: CFL × density (grouped rows).
    fig, axes = plt.subplots(len(METHODS), len(LIMITERS), figsize=(15, 4 * len(METHODS)), sharex=True,
                             sharey=True)
    ylabels = [f"CFL {c:.1f}, ρ {r:g}" for c in CFLS for r in DENSITIES]
    for ax, (method, limiter) in zip(axes.flat, itertools.product(METHODS, LIMITERS)):
        cells = [(PRESSURES.index(r["p_gas"]), CFLS.index(r["cfl"]) * len(DENSITIES) + DENSITIES.index(r["rho_gas"]),
                  r["outcome"]) for r in rows if r["method"] == method and r["limiter"] == limiter]
        draw_panel(ax, cells, PRESSURES, ylabels, f"{method}, limiter {limiter}", 7)
    for ax in axes[-1]:
        ax.set_xlabel("gas pressure (Pa)")
    png = finish_figure(fig, f"Case 4.1 stability map ({args.cells} cells, degree {args.degree}, Tait water)",
                        0.04, os.path.join(args.out, f"stability_map{suffix(args)}.png"))
    print(f"\n{path}\n{png}\n")
    print_table(rows)
    return rows


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


def draw_panel(ax, cells, pressures, ylabels, title, fontsize):
    """One panel of a map: a coloured square per (x, y, outcome), x the gas pressure's index."""
    for x, y, outcome in cells:
        ax.add_patch(plt.Rectangle((x - 0.45, y - 0.45), 0.9, 0.9, color=COLOURS[outcome]))
    ax.set_title(title)
    ax.set_xlim(-0.5, len(pressures) - 0.5)
    ax.set_ylim(-0.5, len(ylabels) - 0.5)
    ax.set_xticks(range(len(pressures)), [f"{p:.0e}" for p in pressures])
    ax.set_yticks(range(len(ylabels)), ylabels, fontsize=fontsize)


def finish_figure(fig, title, legend_height, png):
    """The outcome legend, the title, and the figure written to png (returned)."""
    handles = [plt.Rectangle((0, 0), 1, 1, color=COLOURS[o]) for o in OUTCOMES]
    fig.legend(handles, OUTCOMES, loc="lower center", ncol=4)
    fig.suptitle(title)
    fig.tight_layout(rect=(0, legend_height, 1, 1))
    fig.savefig(png, dpi=110)
    return png


def print_table(rows):
    print("| method | limiter | " + " | ".join(OUTCOMES) + " |")
    print("|---|---|" + "---|" * len(OUTCOMES))
    for method, limiter in itertools.product(METHODS, LIMITERS):
        counts = [sum(1 for r in rows if r["method"] == method and r["limiter"] == limiter and r["outcome"] == o)
                  for o in OUTCOMES]
        print(f"| {method} | {limiter} | " + " | ".join(str(c) for c in counts) + " |")


def undex_fluid(args, case, sets, outdir):
    """Runs undex-fluid; returns (exit status, its error line, or else the last line of its output)."""
    cmd = [os.path.join(args.build, "bin", "undex-fluid"), case, "-o", outdir, "--force"]
    for k, v in dict(sets, **{"output.progress_seconds": 1000}).items():
        cmd += ["--set", f"{k}={v}"]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=3600)
    lines = (proc.stdout + proc.stderr).strip().splitlines()
    errors = [x for x in lines if "error:" in x]
    return proc.returncode, (errors or lines or [""])[-1]


def axis_pressure(args, outdir, t):
    out = subprocess.run([os.path.join(args.build, "bin", "undex"), "sample", outdir, "--time", str(t), "--line",
                          "0,0 1,0", "--points", "2000", "--fields", "p"], capture_output=True, text=True,
                         check=True).stdout
    return np.loadtxt(out.splitlines()[2:], delimiter=",")[:, 2]


def map_2d(args):
    import h5py  # only the 2D map reads outputs

    free = os.path.join(ROOT, "cases", "free_field_2d.case")
    # The wall scene: the case as written with a gauge at the wall's centre (--set cannot add list entries).
    wall = os.path.join(args.out, f"map2d{suffix(args)}", "wall.case")
    os.makedirs(os.path.dirname(wall), exist_ok=True)
    with open(free) as f, open(wall, "w") as g:
        g.write(f.read() + '\ngauges { name: "wall" x: 0.995 y: 0 }\n')
    rows = []
    path = os.path.join(args.out, f"stability_map_2d{suffix(args)}.csv")
    combos = list(itertools.product(SCENES_2D, PRESSURES_2D, METHODS, LIMITERS))
    if args.replot:
        with open(path) as f:
            rows = [dict(r, p_gas=float(r["p_gas"])) for r in csv.DictReader(f)]
        combos = []
    refs = {}
    for n, (scene, p, method, limiter) in enumerate(combos, 1):
        end = SCENES_2D[scene]
        if scene == "free" and p not in refs:
            ref_dir = os.path.join(args.out, f"map2d{suffix(args)}", f"cylindrical_{p:.0e}")
            rc, line = undex_fluid(args, os.path.join(ROOT, "cases", "bubble_1d_cylindrical.case"),
                                   {"domain.cells_x": 4000, "regions[1].p": p, "numerics.threads": 1}, ref_dir)
            if rc != 0:
                raise RuntimeError(f"1D cylindrical reference at {p:.0e} Pa: {line}")
            refs[p] = axis_pressure(args, ref_dir, end)
        d = os.path.join(args.out, f"map2d{suffix(args)}", f"{scene}_{p:.0e}_{method}_{limiter}")
        sets = {"numerics.degree": args.degree, "numerics.cfl": CFL_2D[args.degree], "domain.cells_x": 100,
                "domain.cells_y": 100, "regions[1].p": p, "interface.method": method,
                "numerics.limiter": limiter, "numerics.indicator": "none" if limiter == "none" else "tvb",
                "numerics.threads": 1, "end_time": end, "output.times[0]": end, "output.times[1]": end,
                "output.times[2]": end}
        if scene == "wall":
            sets["boundaries.x_max.type"] = "WALL"
        rc, line = undex_fluid(args, free if scene == "free" else wall, sets, d)
        if rc == 0:
            if scene == "free":
                err = float(np.abs(axis_pressure(args, d, end) - refs[p]).sum() / np.abs(refs[p]).sum())
                outcome = "ok" if err <= 0.10 else "wrong"
                detail = f"relative L1(p) on the axis {err:.4f}"
            else:
                with h5py.File(os.path.join(d, "fluid.h5"), "r") as f:
                    t, pw = f["gauges/wall/t"][()], f["gauges/wall/p"][()]
                k = int(np.argmax(pw))
                outcome, detail = "ok", f"peak wall pressure {pw[k]:.4e} Pa at {t[k]:.3e} s"
        elif rc == 2 and "error:" in line:
            outcome, detail = "stopped", line
        else:
            outcome, detail = "crash", f"exit {rc}: {line[-300:]}"
        rows.append(dict(scene=scene, p_gas=p, method=method, limiter=limiter, outcome=outcome, detail=detail))
        print(f"[{n}/{len(combos)}] {scene} p {p:.0e} {method:12s} limiter {limiter:6s}: {outcome:7s} {detail}",
              flush=True)
    if not args.replot:
        write_csv(path, rows)
    fig, axes = plt.subplots(1, len(SCENES_2D), figsize=(12, 5), sharey=True)
    ylabels = [f"{m}, {lim}" for m in METHODS for lim in LIMITERS]
    for ax, scene in zip(axes, SCENES_2D):
        cells = [(PRESSURES_2D.index(r["p_gas"]), ylabels.index(f"{r['method']}, {r['limiter']}"), r["outcome"])
                 for r in rows if r["scene"] == scene]
        draw_panel(ax, cells, PRESSURES_2D, ylabels, f"{scene} (to {SCENES_2D[scene]:g} s)", 8)
        ax.set_xlabel("gas pressure (Pa)")
    png = finish_figure(fig, f"Case 4.4 stability map (100 x 100, degree {args.degree}, CFL {CFL_2D[args.degree]}, "
                        "Tait water)", 0.06, os.path.join(args.out, f"stability_map_2d{suffix(args)}.png"))
    print(f"\n{path}\n{png}\n")
    for scene in SCENES_2D:
        print(f"\n{scene}:")
        print_table([r for r in rows if r["scene"] == scene])
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="out/bench")
    parser.add_argument("--cells", type=int, default=400)
    parser.add_argument("--only", choices=["1d", "2d"], default=None)
    parser.add_argument("--degree", type=int, choices=[1, 2], default=2)
    parser.add_argument("--replot", action="store_true", help="redraw the maps from their CSV files")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    if args.only in (None, "1d"):
        rows += map_1d(args)
    if args.only in (None, "2d"):
        rows += map_2d(args)
    return 1 if any(r["outcome"] == "crash" for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
