#!/usr/bin/python3
"""Plot the energy histories and the gauges of a structure run.

    plot_structure.py OUTDIR [--output PNG]

Reads OUTDIR/solid.h5 (layout: solid/run_structure.hpp) and draws, in stacked panels: the energies
(kinetic, elastic, plastic, hourglass, external work, balance error), then for every gauge its displacement
and velocity through the thickness (u or u_y, v or v_y) and its PEEQ. The figure goes to
OUTDIR/structure.png unless --output is given.
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import h5py  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("outdir")
    ap.add_argument("--output")
    a = ap.parse_args()
    path = os.path.join(a.outdir, "solid.h5")
    if not os.path.exists(path):
        sys.exit(f"plot_structure.py: {path} does not exist (run the case first)")
    with h5py.File(path, "r") as f:
        e = f["energies"]
        t = e["t"][:] * 1e3
        two_d = int(f.attrs["dimension"]) == 2
        u, v = ("u_y", "v_y") if two_d else ("u", "v")
        fig, ax = plt.subplots(4, 1, figsize=(8, 11), sharex=True)
        for k in ("kinetic", "elastic", "plastic", "viscous", "hourglass", "external", "coupling", "balance_error"):
            if k in e and (k not in ("viscous", "coupling") or abs(e[k][:]).max() > 0):
                ax[0].plot(t, e[k][:], label=k)
        ax[0].set_ylabel("energy (J per " + ("radian or m depth" if two_d else "m²") + ")")
        ax[0].legend(fontsize=8)
        for name, g in f["gauges"].items():
            tg = g["t"][:] * 1e3
            ax[1].plot(tg, g[u][:] * 1e3, label=name)
            ax[2].plot(tg, g[v][:], label=name)
            ax[3].plot(tg, g["peeq"][:], label=name)
        ax[1].set_ylabel("displacement through\nthe thickness (mm)")
        ax[2].set_ylabel("velocity (m/s)")
        ax[3].set_ylabel("PEEQ")
        ax[3].set_xlabel("t (ms)")
        for x in ax[1:]:
            if x.get_legend_handles_labels()[0]:
                x.legend(fontsize=8)
        status = f["status"][()].decode()
        fig.suptitle(os.path.basename(os.path.normpath(a.outdir)) + ", status " + status)
    out = a.output or os.path.join(a.outdir, "structure.png")
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    print(out)


if __name__ == "__main__":
    main()
