#!/usr/bin/python3
"""Pictures of the paper's application (§5; cases/undex_steel_plate.case and cases/undex_sandwich_plate.case):
a near-field underwater explosion under a clamped steel plate (case 1) and a sandwich plate of equal mass
(case 2).

    plot_undex_plates.py DIR_CASE1 DIR_CASE2 [--png-dir DIR] [--no-animation] [--width PX]

DIR_CASE1 and DIR_CASE2 are the output directories of the two runs (fluid.h5, solid.h5). Writes into
--png-dir (default DIR_CASE2/..):
  undex_histories.png      pressure, displacement, velocity and PEEQ at P1 (centre of the lower, wet face) and
                           P2 (centre of the upper face), both cases on shared axes (paper Figs 5.4, 5.7-5.9);
  undex_face_pressure.png  the pressure along the lower wet face at 0.6, 0.9, 1.2, 1.48 and 1.8 ms (Fig. 5.5);
  undex_energies.png       each plate's energies: external work, kinetic, elastic and plastic dissipation per
                           layer, the bulk viscosity's dissipation, and the balance error (Fig. 5.10);
  undex_snapshots_CASE.png pressure and numerical schlieren at the fields' output times (Figs 5.2, 5.3), the
                           gas bubble (phi = 0) outlined in white (red on schlieren), cavitating water (void
                           fraction > 1e-6) in cyan, the plate in grey; the axis r = 0 drawn as a mirror line, the picture mirrored;
  undex_sandwich.gif       an animation of case 2 from the light frames (fluid.h5 /frames; --no-animation skips).

Sources: the pressures are the structure's interface pressure p_I of the wet node nearest r = 0 of each face
(solid.h5 /coupling, every step); displacement u_y, velocity v_y and PEEQ the structure's gauges P1, P2
(solid.h5 /gauges); energies solid.h5 /energies and /energies_by_layer; the pictures the fields' cell
averages (fluid.h5 /fields), block-averaged to at most --width pixels across (default 400) so that a fine
mesh stays cheap.
"""
import argparse
import os

import h5py
import numpy as np

FACE_TIMES = [0.6e-3, 0.9e-3, 1.2e-3, 1.48e-3, 1.8e-3]


class Run:
    """What the pictures read from one run's outputs."""

    def __init__(self, out):
        self.out = out
        self.fluid = os.path.join(out, "fluid.h5")
        self.solid = os.path.join(out, "solid.h5")
        with h5py.File(self.fluid) as f, h5py.File(self.solid) as s:
            self.layers = s.attrs["layers"].decode().split(",")
            self.name = "sandwich plate" if "foam" in self.layers else "steel plate"
            self.dx = (f.attrs["x_max"] - f.attrs["x_min"]) / f.attrs["nx"]
            c = s["coupling"]
            t = c["t"][:]
            self.nodes = len(t) // len(np.unique(t))
            self.t_step = t[:: self.nodes]
            self.p_I = c["p_I"][:].reshape(-1, self.nodes)
            w = f["wet_nodes"]
            first = w["t"][:] == w["t"][0]
            self.node_x = w["x"][:][first]
            self.node_face = w["face"][:][first]
            self.node_order = w["node"][:][first].astype(int)
            self.gauges = {g: {k: s["gauges"][g][k][:] for k in ("t", "u_y", "v_y", "peeq")} for g in ("P1", "P2")}
            e = s["energies"]
            self.energies = {k: e[k][:] for k in e}
            el = s["energies_by_layer"]
            self.layer_energies = {k: el[k][:] for k in el}
            self.field_groups = [(g, f["fields"][g].attrs["time"]) for g in f["fields"]]
            self.solid_groups = [(g, s["fields"][g].attrs["time"]) for g in s["fields"]]
            self.label = f"{self.name} (fluid {self.dx * 100:g} cm)"

    def face_node(self, face):
        """Column of /coupling of the wet node of `face` (0 lower, 1 upper) nearest r = 0."""
        on = np.nonzero(self.node_face == face)[0]
        return self.node_order[on[np.argmin(np.abs(self.node_x[on]))]]

    def face_pressure(self, face):
        return self.t_step, self.p_I[:, self.face_node(face)]

    def face_profile(self, time, face=0):
        """x and p_I of every wet node of `face` at the step ending nearest `time`."""
        i = int(np.argmin(np.abs(self.t_step - time)))
        on = np.nonzero(self.node_face == face)[0]
        order = on[np.argsort(self.node_x[on])]
        return self.t_step[i], self.node_x[order], self.p_I[i, self.node_order[order]]


def plot_histories(runs, png, plt):
    fig, ax = plt.subplots(2, 4, figsize=(19, 8), sharex=True)
    styles = ["-", "--"]
    for run, ls in zip(runs, styles):
        for row, (g, face) in enumerate((("P1", 0), ("P2", 1))):
            t, p = run.face_pressure(face)
            ax[row, 0].plot(t * 1e3, p / 1e6, ls, label=run.label)
            gs = run.gauges[g]
            ax[row, 1].plot(gs["t"] * 1e3, gs["u_y"] * 1e3, ls, label=run.label)
            ax[row, 2].plot(gs["t"] * 1e3, gs["v_y"], ls, label=run.label)
            ax[row, 3].plot(gs["t"] * 1e3, gs["peeq"], ls, label=run.label)
    where = {"P1": "P1, centre of the lower (wet) face", "P2": "P2, centre of the upper face"}
    for row, g in enumerate(("P1", "P2")):
        for col, what in enumerate(("pressure p_I (MPa)", "displacement u_y (mm)", "velocity v_y (m/s)", "PEEQ")):
            ax[row, col].set_title(f"{where[g]}: {what.split(' (')[0]}", fontsize=10)
            ax[row, col].set_ylabel(what)
            ax[row, col].grid(alpha=0.3)
        ax[row, 0].legend(fontsize=8)
    for col in range(4):
        ax[1, col].set_xlabel("t (ms)")
    fig.suptitle("UNDEX under a clamped plate: histories at the plate's centre (paper Figs 5.4, 5.7, 5.8, 5.9)")
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def plot_face_pressure(runs, png, plt):
    fig, ax = plt.subplots(1, len(runs), figsize=(7 * len(runs), 4.5), sharey=True, squeeze=False)
    for a, run in zip(ax[0], runs):
        for time in FACE_TIMES:
            t, x, p = run.face_profile(time)
            a.plot(x, p / 1e6, label=f"t = {t * 1e3:.3f} ms")
        a.set_title(f"{run.label}: pressure p_I along the lower wet face", fontsize=10)
        a.set_xlabel("r (m)")
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    ax[0, 0].set_ylabel("p_I (MPa)")
    fig.suptitle("Pressure on the lower wet face (paper Fig. 5.5)")
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def plot_energies(runs, png, plt):
    fig, ax = plt.subplots(2, len(runs), figsize=(7 * len(runs), 7), sharex=True, squeeze=False,
                           gridspec_kw={"height_ratios": [3, 1]})
    for k, run in enumerate(runs):
        a = ax[0, k]
        e, el = run.energies, run.layer_energies
        scale = 2 * np.pi / 1e6  # per radian in axisymmetry: the whole plate, MJ
        a.plot(e["t"] * 1e3, e["external"] * scale, "k", lw=2, label="external work")
        a.plot(e["t"] * 1e3, e["kinetic"] * scale, label="kinetic")
        a.plot(e["t"] * 1e3, e["elastic"] * scale, label="elastic")
        a.plot(e["t"] * 1e3, e["plastic"] * scale, label="plastic dissipation, all layers")
        if "viscous" in e:
            a.plot(e["t"] * 1e3, e["viscous"] * scale, label="bulk viscosity's dissipation")
        names = {0: "front face", 1: "core", 2: "back face"} if len(run.layers) == 3 else {0: "plate"}
        if len(run.layers) > 1:
            for layer, law in enumerate(run.layers):
                a.plot(el["t"] * 1e3, el[f"plastic_{layer}"] * scale, ":",
                       label=f"plastic dissipation, {names.get(layer, layer)} ({law})")
        a.set_title(run.label, fontsize=10)
        a.set_ylabel("energy of the plate (MJ)")
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
        b = ax[1, k]
        ref = np.maximum(np.abs(e["external"]), 1e-30)
        rel = np.where(np.abs(e["external"]) > 1e-3 * np.abs(e["external"]).max(), e["balance_error"] / ref, np.nan)
        b.plot(e["t"] * 1e3, rel, "r")
        b.set_ylabel("balance error / external")
        b.set_xlabel("t (ms)")
        b.grid(alpha=0.3)
    fig.suptitle("Energies of the plates (paper Fig. 5.10); balance error = kinetic + internal + viscous + "
                 "hourglass + coupling loss - external", fontsize=10)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def block(a, k):
    """Block means of k × k cells (nan-aware), the last blocks possibly smaller."""
    if k <= 1:
        return a
    ny, nx = a.shape
    py, px = -ny % k, -nx % k
    b = np.pad(a.astype(float), ((0, py), (0, px)), constant_values=np.nan)
    b = b.reshape(b.shape[0] // k, k, b.shape[1] // k, k)
    with np.errstate(invalid="ignore"):
        return np.nanmean(b, axis=(1, 3))


def read_picture(run, group, width):
    """Cell averages of one fields output, block-averaged to at most `width` cells across, with the structure
    masked (phi_s >= 0)."""
    with h5py.File(run.fluid) as f:
        a = f.attrs
        g = f["fields"][group]
        k = max(1, int(np.ceil(a["nx"] / width)))
        struct = g["phi_s"][:] >= 0 if "phi_s" in g else np.zeros((a["ny"], a["nx"]), bool)
        fields = {}
        for name in ("p", "rho", "phi", "void_fraction"):
            if name in g:
                v = g[name][:].astype(float)
                if name in ("p", "rho"):
                    v[struct] = np.nan
                fields[name] = block(v, k)
        fields["structure"] = block(struct.astype(float), k) > 0.5
        dx = (a["x_max"] - a["x_min"]) / a["nx"] * k
        dy = (a["y_max"] - a["y_min"]) / a["ny"] * k
        return fields, (a["x_min"], a["y_min"], dx, dy)


def schlieren(rho, dx, dy):
    """Numerical schlieren exp(-15 |grad rho| / max |grad rho|) (dark where the density changes)."""
    r = np.where(np.isnan(rho), np.nanmean(rho), rho)
    gy, gx = np.gradient(r, dy, dx)
    g = np.hypot(gx, gy)
    g[np.isnan(rho)] = 0
    return np.exp(-15 * g / max(g.max(), 1e-30))


def plate_outline(run, time):
    """Lower and upper face of the deformed plate (x, y) from the structure's fields output nearest `time`."""
    with h5py.File(run.solid) as s:
        g, _ = min(run.solid_groups, key=lambda gt: abs(gt[1] - time))
        ref = s["nodes"][:]
        pos = s["fields"][g]["position"][:]
    lo, hi = np.isclose(ref[:, 1], ref[:, 1].min()), np.isclose(ref[:, 1], ref[:, 1].max())
    out = []
    for m in (lo, hi):
        o = np.argsort(pos[m, 0])
        out.append((pos[m, 0][o], pos[m, 1][o]))
    return out


def mirrored(a):
    return np.concatenate([a[:, ::-1], a], axis=1)


def draw_scene(ax, fields, geom, kind, plate, title, plt, vmax=None):
    x0, y0, dx, dy = geom
    ny, nx = fields["p"].shape
    ext = [-(x0 + nx * dx), x0 + nx * dx, y0, y0 + ny * dy]
    if kind == "pressure":
        p = mirrored(fields["p"]) / 1e6
        im = ax.imshow(p, origin="lower", extent=ext, cmap="jet", vmin=0, vmax=vmax or np.nanmax(p),
                       interpolation="nearest")
    else:
        im = ax.imshow(mirrored(schlieren(fields["rho"], dx, dy)), origin="lower", extent=ext, cmap="gray",
                       vmin=0, vmax=1, interpolation="nearest")
    xs = (np.arange(2 * nx) + 0.5) * dx - (x0 + nx * dx)
    ys = y0 + (np.arange(ny) + 0.5) * dy
    if "phi" in fields and np.nanmin(fields["phi"]) < 0 < np.nanmax(fields["phi"]):
        ax.contour(xs, ys, mirrored(fields["phi"]), levels=[0], colors="white" if kind == "pressure" else "red",
                   linewidths=0.8)
    if "void_fraction" in fields and np.nanmax(fields["void_fraction"]) > 1e-6:
        ax.contour(xs, ys, mirrored(fields["void_fraction"]), levels=[1e-6], colors="cyan", linewidths=0.6)
    if plate is not None:
        (xl, yl), (xu, yu) = plate
        xx = np.concatenate([-xl[::-1], xl])
        ax.fill_between(xx, np.interp(xx, np.concatenate([-xl[::-1], xl]), np.concatenate([yl[::-1], yl])),
                        np.interp(np.abs(xx), xu, yu), color="0.55")
    ax.set_xlim(-5, 5)
    ax.set_ylim(-4.5, 2.5)
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=9)
    ax.tick_params(labelsize=7)
    return im


def plot_snapshots(run, png, width, plt):
    groups = [(g, t) for g, t in run.field_groups if t > 0]
    if not groups:
        return
    cols = 3
    rows = int(np.ceil(len(groups) / cols))
    for kind in ("pressure", "schlieren"):
        fig, ax = plt.subplots(rows, cols, figsize=(4.6 * cols, 3.6 * rows), squeeze=False)
        for a in ax.flat[len(groups):]:
            a.axis("off")
        for a, (g, t) in zip(ax.flat, groups):
            fields, geom = read_picture(run, g, width)
            im = draw_scene(a, fields, geom, kind, plate_outline(run, t), f"t = {t * 1e3:.2f} ms", plt)
            if kind == "pressure":
                fig.colorbar(im, ax=a, shrink=0.8, label="p (MPa)")
        gas = "white" if kind == "pressure" else "red"
        fig.suptitle(f"{run.label}: {kind} (paper Figs 5.2, 5.3); gas outlined {gas}, cavitation cyan, plate grey",
                     fontsize=10)
        fig.tight_layout()
        fig.savefig(png.replace(".png", f"_{kind}.png"), dpi=100)
        plt.close(fig)


def animate(run, gif, plt, max_frames=160):
    from matplotlib.animation import FuncAnimation, PillowWriter

    with h5py.File(run.fluid) as f:
        if "frames" not in f:
            return False
        fr = f["frames"]
        a = dict(fr.attrs)
        names = sorted(fr)
        names = names[:: max(1, int(np.ceil(len(names) / max_frames)))]
        stride = int(a["stride"])
        nx, ny = int(np.ceil(a["nx"] / stride)), int(np.ceil(a["ny"] / stride))
        dx, dy = (a["x_max"] - a["x_min"]) / a["nx"] * stride, (a["y_max"] - a["y_min"]) / a["ny"] * stride
        frames = [(fr[n].attrs["time"], fr[n]["p"][:], fr[n]["phi"][:], fr[n]["void_fraction"][:]) for n in names]
    geom = (a["x_min"], a["y_min"], dx, dy)
    vmax = 0.5 * max(np.nanmax(p) for t, p, _, _ in frames if t > 0) / 1e6 if len(frames) > 1 else None
    fig, ax = plt.subplots(figsize=(6, 4.6))

    def draw(i):
        ax.clear()
        t, p, phi, vf = frames[i]
        draw_scene(ax, {"p": p, "phi": phi, "void_fraction": vf}, geom, "pressure", plate_outline(run, t),
                   f"{run.label}: p (0 to {vmax:.0f} MPa), t = {t * 1e3:.2f} ms", plt, vmax=vmax)

    anim = FuncAnimation(fig, draw, frames=len(frames))
    anim.save(gif, writer=PillowWriter(fps=10))
    plt.close(fig)
    return True


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case1", help="output directory of cases/undex_steel_plate.case")
    ap.add_argument("case2", help="output directory of cases/undex_sandwich_plate.case")
    ap.add_argument("--png-dir")
    ap.add_argument("--no-animation", action="store_true")
    ap.add_argument("--width", type=int, default=400, help="at most this many picture cells across (default 400)")
    args = ap.parse_args()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = [Run(args.case1), Run(args.case2)]
    d = args.png_dir or os.path.dirname(os.path.abspath(args.case2))
    os.makedirs(d, exist_ok=True)
    written = []
    for name, fn in (("undex_histories.png", plot_histories), ("undex_face_pressure.png", plot_face_pressure),
                     ("undex_energies.png", plot_energies)):
        fn(runs, os.path.join(d, name), plt)
        written.append(name)
    for run, tag in zip(runs, ("steel", "sandwich")):
        plot_snapshots(run, os.path.join(d, f"undex_snapshots_{tag}.png"), args.width, plt)
        written += [f"undex_snapshots_{tag}_pressure.png", f"undex_snapshots_{tag}_schlieren.png"]
    if not args.no_animation and animate(runs[1], os.path.join(d, "undex_sandwich.gif"), plt):
        written.append("undex_sandwich.gif")
    for w in written:
        print(os.path.join(d, w))


if __name__ == "__main__":
    main()
