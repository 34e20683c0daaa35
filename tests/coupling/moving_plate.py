#!/usr/bin/python3
"""A structure solver with a prescribed motion, for the 2D verification of the fluid's moving structure
(issue 15): a straight plate moves along its normal by d(t), whatever the water does; it answers the
pressures the water puts on it. It speaks the coupling protocol (docs/protocol.md) like rigid_plate.py.

    moving_plate.py [--alpha 0|1] [--faces 1|2] [--nodes N] [--xc XC] [--yc YC] [--length L] [--angle DEG]
                    [--thickness H] (--speed V | --amplitude D --period T) [--dt DT] [--history FILE.h5]
                    [--proto-dir DIR] --couple ENDPOINT

Geometry (the fluid's frame): t = (cos θ, sin θ) along the plate, n = (−sin θ, cos θ). One face (--faces 1):
N nodes at (xc, yc) + s t, s from −L/2 to L/2, normal n (from the water into the plate). Two faces: a plate
of thickness H centred on (xc, yc) with water on both sides: face 0 (front) at (xc, yc) − H/2 n with normal
n, face 1 (back) at (xc, yc) + H/2 n with normal −n; the nodes of each face in order of s.
Motion: the whole plate moves by d(t) n, d(t) = V t (--speed; V < 0 pushes the plate into face 0's water) or
d(t) = D sin²(π t / T) (--amplitude, --period: through D and back in T). Node k of face 0 has the normal
velocity d', a node of face 1 −d'.
Each step n (t the sum of the Δt granted before): Offer the positions at t (from d(t)) and the normal
velocity of the last half step (the last u_I answered; at the first step the exact d'(0)); Answer
u_I = ±[d(t + Δt) − d(t)] / Δt, p_I = max(p_floor, p_L − Z_L (u_I − u_L) − geometric) per node, and the
positions at t + Δt. The area vector of each node is Σ over its segments of n_s ∫ N_k r ds (r = x in
axisymmetry, per radian; r = 1 in plane strain), from the positions at the start of the step.

Record (--history FILE.h5, written when the run ends, also on a failure), group /coupling, one row per step:
t, dt, dt_s (the step offered), work (Σ_k p_I,k u_I,k A_k Δt) and per node (steps × nodes) p_I, u_I, p_L,
u_L, Z_L, area (A_k of the start of the step), x, y (the positions answered, at t + Δt), heartbeats (how many
arrived while this side waited for the step's Grant); /coupling/face the
face of each node. tests/support/checks.py coupled_steps reads it like solid.h5. Exit codes: 0 when the fluid
ends the run, 3 on a coupling failure, 4 on SIGTERM or SIGHUP.
"""
import argparse
import math
import signal
import sys


def area_vectors(xs, ys, alpha, sign):
    """Area vector of each node of one face (nodes in order; sign +1 when the normal into the structure is to
    the left of the direction of travel, −1 to the right)."""
    a = [[0.0, 0.0] for _ in xs]
    for i in range(len(xs) - 1):
        nx, ny = -sign * (ys[i + 1] - ys[i]), sign * (xs[i + 1] - xs[i])  # n_s L
        wa, wb = ((2 * xs[i] + xs[i + 1]) / 6, (xs[i] + 2 * xs[i + 1]) / 6) if alpha else (0.5, 0.5)
        a[i][0] += nx * wa
        a[i][1] += ny * wa
        a[i + 1][0] += nx * wb
        a[i + 1][1] += ny * wb
    return a


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--alpha", type=int, choices=[0, 1], default=0, help="0 plane strain, 1 axisymmetric (x = r)")
    ap.add_argument("--faces", type=int, choices=[1, 2], default=1, help="wet faces: 1 (front) or 2 (both)")
    ap.add_argument("--nodes", type=int, default=21, help="nodes per face (at least 2)")
    ap.add_argument("--xc", type=float, default=0.0, help="x of the plate's centre, m")
    ap.add_argument("--yc", type=float, default=0.0, help="y of the plate's centre, m")
    ap.add_argument("--length", type=float, default=1.0, help="length of the plate, m")
    ap.add_argument("--angle", type=float, default=0.0, help="angle θ of the plate to the x axis, degrees")
    ap.add_argument("--thickness", type=float, default=0.0, help="two faces: the plate's thickness, m")
    ap.add_argument("--speed", type=float, help="d(t) = V t, m/s")
    ap.add_argument("--amplitude", type=float, help="d(t) = D sin²(π t / T): D, m")
    ap.add_argument("--period", type=float, help="d(t) = D sin²(π t / T): T, s")
    ap.add_argument("--dt", type=float, default=1.0, help="the step offered, s")
    ap.add_argument("--timeout", type=float, default=30.0, help="longest wait for the fluid, s")
    ap.add_argument("--history", help="HDF5 record of every step (see above)")
    ap.add_argument("--proto-dir", help="directory of coupling_pb2.py")
    ap.add_argument("--couple", required=True, help="the fluid's endpoint")
    a = ap.parse_args()
    if (a.speed is None) == (a.amplitude is None) or (a.amplitude is not None and not (a.period or 0) > 0):
        ap.error("give either --speed, or --amplitude with --period > 0")
    if a.nodes < 2 or a.length <= 0 or (a.faces == 2 and a.thickness <= 0):
        ap.error("needs --nodes >= 2, --length > 0 and, with two faces, --thickness > 0")
    if a.proto_dir:
        sys.path.insert(0, a.proto_dir)
    import zmq
    import coupling_pb2 as pb

    th = math.radians(a.angle)
    tx, ty, nx, ny = math.cos(th), math.sin(th), -math.sin(th), math.cos(th)
    if a.speed is not None:
        d, d0 = (lambda t: a.speed * t), a.speed
    else:
        d, d0 = (lambda t: a.amplitude * math.sin(math.pi * t / a.period) ** 2), 0.0
    # Reference nodes, face by face; sign: the face's normal is sign × n.
    faces = [(0, 1.0, -0.5 * a.thickness if a.faces == 2 else 0.0)] + ([(1, -1.0, 0.5 * a.thickness)] if a.faces == 2 else [])
    face, sign, X0, Y0 = [], [], [], []
    for f, sg, off in faces:
        for j in range(a.nodes):
            s = a.length * (j / (a.nodes - 1) - 0.5)
            face.append(f)
            sign.append(sg)
            X0.append(a.xc + off * nx + s * tx)
            Y0.append(a.yc + off * ny + s * ty)
    n = len(face)

    def positions(t):
        dd = d(t)
        xs, ys = [x + dd * nx for x in X0], [y + dd * ny for y in Y0]
        if a.alpha and min(xs) < 0:
            raise RuntimeError(f"the plate reaches r = {min(xs)!r} m < 0 at t = {t!r} s")
        return xs, ys

    def areas(xs, ys):
        out = []
        for f, sg, _ in faces:
            k = [i for i in range(n) if face[i] == f]
            out += area_vectors([xs[i] for i in k], [ys[i] for i in k], a.alpha, sg)
        A = [math.hypot(*v) for v in out]
        return A, [v[0] / Ak for v, Ak in zip(out, A)], [v[1] / Ak for v, Ak in zip(out, A)]

    version = 1
    ctx = zmq.Context()
    sock = ctx.socket(zmq.PAIR)
    sock.setsockopt(zmq.LINGER, 2000)
    sock.connect(a.couple)

    def stop(signum, _frame):
        raise SystemExit(4)

    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGHUP, stop)

    def send(step, **body):
        e = pb.Envelope(protocol=version, step=step)
        for name, msg in body.items():
            getattr(e, name).CopyFrom(msg)
        sock.send(e.SerializeToString())

    beats = [0]  # heartbeats received since the last Grant

    def receive(step, kind, timeout):
        while True:
            if not sock.poll(int(timeout * 1000)):
                raise RuntimeError(f"the fluid solver did not answer within {timeout} s at step {step}")
            e = pb.Envelope()
            try:
                e.ParseFromString(sock.recv())
            except Exception as err:  # protobuf's DecodeError
                raise RuntimeError(f"the fluid solver sent a malformed message at step {step} ({err})") from None
            if e.protocol != version:
                raise RuntimeError(f"the fluid solver speaks protocol {e.protocol}, this side {version}")
            body = e.WhichOneof("body")
            if body == "heartbeat":
                beats[0] += 1
                continue
            if body == "error":
                raise RuntimeError(f"the fluid solver stopped with an error at step {step}: {e.error.message}")
            if body == "stop" or (body == kind and e.step == step):
                return e
            raise RuntimeError(f"the fluid solver sent {body} of step {e.step} where {kind} of step {step} was expected")

    rec = {k: [] for k in ("t", "dt", "dt_s", "work", "p_I", "u_I", "p_L", "u_L", "Z_L", "area", "x", "y",
                           "heartbeats")}
    step = 0
    try:
        xs, ys = positions(0.0)
        A, nxs, nys = areas(xs, ys)
        send(0, hello=pb.Hello(solver="moving_plate.py", version="1", dimension=2, alpha=a.alpha, x=xs, y=ys,
                               normal_x=nxs, normal_y=nys, area=A, face=face))
        w = receive(0, "welcome", max(a.timeout, 300))
        if w.WhichOneof("body") == "stop":
            return 0
        end = w.welcome.end_time
        print(f"moving_plate.py: {n} nodes coupled to {w.welcome.solver} {w.welcome.version}, end time {end} s",
              flush=True)
        t, u = 0.0, [sg * d0 for sg in sign]
        while True:
            step += 1
            send(step, offer=pb.Offer(dt=a.dt, x=xs, y=ys, velocity=u))
            beats[0] = 0
            g = receive(step, "grant", a.timeout)
            if g.WhichOneof("body") == "stop":
                print(f"moving_plate.py: done at t = {t:.6g} s: {g.stop.reason}", flush=True)
                return 0
            g = g.grant
            dt = g.dt
            if not (0 < dt <= a.dt) or abs(g.time - t) > 1e-9 * end or \
                    not (len(g.p_L) == len(g.u_L) == len(g.Z_L) == len(g.geometric) == n):
                raise RuntimeError(f"the fluid solver sent a Grant at step {step} with dt = {dt!r} (offered {a.dt!r}), "
                                   f"time = {g.time!r} (this side {t!r}) or not one value per interface node ({n})")
            A, _, _ = areas(xs, ys)
            speed = (d(t + dt) - d(t)) / dt
            u = [sg * speed for sg in sign]
            p_I = [max(g.p_floor, g.p_L[k] - g.Z_L[k] * (u[k] - g.u_L[k]) - g.geometric[k]) for k in range(n)]
            xs, ys = positions(t + dt)
            send(step, answer=pb.Answer(p_I=p_I, u_I=u, x=xs, y=ys))
            for key, val in (("t", t), ("dt", dt), ("dt_s", a.dt), ("p_I", p_I), ("u_I", u), ("p_L", list(g.p_L)),
                             ("u_L", list(g.u_L)), ("Z_L", list(g.Z_L)), ("area", A), ("x", xs), ("y", ys),
                             ("work", sum(p * uk * Ak * dt for p, uk, Ak in zip(p_I, u, A))),
                             ("heartbeats", beats[0])):
                rec[key].append(val)
            t += dt
    except RuntimeError as err:
        print(f"moving_plate.py: error: coupling: {err}", file=sys.stderr, flush=True)
        try:
            send(step, error=pb.Error(message=str(err)))
        except Exception:
            pass
        return 3
    finally:
        if a.history:
            import h5py
            import numpy as np
            with h5py.File(a.history, "w") as f:
                c = f.create_group("coupling")
                for key, val in rec.items():
                    c.create_dataset(key, data=np.array(val, dtype=float).reshape((len(val),) + ((n,) if key in (
                        "p_I", "u_I", "p_L", "u_L", "Z_L", "area", "x", "y") else ())))
                c.create_dataset("face", data=np.array(face, dtype=np.int32))
        sock.close()
        ctx.term()


if __name__ == "__main__":
    sys.exit(main())
