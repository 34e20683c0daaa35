#!/usr/bin/python3
"""Mirror asymmetry of a 2D fluid output: for every output group of <dir>/fluid.h5, the max-norm and L1
differences of p and rho (cell averages) from their mirror images, relative to max|f| (max) and to
sum|f| (L1). Mirrors: "diag" (x = y: transpose), "x" (x -> -x about the domain centre: flip columns),
"y" (flip rows). Usage: mirror_error.py DIR [--mirrors diag,x,y] [--vars p,rho] [--coefficients]
--coefficients also compares the DG coefficients (mapped by the mirror: ξ <-> η for diag, sign of odd
powers for flips), which catches asymmetry that the cell averages do not show yet.
Exit status 0; prints one line per group and mirror."""
import sys
import argparse
import h5py
import numpy as np

# 2D basis order (fluid/basis.hpp): 1, ξ, η, ξη, ξ²−1/3, η²−1/3
PX = [0, 1, 0, 1, 2, 0]
PY = [0, 0, 1, 1, 0, 2]


def mirror_field(a, m):
    if a.ndim == 1:  # 1D: "x" flips about the domain centre
        return a[::-1]
    if m == "diag":
        return a.T
    if m == "x":
        return a[:, ::-1]
    if m == "y":
        return a[::-1, :]
    raise ValueError(m)


def mirror_coefficients(c, nx, ny, nv, nb, m):
    """c: (cells, nv*nb) -> mirrored coefficients on the same cells, array (ny, nx, nv, nb)."""
    if nv == 3:  # 1D: (rho, rho u, E), basis 1, ξ, ξ² − 1/3
        a = c.reshape(nx, nv, nb)
        out = a[::-1].copy()
        out[:, 1] *= -1
        return a, out * np.array([(-1.0) ** l for l in range(nb)])
    a = c.reshape(ny, nx, nv, nb)
    b = mirror_field_4(a, m)
    out = b.copy()
    # variables: rho, rho u, rho v, E
    if m == "diag":
        out[:, :, 1], out[:, :, 2] = b[:, :, 2].copy(), b[:, :, 1].copy()
        perm = [0, 2, 1, 3, 5, 4][:nb]
        out = out[:, :, :, perm]
    else:
        if m == "x":
            out[:, :, 1] *= -1
            sign = np.array([(-1.0) ** PX[l] for l in range(nb)])
        else:
            out[:, :, 2] *= -1
            sign = np.array([(-1.0) ** PY[l] for l in range(nb)])
        out = out * sign
    return a, out


def mirror_field_4(a, m):
    if m == "diag":
        return a.transpose(1, 0, 2, 3)
    if m == "x":
        return a[:, ::-1]
    return a[::-1, :]


def rel(a, b):
    d = np.abs(a - b)
    mx = d.max() / max(np.abs(a).max(), 1e-300)
    l1 = d.sum() / max(np.abs(a).sum(), 1e-300)
    return mx, l1


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir")
    ap.add_argument("--mirrors", default="diag")
    ap.add_argument("--vars", default="p,rho")
    ap.add_argument("--coefficients", action="store_true")
    ap.add_argument("--max", action="store_true", help="print only the largest max-norm error and exit")
    args = ap.parse_args()
    worst = 0.0
    with h5py.File(args.dir.rstrip("/") + "/fluid.h5", "r") as f:
        nx, ny = int(f.attrs["nx"]), int(f.attrs.get("ny", 1))
        nv, nb = int(f.attrs["variables"]), int(f.attrs["basis_functions"])
        for g in sorted(f["fields"]):
            grp = f["fields"][g]
            t = float(grp.attrs["time"])
            step = int(grp.attrs["step"])
            for m in args.mirrors.split(","):
                parts = []
                for v in args.vars.split(","):
                    a = grp[v][()]
                    mx, l1 = rel(a, mirror_field(a, m))
                    worst = max(worst, mx) if np.isfinite(mx) else float("inf")  # NaN is no mirror image
                    parts.append(f"{v}: max {mx:.3e} L1 {l1:.3e}")
                if args.coefficients and nb > 1:
                    a, b = mirror_coefficients(grp["coefficients"][()], nx, ny, nv, nb, m)
                    d = np.abs(a - b).max() / np.abs(a).max()
                    worst = max(worst, d) if np.isfinite(d) else float("inf")
                    parts.append(f"coef: max {d:.3e}")
                if not args.max:
                    print(f"{g} t={t:.6g} step={step} {m}: " + "  ".join(parts))
    if args.max:
        print(f"{worst:.3e}")


if __name__ == "__main__":
    main()
