#!/usr/bin/python3
"""Plot case 4.5 (cases/sandwich_plate_water_backed_2d.case): the pressure and displacement histories at P1,
the centre of the plate's lower (wet) face, and the wet-face pressure along the plate at the output times.

    plot_sandwich_plate_2d.py OUT_DIR [OUT_DIR ...] [--png FILE] [--csv FILE]

Each OUT_DIR is a run's output directory (fluid.h5, solid.h5); several (e.g. a grid study) are drawn
together, labelled by their fluid cell size. Pressure at P1: the structure's interface pressure p_I of the
wet node nearest P1 (solid.h5 /coupling, every step) and the fluid's own pressure half a cell below it
(fluid.h5 /gauges/P1). Displacement: the structure's gauge P1 (solid.h5 /gauges/P1 u_y). The figure goes to
--png (default OUT_DIR/sandwich_plate_2d.png of the first run); --csv writes t, p_I, u_y at P1 of each run.
Prints per run: the peak P1 pressure and its time, and the P1 displacement at the end.
"""
import argparse
import os

import h5py
import numpy as np


def p1_pressure(out):
    with h5py.File(os.path.join(out, "solid.h5")) as s, h5py.File(os.path.join(out, "fluid.h5")) as f:
        c = s["coupling"]
        t, p = c["t"][:], c["p_I"][:]
        steps = len(np.unique(t))
        nodes = len(t) // steps
        w = f["wet_nodes"]
        first = w["t"][:] == w["t"][0]
        x, face = w["x"][:][first], w["face"][:][first]
        front = np.nonzero(face == 0)[0]
        k = front[np.argmin(np.abs(x[front]))]  # the front's node nearest x = 0
        g = f["gauges/P1"]
        dx = (f.attrs["x_max"] - f.attrs["x_min"]) / f.attrs["nx"]
        return t[k::nodes], p[k::nodes], g["t"][:], g["p"][:], dx


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", nargs="+")
    ap.add_argument("--png")
    ap.add_argument("--csv")
    a = ap.parse_args()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    rows = []
    for out in a.out:
        t, pI, tg, pg, dx = p1_pressure(out)
        with h5py.File(os.path.join(out, "solid.h5")) as s:
            gs = s["gauges/P1"]
            ts, uy = gs["t"][:], gs["u_y"][:]
        label = f"fluid {dx * 100:g} cm"
        ax[0].plot(t * 1e3, pI / 1e6, label=f"p_I, {label}")
        ax[0].plot(tg * 1e3, pg / 1e6, ":", label=f"water below P1, {label}")
        ax[1].plot(ts * 1e3, uy * 1e3, label=label)
        k = int(np.argmax(pI))
        print(f"{out}: fluid dx {dx:g} m: P1 peak p_I {pI[k] / 1e6:.4f} MPa at {t[k] * 1e3:.4f} ms; "
              f"P1 displacement at {ts[-1] * 1e3:.3g} ms: {uy[-1] * 1e3:.4f} mm")
        rows.append((dx, t, pI, np.interp(t, ts, uy)))
    with h5py.File(os.path.join(a.out[-1], "fluid.h5")) as f:
        w = f["wet_nodes"]
        tw, face, x, p = w["t"][:], w["face"][:], w["x"][:], w["p_I"][:]
        for T in np.unique(tw)[1::2]:
            m = (tw == T) & (face == 0)
            ax[2].plot(x[m], p[m] / 1e6, label=f"{T * 1e3:.2f} ms")
    ax[0].set(xlabel="t (ms)", ylabel="pressure at P1 (MPa)", title="P1 pressure")
    ax[1].set(xlabel="t (ms)", ylabel="u_y at P1 (mm)", title="P1 displacement")
    ax[2].set(xlabel="x (m)", ylabel="p_I (MPa)", title=f"lower face pressure ({os.path.basename(a.out[-1])})")
    for x_ in ax:
        x_.grid(alpha=0.3)
        x_.legend(fontsize=7)
    fig.tight_layout()
    png = a.png or os.path.join(a.out[0], "sandwich_plate_2d.png")
    fig.savefig(png, dpi=110)
    print(f"figure: {png}")
    if a.csv:
        with open(a.csv, "w") as c:
            c.write("dx,t,p_I,u_y\n")
            for dx, t, pI, uy in rows:
                for k in range(len(t)):
                    c.write(f"{dx!r},{t[k]!r},{pI[k]!r},{uy[k]!r}\n")


if __name__ == "__main__":
    main()
