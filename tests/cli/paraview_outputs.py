"""ParaView (pvbatch, Debian's paraview) opens a coupled 2D run's outputs through their XDMF files
(tests/cli/paraview_outputs.sh runs it): solid.xmf's last time has the deformed geometry (solid.h5 position),
displacement and velocity as 3-component point vectors, and Warp By Vector by the displacement with scale
factor −1 takes the points back to the reference nodes (solid.h5 /nodes; read here with h5py, not through
ParaView): node order, vector layout and geometry agree. fluid.xmf opens with its cell fields.

    pvbatch paraview_outputs.py OUT_DIR
"""
import sys

import h5py
import numpy as np
from paraview import servermanager as sm
from paraview import simple as pv
from vtk.numpy_interface import dataset_adapter as dsa

out = sys.argv[1]
failed = []


def check(ok, what):
    print(("ok: " if ok else "FAIL: ") + what)
    if not ok:
        failed.append(what)


with h5py.File(f"{out}/solid.h5", "r") as s:
    last = sorted(s["fields"])[-1]
    t_last = s["fields"][last].attrs["time"]
    position = s["fields"][last]["position"][:]
    reference = s["nodes"][:]
    u = s["fields"][last]["displacement"][:]

solid = pv.XDMFReader(FileNames=[f"{out}/solid.xmf"])
solid.UpdatePipeline(t_last)
times = list(solid.TimestepValues)
check(abs(times[-1] - t_last) <= 1e-12 * max(t_last, 1e-30), f"solid.xmf's last time {times[-1]} is solid.h5's {t_last}")
data = dsa.WrapDataObject(sm.Fetch(solid))
pts = np.asarray(data.Points)
check(pts.shape == (len(position), 3), f"solid.xmf has {pts.shape[0]} points (solid.h5: {len(position)})")
check(np.max(np.abs(pts[:, :2] - position)) <= 1e-12, "the points are the deformed positions")
for name in ("displacement", "velocity"):
    arr = data.PointData[name]
    check(arr is not None and np.asarray(arr).shape == (len(position), 3), f"{name} is a point vector of 3 components")
check(np.max(np.abs(u[:, :2])) > 0, f"the plate has moved (largest displacement {np.max(np.abs(u)):.3e} m)")
warp = pv.WarpByVector(Input=solid, Vectors=["POINTS", "displacement"], ScaleFactor=-1.0)
warp.UpdatePipeline(t_last)
back = np.asarray(dsa.WrapDataObject(sm.Fetch(warp)).Points)
err = np.max(np.abs(back[:, :2] - reference))
check(err <= 1e-12, f"Warp By Vector (displacement, scale -1) gives the reference nodes (largest error {err:.1e} m)")

fluid = pv.XDMFReader(FileNames=[f"{out}/fluid.xmf"])
fluid.UpdatePipeline(list(fluid.TimestepValues)[-1])
fd = dsa.WrapDataObject(sm.Fetch(fluid))
names = list(fd.CellData.keys())
check(all(n in names for n in ("rho", "p", "u", "v")), f"fluid.xmf has the cell fields ({', '.join(names)})")
print(f"{len(failed)} failed")
sys.exit(1 if failed else 0)
