#!/usr/bin/python3
"""Plot density, velocity and pressure profiles (and the void fraction, when present) of an undex run.

    plot_profiles.py OUTDIR [--time T] [--output PNG] [--reference OUTDIR2] [--reference-csv CSV]

Reads OUTDIR/fluid.h5 (layout: fluid/output.hpp), picks the output nearest the time T (default: the last
output) and draws the cell averages against x in stacked panels. A 2D output is plotted along the row of
cells nearest y = 0. The figure goes to OUTDIR/profiles.png unless --output is given.
A reference is drawn as a black line: another run (--reference, its output nearest the same time, e.g. the
1D cylindrical bubble for the 2D free field) or a CSV with header x,rho,u,p (--reference-csv, e.g. the exact
solution written by `build/bin/undex_1d_error CASE --exact CSV`). A two-fluid run also marks the interface
(zero of the level set phi) with a dotted vertical line.
"""
import argparse
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import h5py  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def text_attr(obj, key, default=""):
    """A text of the file: a string dataset (case, status), or an attribute in files written before they were
    datasets; default when missing."""
    if key in obj and isinstance(obj[key], h5py.Dataset):
        value = obj[key][()]
    elif key in obj.attrs:
        value = obj.attrs[key]
    else:
        return default
    if isinstance(value, np.ndarray):
        value = value.item() if value.size == 1 else value.tolist()
    if isinstance(value, bytes):
        value = value.decode("utf-8", "replace")
    return str(value)


def case_name(h5, outdir):
    match = re.search(r'^name:\s*"([^"]*)"', text_attr(h5, "case"), re.MULTILINE)
    if match and match.group(1):
        return match.group(1)
    return os.path.basename(os.path.normpath(outdir))


def name_of_run(h5_path):
    return os.path.basename(os.path.dirname(os.path.abspath(h5_path))) or "run"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("outdir", metavar="OUTDIR", help="output directory of a run (holding fluid.h5), or the .h5 file")
    parser.add_argument("--time", type=float, default=None, metavar="T",
                        help="plot the output nearest this time in s (default: the last output)")
    parser.add_argument("--output", default=None, metavar="PNG", help="figure file (default: OUTDIR/profiles.png)")
    parser.add_argument("--reference", default=None, metavar="OUTDIR2", help="a reference run drawn as a line")
    parser.add_argument("--reference-csv", default=None, metavar="CSV", help="a reference profile x,rho,u,p")
    args = parser.parse_args(argv)

    if os.path.isdir(args.outdir):
        h5_path = os.path.join(args.outdir, "fluid.h5")
        png = args.output or os.path.join(args.outdir, "profiles.png")
    else:
        h5_path = args.outdir
        png = args.output or os.path.join(os.path.dirname(os.path.abspath(h5_path)), "profiles.png")
    if not os.path.isfile(h5_path):
        parser.error(f"{h5_path}: no such file (is {args.outdir} the output directory of a run?)")

    with h5py.File(h5_path, "r") as h5:
        if "fields" not in h5 or len(h5["fields"]) == 0:
            sys.exit(f"plot_profiles: {h5_path} holds no output")
        groups = sorted(h5["fields"].keys())
        times = np.array([float(h5["fields"][g].attrs["time"]) for g in groups])
        k = len(groups) - 1 if args.time is None else int(np.argmin(np.abs(times - args.time)))
        group = h5["fields"][groups[k]]
        t = times[k]
        x = h5["x"][()]
        two_d = group["rho"].ndim == 2
        row_label = ""
        if two_d:
            y = h5["y"][()]
            j = int(np.argmin(np.abs(y)))
            yj = 0.0 if abs(y[j]) < 1e-9 * (abs(y[-1] - y[0]) or 1.0) else y[j]  # round-off of a centred row
            row_label = f", row y = {yj:.4g}"

            def take(name):
                return group[name][j, :]
        else:

            def take(name):
                return group[name][()]

        panels = [("rho", r"density $\rho$ (kg/m$^3$)"), ("u", r"velocity $u$ (m/s)"), ("p", r"pressure $p$ (Pa)")]
        if "void_fraction" in group:
            panels.append(("void_fraction", r"void fraction $\alpha$"))
        data = [(take(name), label) for name, label in panels]
        interfaces = []
        if "phi" in group:
            phi = take("phi")
            for i in range(len(phi) - 1):
                if (phi[i] < 0) != (phi[i + 1] < 0):
                    interfaces.append(x[i] + (x[i + 1] - x[i]) * phi[i] / (phi[i] - phi[i + 1]))
        name = case_name(h5, args.outdir)
        status = text_attr(h5, "status", "complete")
        last_good = int(group.attrs.get("last_good", 0))

    title = f"{name}: t = {t:.6g} s{row_label}"
    if status != "complete":
        title += f"\n(run status: {status})"
    if last_good:
        title += "\n(last good state before a failure)"

    reference = {}
    ref_label = ""
    if args.reference:
        ref_path = os.path.join(args.reference, "fluid.h5") if os.path.isdir(args.reference) else args.reference
        with h5py.File(ref_path, "r") as rh5:
            rgroups = sorted(rh5["fields"].keys())
            rtimes = np.array([float(rh5["fields"][g].attrs["time"]) for g in rgroups])
            rg = rh5["fields"][rgroups[int(np.argmin(np.abs(rtimes - t)))]]
            reference = {"x": rh5["x"][()]}
            for field in ("rho", "u", "p", "void_fraction"):
                if field in rg:
                    values = rg[field][()]
                    reference[field] = values if values.ndim == 1 else values[int(np.argmin(np.abs(rh5["y"][()]))), :]
            ref_label = case_name(rh5, args.reference)
    elif args.reference_csv:
        table = np.genfromtxt(args.reference_csv, delimiter=",", names=True, comments="#")
        reference = {field: table[field] for field in table.dtype.names}
        ref_label = os.path.basename(args.reference_csv)

    fig, axes = plt.subplots(len(data), 1, sharex=True, figsize=(8, 2.3 * len(data) + 0.8), squeeze=False)
    axes = axes[:, 0]
    for ax, (values, label), (field, _) in zip(axes, data, panels):
        ax.plot(x, values, "-", color="tab:blue", linewidth=0.8, label=name_of_run(h5_path))
        ax.plot(x, values, "o", color="tab:blue", markersize=2)
        if field in reference:
            ax.plot(reference["x"], reference[field], "-", color="black", linewidth=0.9, label=ref_label)
        for xi in interfaces:
            ax.axvline(xi, color="tab:gray", linestyle=":", linewidth=0.8)
        ax.set_ylabel(label)
        ax.grid(True, linewidth=0.3, alpha=0.6)
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 4), useMathText=True)
    if reference:
        axes[0].legend(loc="best", fontsize=8)
    axes[-1].set_xlabel("x (m)")
    axes[-1].set_xlim(x[0] - 0.5 * (x[1] - x[0]) if len(x) > 1 else None,
                      x[-1] + 0.5 * (x[-1] - x[-2]) if len(x) > 1 else None)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)
    print(f"{png}: {name}, output {groups[k]} at t = {t:.6g} s{row_label}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
