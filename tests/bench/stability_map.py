#!/usr/bin/python3
"""Stability map of the gas–water interface treatment on case 4.1 (cases/undex_1d.case).

    /usr/bin/python3 tests/bench/stability_map.py [--build build] [--out out/bench] [--cells 400]

Sweeps the gas pressure (1e6 … 1e11 Pa) and the gas density (16.3, 163, 1630 kg/m^3: density ratios 0.0163 …
1.63 against water), for the real and the original ghost fluid method, with and without the limiter
(WENO or minmod on TVB-troubled cells, or none; the positivity scaling stays on), at CFL 0.1, 0.2, 0.3, 0.4; degree 2,
Tait water, one thread. Each run is classified against the exact solution of its own states
(build/bin/undex_1d_error); the run ends at 1e-4 s or earlier, when the fastest exact wave has covered 80 %
of the way to the boundary (strong gas pressures drive the shock out of [0, 1] before 1e-4 s):
    ok       completed, shock and interface within 5 cells of the exact positions;
    wrong    completed, but the shock or the interface is off by more than 5 cells;
    stopped  the solver stopped with its clear error (the message is kept in the CSV);
    crash    anything else (a signal, no output) -- there should be none.
Writes OUT/stability_map.csv and OUT/stability_map.png, and prints a summary table.
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
METHODS = ["real_gfm", "original_gfm"]
LIMITERS = ["weno", "minmod", "none"]
CFLS = [0.1, 0.2, 0.3, 0.4]
OUTCOMES = ["ok", "wrong", "stopped", "crash"]


def run(tool, case, cells, p, rho, method, limiter, cfl):
    sets = {"domain.cells_x": cells, "regions[1].p": p, "regions[1].rho": rho, "interface.method": method,
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
    elif proc.returncode in (2, 3) and len(fields) >= 5 and fields[3] == "stopped":
        outcome, detail = "stopped", fields[4]
    else:
        outcome, detail = "crash", f"exit {proc.returncode}: {proc.stderr.strip()[-300:]}"
    return outcome, detail


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="out/bench")
    parser.add_argument("--cells", type=int, default=400)
    parser.add_argument("--replot", action="store_true", help="redraw OUT/stability_map.png from its CSV")
    args = parser.parse_args()
    tool = os.path.join(args.build, "bin", "undex_1d_error")
    case = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "cases", "undex_1d.case")
    os.makedirs(args.out, exist_ok=True)
    rows = []
    combos = list(itertools.product(METHODS, LIMITERS, CFLS, DENSITIES, PRESSURES))
    path = os.path.join(args.out, "stability_map.csv")
    if args.replot:
        with open(path) as f:
            rows = [dict(r, cfl=float(r["cfl"]), rho_gas=float(r["rho_gas"]), p_gas=float(r["p_gas"]))
                    for r in csv.DictReader(f)]
        combos = []
    for n, (method, limiter, cfl, rho, p) in enumerate(combos, 1):
        outcome, detail = run(tool, case, args.cells, p, rho, method, limiter, cfl)
        rows.append(dict(method=method, limiter=limiter, cfl=cfl, rho_gas=rho, p_gas=p, outcome=outcome,
                         detail=detail))
        print(f"[{n}/{len(combos)}] {method:12s} limiter {limiter:4s} CFL {cfl:.1f} rho {rho:7.1f} p {p:.0e}: "
              f"{outcome:7s} {detail}", flush=True)
    if not args.replot:
        with open(path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            w.writeheader()
            w.writerows(rows)

    # Map: one panel per (method, limiter); x: gas pressure, y: CFL × density (grouped rows).
    colours = {"ok": "#4caf50", "wrong": "#ff9800", "stopped": "#2196f3", "crash": "#000000"}
    fig, axes = plt.subplots(2, 3, figsize=(15, 8), sharex=True, sharey=True)
    ylabels = [f"CFL {c:.1f}, ρ {r:g}" for c in CFLS for r in DENSITIES]
    for ax, (method, limiter) in zip(axes.flat, itertools.product(METHODS, LIMITERS)):
        for r in rows:
            if r["method"] != method or r["limiter"] != limiter:
                continue
            x = PRESSURES.index(r["p_gas"])
            y = CFLS.index(r["cfl"]) * len(DENSITIES) + DENSITIES.index(r["rho_gas"])
            ax.add_patch(plt.Rectangle((x - 0.45, y - 0.45), 0.9, 0.9, color=colours[r["outcome"]]))
        ax.set_title(f"{method}, limiter {limiter}")
        ax.set_xlim(-0.5, len(PRESSURES) - 0.5)
        ax.set_ylim(-0.5, len(ylabels) - 0.5)
        ax.set_xticks(range(len(PRESSURES)), [f"{p:.0e}" for p in PRESSURES])
        ax.set_yticks(range(len(ylabels)), ylabels, fontsize=7)
    for ax in axes[-1]:
        ax.set_xlabel("gas pressure (Pa)")
    handles = [plt.Rectangle((0, 0), 1, 1, color=colours[o]) for o in OUTCOMES]
    fig.legend(handles, OUTCOMES, loc="lower center", ncol=4)
    fig.suptitle(f"Case 4.1 stability map ({args.cells} cells, degree 2, Tait water)")
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    png = os.path.join(args.out, "stability_map.png")
    fig.savefig(png, dpi=110)

    print(f"\n{path}\n{png}\n")
    print("| method | limiter | " + " | ".join(OUTCOMES) + " |")
    print("|---|---|" + "---|" * len(OUTCOMES))
    for method, limiter in itertools.product(METHODS, LIMITERS):
        counts = [sum(1 for r in rows if r["method"] == method and r["limiter"] == limiter and r["outcome"] == o)
                  for o in OUTCOMES]
        print(f"| {method} | {limiter} | " + " | ".join(str(c) for c in counts) + " |")
    return 1 if any(r["outcome"] == "crash" for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
