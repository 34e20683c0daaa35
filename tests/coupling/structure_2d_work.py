#!/usr/bin/python3
"""The structure side of 2D coupling over real sockets (issue 15, items 3 and 5): this script plays a 2D fluid
against undex-solid (a plane-strain plate wet on both faces, clamped; the same wet on its back only; the
same plate axisymmetric from the axis, wet in front) and undex-rigid (an axisymmetric rigid face of five nodes), with a fluid state that
changes in space and time (a spell of tension makes some nodes cavitate). From its own side of the messages
only, as the fluid does (docs/protocol.md):

- the Hello's faces in the contract's order (front = face 0 with normal +y, back = face 1 with normal −y, or
  face 0 when wet alone), each node at its face's y in the fluid's frame, x increasing along a face;
- the Hello's areas and normals are those of the area vectors of its positions, recomputed here;
- each Offer starts where the last Answer ended;
- u_I is each node's motion over the step along its normal n_k of the start of the step, n_k recomputed here
  from the Offer's positions (bound 1e-11 m/s, measured 4.2e-12: round-off of positions of 0.1 m over a step
  of 2e-7 s);
- every answer keeps p_I = p_L − Z_L (u_I − u_L) − geometric (bound 2e-16 of 100 MPa, measured 7.5e-17:
  round-off) or p_I = p_floor;
- the work W = Σ over steps and nodes of A_k p_I u_I Δt, with A_k from the Offer's positions, equals the
  structure's external work in solid.h5 /energies (its own nodal forces times displacements) to 1e-8
  relative (measured 1e-15).

    structure_2d_work.py BIN_DIR TESTS_DIR PYTHON_DIR WORK_DIR
"""
import math
import os
import subprocess
import sys

import h5py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from checks import check, finish  # noqa: E402

BIN, TESTS, PYDIR, WORK = [os.path.abspath(p) for p in sys.argv[1:5]]
sys.path.insert(0, PYDIR)
import coupling_pb2 as pb  # noqa: E402
import zmq  # noqa: E402

STEPS = 200
P_FLOOR = 2338.0


def area_vectors(x, y, face, alpha, normal_x, normal_y):
    """a_k = Σ n_s ∫ N_k r ds over the segments of k's face, the side of the structure taken from the given
    normals (one side per face). Returns areas and unit normals."""
    n = len(x)
    ax, ay = [0.0] * n, [0.0] * n
    for k in range(n - 1):
        if face[k] != face[k + 1]:
            continue
        xa, xb, dx, dy = x[k], x[k + 1], x[k + 1] - x[k], y[k + 1] - y[k]
        sa, sb = ((2 * xa + xb) / 6, (xa + 2 * xb) / 6) if alpha == 1 else (0.5, 0.5)
        ax[k] += -dy * sa
        ay[k] += dx * sa
        ax[k + 1] += -dy * sb
        ay[k + 1] += dx * sb
    sign = {}
    for k in range(n):
        sign[face[k]] = sign.get(face[k], 0.0) + normal_x[k] * ax[k] + normal_y[k] * ay[k]
    A = [math.hypot(ax[k], ay[k]) for k in range(n)]
    s = [1.0 if sign[face[k]] >= 0 else -1.0 for k in range(n)]
    return A, [s[k] * ax[k] / A[k] for k in range(n)], [s[k] * ay[k] / A[k] for k in range(n)]


def fluid_state(step, x, face):
    """p_L, u_L, Z_L, geometric at every node: a pressure that varies along the plate and in time on face 0,
    a spell of tension on face 1 (cavitation)."""
    p_L, u_L = [], []
    for k in range(len(x)):
        if face[k] == 0:
            p_L.append(1e5 + 2e7 * (1 + math.sin(0.05 * step)) * (1 - 2 * x[k]))
        else:
            p_L.append(-3e7 if 80 < step < 140 else 1e5)
        u_L.append(0.3 * math.cos(0.1 * step))
    return p_L, u_L, [1.5e6] * len(x), [1e3 * xi for xi in x]


def run(name, command, out, layout):
    ctx = zmq.Context.instance()
    sock = ctx.socket(zmq.PAIR)
    sock.setsockopt(zmq.LINGER, 0)
    endpoint = "ipc://" + os.path.join(WORK, name + ".ipc")
    sock.bind(endpoint)
    log = open(os.path.join(WORK, name + ".log"), "w")
    proc = subprocess.Popen(command + ["--set", f"output.directory={out}", "--couple", endpoint], stdout=log,
                            stderr=subprocess.STDOUT)

    def recv(kind):
        if not sock.poll(30000):
            raise RuntimeError(f"{name}: no {kind} within 30 s")
        e = pb.Envelope()
        e.ParseFromString(sock.recv())
        if e.WhichOneof("body") != kind:
            raise RuntimeError(f"{name}: {e.WhichOneof('body')} where {kind} was due")
        return e

    def send(step, **body):
        e = pb.Envelope(protocol=1, step=step)
        for k, v in body.items():
            getattr(e, k).CopyFrom(v)
        sock.send(e.SerializeToString())

    try:
        h = recv("hello").hello
        face = list(h.face) or [0] * len(h.x)
        A, nx, ny = area_vectors(list(h.x), list(h.y), face, h.alpha, list(h.normal_x), list(h.normal_y))
        worst = max(max(abs(A[k] - h.area[k]) / A[k], math.hypot(nx[k] - h.normal_x[k], ny[k] - h.normal_y[k]))
                    for k in range(len(A)))
        check(h.dimension == 2 and worst < 1e-12,
              f"{name}: Hello of {len(A)} nodes on {max(face) + 1} face(s): areas and normals of its positions "
              f"(worst {worst:.1e})", f"dimension {h.dimension}")
        # The contract's layout: per face its y and normal_y, the nodes in order of increasing x.
        got = [(face[k], h.y[k], h.normal_x[k], h.normal_y[k]) for k in range(len(face))]
        want = [(f, y, 0.0, ny) for f, (y, ny, count) in enumerate(layout) for _ in range(count)]
        check(got == want and all(face[k] != face[k + 1] or h.x[k] < h.x[k + 1] for k in range(len(face) - 1)),
              f"{name}: faces, their y and normals as the contract orders them: {layout}", f"{got}")
        send(0, welcome=pb.Welcome(solver="structure_2d_work.py", version="1", end_time=1.0))
        work, time, u_max, worst_u, worst_p, cavitating, moved = 0.0, 0.0, 0.0, 0.0, 0.0, 0, ""
        last = None
        for step in range(1, STEPS + 1):
            o = recv("offer").offer
            x, y = list(o.x), list(o.y)
            if last is not None and (x, y) != last and not moved:
                moved = f"step {step}: the Offer's positions are not the last Answer's"
            A, nx, ny = area_vectors(x, y, face, h.alpha, nx, ny)
            dt = min(o.dt, 2e-7)
            p_L, u_L, Z_L, geo = fluid_state(step, x, face)
            send(step, grant=pb.Grant(dt=dt, time=time, p_L=p_L, u_L=u_L, Z_L=Z_L, geometric=geo, p_floor=P_FLOOR))
            a = recv("answer").answer
            for k in range(len(x)):
                p, u = a.p_I[k], a.u_I[k]
                work += A[k] * p * u * dt
                u_max = max(u_max, abs(u))
                worst_u = max(worst_u, abs((nx[k] * (a.x[k] - x[k]) + ny[k] * (a.y[k] - y[k])) / dt - u))
                if p == P_FLOOR:
                    cavitating += 1
                else:
                    worst_p = max(worst_p, abs(p - (p_L[k] - Z_L[k] * (u - u_L[k]) - geo[k])) / 1e8)
            last = (list(a.x), list(a.y))
            time += dt
        recv("offer")
        send(STEPS + 1, stop=pb.Stop(reason="end of the 2D work check"))
        code = proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
        sock.close()
        log.close()
    check(code == 0, f"{name}: ends with status 0 on Stop", open(os.path.join(WORK, name + ".log")).read())
    check(not moved, f"{name}: each Offer starts where the last Answer ended", moved)
    check(worst_u < 1e-11,  # measured 4.2e-12
          f"{name}: u_I is the motion along n_k of the start of the step (worst {worst_u:.1e} of {u_max:.2f} m/s)")
    check(worst_p < 2e-16 and cavitating > 0,  # measured 7.5e-17
          f"{name}: p_I = p_L − Z_L (u_I − u_L) − geometric (worst {worst_p:.1e} of 100 MPa) or p_floor "
          f"({cavitating} answers)")
    with h5py.File(os.path.join(out, "solid.h5"), "r") as f:
        e = f["energies"]
        external, t_last = e["external"][-1], e["t"][-1]
    rel = abs(external - work) / abs(work)
    check(rel < 1e-8 and abs(t_last - time) <= 1e-12 * time,  # the contract's bound; measured 4e-16
          f"{name}: external work {external:.9e} J = Σ A_k p_I u_I Δt {work:.9e} J of the messages "
          f"(relative {rel:.1e})", f"last record at t = {t_last}, fluid time {time}")


os.makedirs(WORK, exist_ok=True)
plate = os.path.join(TESTS, "cases", "plate_2d.case")
# plate_2d.case: front (face 0) at y = -5 mm, normal +y; back (face 1) at +5 mm, normal −y; 5 nodes each.
run("solid-planar", [os.path.join(BIN, "undex-solid"), plate], os.path.join(WORK, "solid-planar"),
    [(-0.005, 1.0, 5), (0.005, -1.0, 5)])
# Wet on the back only: face 0 is the back.
run("solid-back-only", [os.path.join(BIN, "undex-solid"), plate, "--set", "structure.front.type=FREE"],
    os.path.join(WORK, "solid-back-only"), [(0.005, -1.0, 5)])
run("solid-axisymmetric",
    [os.path.join(BIN, "undex-solid"), plate, "--set", "geometry=AXISYMMETRIC_2D", "--set",
     "structure.plate.left.type=SYMMETRY", "--set", "structure.back.type=FREE"],
    os.path.join(WORK, "solid-axisymmetric"), [(-0.005, 1.0, 5)])
run("rigid-axisymmetric", [os.path.join(BIN, "undex-rigid"), os.path.join(TESTS, "cases", "rigid_plate_2d.case")],
    os.path.join(WORK, "rigid-axisymmetric"), [(0.0, 1.0, 5)])
finish()
