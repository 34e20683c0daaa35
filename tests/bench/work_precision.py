#!/usr/bin/python3
"""Work–precision charts of the gas–water solver: error against wall time, log–log.

    /usr/bin/python3 tests/bench/work_precision.py [--build build] [--out out/bench] [--only 4.1|4.4|app]

Case 4.1 (cases/undex_1d.case), one thread: degrees 0, 1, 2 on 100 … 3200 cells (CFL 0.8, 0.4, 0.2), for the
real and the modified ghost fluid method, the minmod limiter (degrees 1, 2) and the WENO limiter (degree 2),
and both water models; error L1(p)/p* against the exact solution of each water model, wall time of the
time stepping (build/bin/undex_1d_error).
Case 4.4 (cases/free_field_2d.case), two threads: degrees 1 and 2 on 50², 100², 200², for the real GFM with
the WENO limiter (the paper's setting) and the modified GFM with the minmod limiter (the case file's); error:
relative L1 of p along the positive x axis against the 1D cylindrical bubble (cases/bubble_1d_cylindrical.case, 5000 cells,
run once and kept in OUT); wall time as reported by undex-fluid (time stepping and output).
The application (cases/undex_sandwich_plate.case as shipped but for the fluid's cells and degree), two fluid
threads and one structure thread: degrees 1 (the case's CFL 0.2) and 2 (CFL 0.15, the highest the set-up
allows next to a structure in 2D) at fluid cells of 0.04, 0.02 and 0.01 m; the P1 peak
pressure (the structure's p_I at the wet node nearest r = 0) and the final P2 displacement, each against
the finest degree-2 run (the most accurate run there is; its own error is not known, and the change from the
next coarser degree-2 run is printed as a hint of it); wall time of the whole coupled run (`undex run`).
A run whose output is complete and whose wall time was recorded (OUT/app_k*_*/wall_seconds) is not run
again: the expensive ones can be run one per session.
Writes OUT/work_precision_41.csv/.png, OUT/work_precision_44.csv/.png and OUT/work_precision_app.csv/.png
and prints, per water model and for the application, the cheapest setting that reaches each of a few error
levels.
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
CFL = {0: 0.8, 1: 0.4, 2: 0.2}


def sets_args(sets):
    out = []
    for k, v in sets.items():
        out += ["--set", f"{k}={v}"]
    return out


def case_41(args):
    tool = os.path.join(args.build, "bin", "undex_1d_error")
    rows = []
    configs = [(k, "minmod") for k in (0, 1, 2)] + [(2, "weno")]
    for water in ("tait", "stiffened_gas"):
        for method in ("real_gfm", "modified_gfm"):
            for k, limiter in configs:
                for n in (100, 200, 400, 800, 1600, 3200):
                    sets = {"domain.cells_x": n, "numerics.degree": k, "numerics.cfl": CFL[k],
                            "interface.method": method, "numerics.threads": 1, "numerics.limiter": limiter,
                            "materials[1].tait.as_stiffened_gas": "true" if water == "stiffened_gas" else "false"}
                    proc = subprocess.run([tool, os.path.join(ROOT, "cases", "undex_1d.case")] + sets_args(sets),
                                          capture_output=True, text=True)
                    f = proc.stdout.strip().split(",")
                    if proc.returncode != 0 or len(f) < 12:
                        print(f"4.1 {water} {method} k={k} N={n}: {proc.stdout.strip()} {proc.stderr.strip()}")
                        continue
                    row = dict(water=water, method=method, degree=k, limiter=limiter, cells=n, cfl=CFL[k],
                               wall=float(f[3]),
                               l1_p_rel=float(f[7]), shock_cells=float(f[9]), interface_cells=float(f[10]))
                    rows.append(row)
                    print(f"4.1 {water:13s} {method:12s} {limiter:6s} k={k} N={n:5d}: wall {row['wall']:.3f} s, "
                          f"L1(p)/p* {row['l1_p_rel']:.3e}, shock {row['shock_cells']:+.2f}, "
                          f"interface {row['interface_cells']:+.2f} cells", flush=True)
    write_csv(os.path.join(args.out, "work_precision_41.csv"), rows)
    fig, axes = plt.subplots(1, 2, figsize=(12, 5), sharey=True)
    styles = {"real_gfm": "-", "modified_gfm": "--"}
    colours = {0: "tab:gray", 1: "tab:blue", 2: "tab:red"}
    for ax, water in zip(axes, ("tait", "stiffened_gas")):
        for method in ("real_gfm", "modified_gfm"):
            for k, limiter in configs:
                sel = [r for r in rows if r["water"] == water and r["method"] == method and r["degree"] == k
                       and r["limiter"] == limiter]
                if not sel:
                    continue
                label = f"{method}, degree {k}" + ("" if k == 0 else f", {limiter}")
                ax.loglog([r["wall"] for r in sel], [r["l1_p_rel"] for r in sel], styles[method],
                          marker="o" if limiter == "minmod" else "x", color=colours[k] if limiter == "minmod"
                          else "tab:orange", label=label)
                for r in sel:
                    ax.annotate(str(r["cells"]), (r["wall"], r["l1_p_rel"]), fontsize=6, alpha=0.7)
        ax.set_title(f"case 4.1, {water.replace('_', '-')} water")
        ax.set_xlabel("wall time of the time stepping, one thread (s)")
        ax.grid(True, which="both", linewidth=0.3, alpha=0.6)
    axes[0].set_ylabel("L1(p) / p*  (mean absolute error over [0, 1])")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "work_precision_41.png"), dpi=110)
    for water in ("tait", "stiffened_gas"):
        print(f"\ncheapest setting per error level, {water} water:")
        for level in (3e-3, 1e-3, 9e-4, 5e-4, 3e-4):
            ok = [r for r in rows if r["water"] == water and r["l1_p_rel"] <= level]
            if ok:
                r = min(ok, key=lambda r: r["wall"])
                print(f"  L1(p)/p* <= {level:.0e}: {r['method']}, {r['limiter']}, degree {r['degree']}, {r['cells']} cells, "
                      f"{r['wall']:.3f} s (error {r['l1_p_rel']:.2e})")
            else:
                print(f"  L1(p)/p* <= {level:.0e}: not reached")


def undex_fluid(args, case, sets, outdir):
    exe = os.path.join(args.build, "bin", "undex-fluid")
    sets = dict(sets, **{"output.directory": outdir, "output.progress_seconds": 1000})
    proc = subprocess.run([exe, case] + sets_args(sets), capture_output=True, text=True)
    m = re.search(r"done: (\d+) steps, wall ([0-9.]+) s", proc.stdout)
    if proc.returncode != 0 or not m:
        raise RuntimeError(f"{case}: {proc.stdout[-500:]} {proc.stderr[-500:]}")
    return float(m.group(2))


def axis_profile(args, outdir, field="p"):
    exe = os.path.join(args.build, "bin", "undex")
    out = subprocess.run([exe, "sample", outdir, "--time", "1e-4", "--line", "0,0 1,0", "--points", "2000",
                          "--fields", field], capture_output=True, text=True, check=True).stdout
    return np.loadtxt(out.splitlines()[2:], delimiter=",")[:, 2]


def case_44(args):
    ref_dir = os.path.join(args.out, "bubble_1d_cylindrical_5000")
    if not os.path.isfile(os.path.join(ref_dir, "fluid.h5")):
        print("4.4 reference: 1D cylindrical bubble, 5000 cells ...", flush=True)
        undex_fluid(args, os.path.join(ROOT, "cases", "bubble_1d_cylindrical.case"), {"numerics.threads": 2},
                    ref_dir)
    ref = axis_profile(args, ref_dir)
    rows = []
    settings = [("real_gfm", "weno"), ("modified_gfm", "minmod")]
    for method, limiter in settings:
        for k in (1, 2):
            for n in (50, 100, 200):
                d = os.path.join(args.out, f"free_field_{method}_{limiter}_k{k}_{n}")
                wall = undex_fluid(args, os.path.join(ROOT, "cases", "free_field_2d.case"),
                                   {"domain.cells_x": n, "domain.cells_y": n, "numerics.degree": k,
                                    "numerics.cfl": CFL[k], "numerics.threads": 2, "interface.method": method,
                                    "numerics.limiter": limiter, "output.times[0]": 1e-4,
                                    "output.times[1]": 1e-4, "output.times[2]": 1e-4}, d)
                err = float(np.abs(axis_profile(args, d) - ref).sum() / np.abs(ref).sum())
                rows.append(dict(method=method, limiter=limiter, degree=k, cells=n, wall=wall, rel_l1_p=err))
                print(f"4.4 {method} {limiter} k={k} {n}x{n}: wall {wall:.2f} s, relative L1(p) on the axis "
                      f"{err:.4f}", flush=True)
    write_csv(os.path.join(args.out, "work_precision_44.csv"), rows)
    fig, ax = plt.subplots(figsize=(6, 5))
    for (method, limiter), style in zip(settings, ("-", "--")):
        for k, c in ((1, "tab:blue"), (2, "tab:red")):
            sel = [r for r in rows if r["degree"] == k and r["method"] == method]
            ax.loglog([r["wall"] for r in sel], [r["rel_l1_p"] for r in sel], style, marker="o", color=c,
                      label=f"{method}, {limiter}, degree {k}")
            for r in sel:
                ax.annotate(f"{r['cells']}²", (r["wall"], r["rel_l1_p"]), fontsize=7)
    ax.set_xlabel("wall time, two threads (s)")
    ax.set_ylabel("relative L1(p) on the x axis vs 1D cylindrical (5000 cells)")
    ax.set_title("case 4.4, Tait water")
    ax.grid(True, which="both", linewidth=0.3, alpha=0.6)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "work_precision_44.png"), dpi=110)


APP_CELLS = [(125, 300), (250, 600), (500, 1200)]  # fluid cells 0.04, 0.02, 0.01 m
APP_CFL_DEGREE_2 = 0.15  # the highest `undex check` allows for degree 2 next to a structure in 2D


def run_application(args, k, nx, ny):
    """Output directory and wall time of the sandwich plate at degree k on nx x ny fluid cells."""
    d = os.path.join(args.out, f"app_k{k}_{nx}")
    stamp = os.path.join(d, "wall_seconds")
    sys.path.insert(0, os.path.join(ROOT, "tests", "support"))
    from checks import status_of  # noqa: E402
    if os.path.isfile(stamp) and status_of(os.path.join(d, "fluid.h5")) == "complete":
        return d, float(open(stamp).read())
    sets = {"domain.cells_x": nx, "domain.cells_y": ny, "numerics.degree": k, "numerics.threads": 2,
            "structure.threads": 1, "output.progress_seconds": 60}
    if k == 2:
        sets["numerics.cfl"] = APP_CFL_DEGREE_2
    t0 = time.monotonic()
    with open(os.path.join(args.out, f"app_k{k}_{nx}.log"), "w") as log:
        proc = subprocess.run([os.path.join(args.build, "bin", "undex"), "run",
                               os.path.join(ROOT, "cases", "undex_sandwich_plate.case"), "-o", d, "--force"]
                              + sets_args(sets), stdout=log, stderr=subprocess.STDOUT)
    wall = time.monotonic() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"application, degree {k}, {nx} x {ny}: exit {proc.returncode} (see {log.name})")
    with open(stamp, "w") as f:
        f.write(f"{wall:.1f}\n")
    return d, wall


def case_app(args):
    sys.path.insert(0, os.path.join(ROOT, "cases"))
    from undex_findings import gauge, p_I_at_centre  # noqa: E402
    runs = []
    for k in (1, 2):
        for nx, ny in APP_CELLS:
            d, wall = run_application(args, k, nx, ny)
            _, p1 = p_I_at_centre(d, 0)
            p2 = gauge(d, "P2")
            runs.append(dict(degree=k, cells_x=nx, cells_y=ny, dx=5.0 / nx, wall=wall, p1_peak_MPa=p1.max() / 1e6,
                             p2_final_mm=p2["u_y"][-1] * 1e3))
            r = runs[-1]
            print(f"application k={k} {nx}x{ny} ({r['dx']:g} m): wall {wall:.0f} s, P1 peak {r['p1_peak_MPa']:.4g} "
                  f"MPa, P2 final {r['p2_final_mm']:.4g} mm", flush=True)
    ref = max((r for r in runs if r["degree"] == 2), key=lambda r: r["cells_x"])
    for r in runs:
        r["p1_error"] = abs(r["p1_peak_MPa"] / ref["p1_peak_MPa"] - 1)
        r["p2_error"] = abs(r["p2_final_mm"] / ref["p2_final_mm"] - 1)
    write_csv(os.path.join(args.out, "work_precision_app.csv"), runs)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6), sharey=True)
    for ax, key, title in ((axes[0], "p1_error", "P1 peak pressure"), (axes[1], "p2_error", "P2 final displacement")):
        for k, c in ((1, "tab:blue"), (2, "tab:red")):
            sel = [r for r in runs if r["degree"] == k and r is not ref]
            ax.loglog([r["wall"] for r in sel], [max(r[key], 1e-5) for r in sel], "-o", color=c,
                      label=f"degree {k}")
            for r in sel:
                ax.annotate(f"{r['dx']:g} m", (r["wall"], max(r[key], 1e-5)), fontsize=7)
        ax.axhline(0.02, color="k", linewidth=0.6, linestyle=":", label="2 %")
        ax.axvline(ref["wall"], color="tab:red", linewidth=0.6, linestyle="--",
                   label=f"reference: degree 2, {ref['dx']:g} m")
        ax.set_title(f"sandwich plate: {title}")
        ax.set_xlabel("wall time of the coupled run, 2 fluid threads + 1 structure thread (s)")
        ax.grid(True, which="both", linewidth=0.3, alpha=0.6)
    axes[0].set_ylabel("relative difference from the reference run")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "work_precision_app.png"), dpi=110)
    print(f"reference: degree 2 at {ref['dx']:g} m: P1 peak {ref['p1_peak_MPa']:.4g} MPa, P2 final "
          f"{ref['p2_final_mm']:.4g} mm, wall {ref['wall']:.0f} s")
    next_ = [r for r in runs if r["degree"] == 2 and r is not ref]
    if next_:
        r = max(next_, key=lambda r: r["cells_x"])
        print(f"  the next coarser degree-2 run ({r['dx']:g} m) differs from it by {r['p1_error']:.2%} (P1) and "
              f"{r['p2_error']:.2%} (P2)")
    for level in (0.05, 0.02, 0.01):
        ok = [r for r in runs if r is not ref and r["p1_error"] <= level and r["p2_error"] <= level]
        if ok:
            r = min(ok, key=lambda r: r["wall"])
            print(f"  both within {level:.0%}: cheapest degree {r['degree']} at {r['dx']:g} m, {r['wall']:.0f} s "
                  f"(P1 {r['p1_error']:.2%}, P2 {r['p2_error']:.2%})")
        else:
            print(f"  both within {level:.0%}: no coarser run")


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print(path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="out/bench")
    parser.add_argument("--only", choices=["4.1", "4.4", "app"], default=None)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    if args.only in (None, "4.1"):
        case_41(args)
    if args.only in (None, "4.4"):
        case_44(args)
    if args.only in (None, "app"):
        case_app(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
