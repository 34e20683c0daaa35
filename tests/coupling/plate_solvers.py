#!/usr/bin/python3
"""The 2D Python structure solvers (rigid_plate.py --dimension 2, moving_plate.py) against a fake fluid written
here: it binds a PAIR socket, starts the solver with --couple, plays Welcome, Grants and Stop
(docs/protocol.md) and checks every Hello, Offer and Answer against closed forms computed here, not by the
solvers' code:
- area vectors (the 2D contract, docs/protocol.md): a straight face of nodes spaced L has A = L/2 at its ends
  and L inside in plane strain; in axisymmetry (per radian) A = L (2 r_end + r_next)/6 at an end (positive
  on the axis, r = 0) and L r_k inside; the normal is the face's, from the water into the plate;
- rigid_plate.py: one body velocity v at every node; per node p_I = max(p_floor, p_L − Z_L (v − u_L) − g);
  the body's central-difference equation m ΣA (v − v⁻) = h ((−p_back − k d − c v⁻) ΣA + Σ A_k p_I,k) to
  1e-12 of its terms (round-off of sums of a few terms: measured below 1e-15); steps with no node, some
  nodes and all nodes at p_floor;
- moving_plate.py: positions at the start (Offer) and end (Answer) of every step equal the reference nodes
  moved by d(t) n, d(t) = V t or D sin²(π t / T), within 1e-12 m (round-off: measured below 1e-16 m);
  u_I = ±(d(t + Δt) − d(t)) / Δt within 1e-9 relative (measured below 1e-13: the round-off of d(t + Δt) −
  d(t)); p_I as above; its record's t, dt, dt_s bitwise equal to the messages, its areas equal to the
  closed form of the step's starting positions, its work Σ p_I u_I A Δt equal to the sum formed here from the
  messages and the closed-form areas (1e-12 relative; measured below 1e-15).

    plate_solvers.py PYTHON_DIR
"""
import math
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
PYDIR = sys.argv[1]
sys.path.insert(0, PYDIR)
sys.path.insert(0, os.path.join(HERE, "..", "support"))
import zmq  # noqa: E402
import coupling_pb2 as pb  # noqa: E402
from checks import check, finish  # noqa: E402

TMP = tempfile.mkdtemp(prefix="plate_solvers.")


def closed_areas(rs, L, alpha):
    """A_k of a straight face of uniformly spaced nodes (spacing L) at radii rs (ignored in plane strain)."""
    n = len(rs)
    if not alpha:
        return np.array([L / 2] + [L] * (n - 2) + [L / 2])
    return np.array([L * (2 * rs[0] + rs[1]) / 6] + [L * rs[k] for k in range(1, n - 1)] +
                    [L * (rs[-2] + 2 * rs[-1]) / 6])


def session(name, cmd, grant_of, steps, end_time=1.0):
    """Runs one solver against the fake fluid for `steps` steps; grant_of(step, time, offer) gives the
    Grant's fields. Returns the Hello and the list of (offer, grant, answer) and checks the exit code."""
    ctx = zmq.Context()
    sock = ctx.socket(zmq.PAIR)
    sock.setsockopt(zmq.LINGER, 0)
    endpoint = f"ipc://{TMP}/{name}.ipc"
    sock.bind(endpoint)
    proc = subprocess.Popen(cmd + ["--proto-dir", PYDIR, "--couple", endpoint], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)

    def send(step, **body):
        e = pb.Envelope(protocol=1, step=step)
        for k, v in body.items():
            getattr(e, k).CopyFrom(v)
        sock.send(e.SerializeToString())

    def recv(kind, step):
        if not sock.poll(20000):
            raise RuntimeError(f"{name}: no {kind} of step {step}")
        e = pb.Envelope()
        e.ParseFromString(sock.recv())
        if e.WhichOneof("body") != kind or e.step != step:
            raise RuntimeError(f"{name}: got {e.WhichOneof('body')} of step {e.step}, not {kind} of step {step}")
        return getattr(e, kind)

    log = []
    try:
        hello = recv("hello", 0)
        send(0, welcome=pb.Welcome(solver="plate_solvers.py", version="1", end_time=end_time))
        t = 0.0
        for step in range(1, steps + 1):
            offer = recv("offer", step)
            g = pb.Grant(time=t, **grant_of(step, t, offer))
            send(step, grant=g)
            log.append((offer, g, recv("answer", step)))
            t += g.dt
        recv("offer", steps + 1)
        send(steps + 1, stop=pb.Stop(reason="end time reached"))
        out, _ = proc.communicate(timeout=20)
        check(proc.returncode == 0, f"{name}: exits 0 after the Stop", out)
    except RuntimeError as e:
        proc.kill()
        check(False, f"{name}: plays the protocol", f"{e}\n{proc.communicate()[0]}")
        hello = None
    finally:
        sock.close()
        ctx.term()
    return hello, log


def close(a, b, tol):
    return len(a) == len(b) and float(np.max(np.abs(np.asarray(a, float) - np.asarray(b, float)))) <= tol


# ---- rigid_plate.py --dimension 2: plane strain and axisymmetric (first node on the axis)
for alpha, x0, x1, nodes in ((0, -0.2, 0.2, 5), (1, 0.0, 0.3, 4)):
    m, k_s, c_d, p_back, y_front = 50.0, 1e6, 10.0, 1e5, 0.1
    xs = np.linspace(x0, x1, nodes)
    L = (x1 - x0) / (nodes - 1)
    A_ref = closed_areas(xs, L, alpha)
    floors = {3: 3.5e6, 4: 2.5e7}  # step 3: nodes 0 and 1 at the floor (p_L 1 MPa apart, Z_L v below 0.3 MPa); step 4: all

    def rigid_grant(step, t, offer):
        dt = offer.dt
        return dict(dt=dt, p_L=[2e6 + 1e6 * k for k in range(nodes)], u_L=[0.01 * k for k in range(nodes)],
                    Z_L=[1.5e6 + 1e4 * k for k in range(nodes)], geometric=[alpha * 1e3 * (k + 1) for k in range(nodes)],
                    p_floor=floors.get(step, -1e9))

    name = f"rigid_plate 2D alpha={alpha}"
    hello, log = session(f"rigid{alpha}", ["/usr/bin/python3", os.path.join(HERE, "rigid_plate.py"), "--mass", str(m),
                                           "--stiffness", str(k_s), "--damping", str(c_d), "--dt", "1e-6,2e-6",
                                           "--dimension", "2", "--alpha", str(alpha), "--nodes", str(nodes), "--x0",
                                           str(x0), "--x1", str(x1), "--y-front", str(y_front)], rigid_grant, 6)
    if hello is None:
        continue
    check(hello.dimension == 2 and hello.alpha == alpha and list(hello.face) == [0] * nodes
          and close(hello.x, xs, 1e-15) and close(hello.y, [y_front] * nodes, 0)
          and close(hello.normal_x, [0] * nodes, 0) and close(hello.normal_y, [1] * nodes, 0),
          f"{name}: Hello has the plate's nodes, face 0 and normal +y", str(hello))
    check(close(hello.area, A_ref, 1e-15 * max(A_ref)) and min(hello.area) > 0,
          f"{name}: Hello areas are the closed form {A_ref}" + (" (positive on the axis)" if alpha else ""),
          f"got {list(hello.area)}")
    d, v, last_dt, resid, pos_err, pI_err, n_floor = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, []
    for step, (offer, g, ans) in enumerate(log, 1):
        pos_err = max(pos_err, abs(offer.y[0] - y_front - d), max(abs(y - offer.y[0]) for y in offer.y),
                      max(abs(u - v) for u in offer.velocity))
        vn = ans.u_I[0]
        h = 0.5 * g.dt if step == 1 else 0.5 * (g.dt + last_dt)
        terms = [m * A_ref.sum() * vn, m * A_ref.sum() * v, h * (-p_back - k_s * d - c_d * v) * A_ref.sum()]
        terms += [h * A * p for A, p in zip(A_ref, ans.p_I)]
        resid = max(resid, abs(terms[0] - terms[1] - sum(terms[2:])) / max(abs(x) for x in terms))
        rel = [g.p_L[k] - g.Z_L[k] * (vn - g.u_L[k]) - g.geometric[k] for k in range(nodes)]
        pI_err = max(pI_err, max(abs(u - vn) for u in ans.u_I),
                     max(abs(p - max(g.p_floor, r)) / abs(r) for p, r in zip(ans.p_I, rel)))
        n_floor.append(sum(p == g.p_floor for p in ans.p_I))
        d += g.dt * vn
        pos_err = max(pos_err, max(abs(y - y_front - d) for y in ans.y), float(np.max(np.abs(np.array(ans.x) - xs))))
        v, last_dt = vn, g.dt
    check(resid <= 1e-12, f"{name}: the body's equation of motion holds with every node's p_I "
          f"(relative residual {resid:.2e} <= 1e-12)")
    check(pI_err <= 1e-12, f"{name}: one velocity, p_I = max(p_floor, p_L − Z_L (u_I − u_L) − g) at every node "
          f"(relative error {pI_err:.2e} <= 1e-12)")
    check(pos_err <= 1e-12, f"{name}: Offer and Answer positions and velocities follow the body ({pos_err:.2e} m)")
    check(n_floor[0] == 0 and 0 < n_floor[2] < nodes and n_floor[3] == nodes,
          f"{name}: steps with none, some and all nodes at p_floor ({n_floor})")


# ---- moving_plate.py
def moving(name, opts, alpha, faces, nodes, xc, yc, length, angle, thickness, dfun, d0, dts):
    th = math.radians(angle)
    tvec, nvec = np.array([math.cos(th), math.sin(th)]), np.array([-math.sin(th), math.cos(th)])
    ref, sign = [], []
    for f in range(faces):
        off = 0.0 if faces == 1 else (-0.5 if f == 0 else 0.5) * thickness
        for s in np.linspace(-length / 2, length / 2, nodes):
            ref.append(np.array([xc, yc]) + off * nvec + s * tvec)
            sign.append(1.0 if f == 0 else -1.0)
    ref, sign = np.array(ref), np.array(sign)
    L = length / (nodes - 1)

    def areas(pos):  # closed form per face from the positions
        return np.concatenate([closed_areas(pos[f * nodes:(f + 1) * nodes, 0], L, alpha) for f in range(faces)])

    def grant(step, t, offer):
        n = len(offer.x)
        # p_L 10 MPa apart from node to node, Z_L |u_I − u_L| below 3 MPa: the floor of step 2 holds half the nodes.
        return dict(dt=dts[(step - 1) % len(dts)], p_L=[1e5 + 1e7 * k for k in range(n)], u_L=[0.2 - 0.05 * k for k in range(n)],
                    Z_L=[1.4e6 + 2e4 * k for k in range(n)], geometric=[alpha * 500.0 * k for k in range(n)],
                    p_floor=1e5 + 1e7 * (n / 2 - 0.5) if step == 2 else -1e9)

    hist = os.path.join(TMP, f"{name}.h5")
    hello, log = session(name, ["/usr/bin/python3", os.path.join(HERE, "moving_plate.py"), "--alpha", str(alpha),
                                "--faces", str(faces), "--nodes", str(nodes), "--xc", repr(xc), "--yc", repr(yc),
                                "--length", repr(length), "--angle", repr(angle), "--thickness", repr(thickness),
                                "--dt", repr(max(dts)), "--history", hist] + opts, grant, 8)
    if hello is None:
        return
    normals = sign[:, None] * nvec[None, :]
    A0 = areas(ref)
    check(hello.dimension == 2 and hello.alpha == alpha and list(hello.face) == [f for f in range(faces) for _ in range(nodes)]
          and close(hello.x, ref[:, 0], 1e-12) and close(hello.y, ref[:, 1], 1e-12)
          and close(hello.normal_x, normals[:, 0], 1e-15) and close(hello.normal_y, normals[:, 1], 1e-15),
          f"{name}: Hello has the faces' nodes in order and their normals into the plate", str(hello))
    check(close(hello.area, A0, 1e-14 * max(A0)) and min(hello.area) > 0,
          f"{name}: Hello areas are the closed form" + (" (positive on the axis)" if alpha else ""),
          f"got {list(hello.area)}, closed form {list(A0)}")
    t, u_prev, pos_err, u_err, p_err, work = 0.0, sign * d0, 0.0, 0.0, 0.0, []
    for offer, g, ans in log:
        start = ref + dfun(t) * nvec
        end = ref + dfun(t + g.dt) * nvec
        pos_err = max(pos_err, float(np.max(np.abs(np.c_[offer.x, offer.y] - start))),
                      float(np.max(np.abs(np.c_[ans.x, ans.y] - end))))
        u_ref = sign * (dfun(t + g.dt) - dfun(t)) / g.dt
        scale = max(float(np.max(np.abs(u_ref))), 1e-300)
        u_err = max(u_err, float(np.max(np.abs(np.array(ans.u_I) - u_ref))) / scale,
                    float(np.max(np.abs(np.array(offer.velocity) - u_prev))) / scale)
        p_ref = np.maximum(g.p_floor, np.array(g.p_L) - np.array(g.Z_L) * (np.array(ans.u_I) - np.array(g.u_L))
                           - np.array(g.geometric))
        p_err = max(p_err, float(np.max(np.abs(np.array(ans.p_I) - p_ref) / np.abs(p_ref))))
        work.append(float(np.sum(np.array(ans.p_I) * np.array(ans.u_I) * areas(start) * g.dt)))
        u_prev, t = np.array(ans.u_I), t + g.dt
    check(pos_err <= 1e-12, f"{name}: Offer and Answer positions are the nodes moved by d(t) n ({pos_err:.2e} m <= 1e-12)")
    check(u_err <= 1e-9, f"{name}: u_I = ±(d(t+dt) - d(t))/dt, Offer velocity = the last u_I "
          f"(relative error {u_err:.2e} <= 1e-9)")
    check(p_err <= 1e-12, f"{name}: p_I = max(p_floor, p_L − Z_L (u_I − u_L) − g) (relative error {p_err:.2e})")
    at_floor = [p == log[1][1].p_floor for p in log[1][2].p_I]
    check(any(at_floor) and not all(at_floor), f"{name}: step 2 holds some nodes, not all, at p_floor ({at_floor})")
    with h5py.File(hist, "r") as f:
        c = f["coupling"]
        rt, rdt, rdts, rA, rW = c["t"][:], c["dt"][:], c["dt_s"][:], c["area"][:], c["work"][:]
        rp, ru = c["p_I"][:], c["u_I"][:]
    sent_t = np.cumsum([0.0] + [g.dt for _, g, _ in log])[:-1]
    sent_dt = np.array([g.dt for _, g, _ in log])
    check(len(rt) == len(log) and np.array_equal(rt, sent_t) and np.array_equal(rdt, sent_dt)
          and np.all(rdts == max(dts)) and np.array_equal(rp, [a.p_I for _, _, a in log])
          and np.array_equal(ru, [a.u_I for _, _, a in log]),
          f"{name}: the record's t, dt, dt_s, p_I, u_I are the messages' bit for bit", f"{rt} {sent_t} {rdt}")
    t, a_err = 0.0, 0.0
    for k, (_, g, _) in enumerate(log):
        ref_A = areas(ref + dfun(t) * nvec)
        a_err = max(a_err, float(np.max(np.abs(rA[k] - ref_A))) / float(np.max(ref_A)))
        t += g.dt
    w_err = float(np.max(np.abs(rW - work) / np.abs(work)))
    check(a_err <= 1e-12, f"{name}: recorded areas are the closed form of each step's starting positions ({a_err:.2e})")
    check(w_err <= 1e-12, f"{name}: recorded work Σ p_I u_I A Δt per step is the messages' ({w_err:.2e} <= 1e-12)")


V = -1.0  # pushes face 0's water
moving("moving plane 2 faces 30deg", ["--speed", repr(V)], 0, 2, 6, 0.013, -0.02, 0.5, 30.0, 0.03,
       lambda t: V * t, V, [1e-4, 0.6e-4])
D, T, TH = -0.002, 8e-3, 20.0  # d < 0: along −n = (sin θ, −cos θ), away from the axis
moving("moving axisymmetric from the axis 20deg", ["--amplitude", repr(D), "--period", repr(T)], 1, 1, 5,
       0.2 * math.cos(math.radians(TH)), 0.1, 0.4, TH, 0.0, lambda t: D * math.sin(math.pi * t / T) ** 2, 0.0,
       [1e-3, 0.5e-3])
finish()
