#!/usr/bin/python3
"""Plot density, velocity and pressure profiles (and the void fraction, when present) of an undex run.

    plot_profiles.py OUTDIR [--time T] [--output PNG]

Reads OUTDIR/fluid.h5 (layout: fluid/output.hpp), picks the output nearest the time T (default: the last
output) and draws the cell averages against x in stacked panels. A 2D output is plotted along the row of
cells nearest y = 0. The figure goes to OUTDIR/profiles.png unless --output is given.
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
    """A string attribute (stored as bytes or str), or default when missing."""
    if key not in obj.attrs:
        return default
    value = obj.attrs[key]
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


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("outdir", metavar="OUTDIR", help="output directory of a run (holding fluid.h5), or the .h5 file")
    parser.add_argument("--time", type=float, default=None, metavar="T",
                        help="plot the output nearest this time in s (default: the last output)")
    parser.add_argument("--output", default=None, metavar="PNG", help="figure file (default: OUTDIR/profiles.png)")
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
        name = case_name(h5, args.outdir)
        status = text_attr(h5, "status", "complete")
        last_good = int(group.attrs.get("last_good", 0))

    title = f"{name}: t = {t:.6g} s{row_label}"
    if status != "complete":
        title += f"\n(run status: {status})"
    if last_good:
        title += "\n(last good state before a failure)"

    fig, axes = plt.subplots(len(data), 1, sharex=True, figsize=(8, 2.3 * len(data) + 0.8), squeeze=False)
    axes = axes[:, 0]
    for ax, (values, label) in zip(axes, data):
        ax.plot(x, values, "-", color="tab:blue", linewidth=0.8)
        ax.plot(x, values, "o", color="tab:blue", markersize=2)
        ax.set_ylabel(label)
        ax.grid(True, linewidth=0.3, alpha=0.6)
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 4), useMathText=True)
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
