#!/usr/bin/python3
"""A rigid-plate structure solver written in Python: the test of the coupling protocol's claim that any
program speaking it can replace undex-solid (docs/protocol.md). It uses only Debian's python3-zmq and
python3-protobuf and the generated build/python/coupling_pb2.py (on PYTHONPATH or --proto-dir).

    rigid_plate.py --mass M [--stiffness K] [--damping C] [--back-pressure P] [--dt DT[,DT...]] [--history CSV]
                   [--dimension 2 [--alpha 0|1] [--nodes N] [--x0 X0] [--x1 X1] [--y-front Y]] --couple ENDPOINT

A plate per unit area, m du/dt = p_I - p_back - k x - c du/dt, with the interface condition of physics.md §5
solved together with the plate's central-difference equation of motion (written here from the formula, not
from the C++ code). Exit codes: 0 when the fluid ends the run, 3 on a coupling failure.

--dimension 2: a flat rigid plate of N nodes from x0 to x1 at y = y_front (one wet face, face 0, normal +y
from the fluid below into the plate; alpha 1: axisymmetric, x = r, per radian), moving along +y as one body
of mass m Σ A_k. The area vector of node k is Σ over its segments of n_s ∫ N_k r ds (docs/protocol.md: L/2
to each end of a segment in plane strain, L (2 r_a + r_b)/6 and L (r_a + 2 r_b)/6 in axisymmetry). Every
node moves with the body, u_I,k = v, so the body's equation m Σ A (v − v⁻) = h (F Σ A + Σ A_k p_I,k) and
every node's p_I,k = max(p_floor, p_L,k − Z_L,k (v − u_L,k) − g_k) are solved together in closed form: the
nodes held at p_floor are found first (a node that falls below it stays below as v grows). The CSV then has
t, dt, u_I, y (the displacement), work (Σ_k p_I,k u_I A_k Δt), dt_s and p_I_0 ... p_I_{N-1} per step.
"""
import argparse
import math
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mass", type=float, required=True, help="areal mass m, kg/m²")
    ap.add_argument("--stiffness", type=float, default=0.0, help="spring k per unit area, N/m³")
    ap.add_argument("--damping", type=float, default=0.0, help="dashpot c per unit area, N s/m³")
    ap.add_argument("--back-pressure", type=float, default=1e5, help="pressure on the dry face, Pa")
    ap.add_argument("--dt", type=lambda s: [float(x) for x in s.split(",")], default=[1.0],
                    help="the step offered, s; a comma-separated list is offered in turn, step by step")
    ap.add_argument("--timeout", type=float, default=30.0, help="longest wait for the fluid, s")
    ap.add_argument("--history", help="CSV of t, dt, p_I, u_I, x and the step offered dt_s per step")
    ap.add_argument("--proto-dir", help="directory of coupling_pb2.py")
    ap.add_argument("--couple", required=True, help="the fluid's endpoint")
    ap.add_argument("--dimension", type=int, choices=[1, 2], default=1, help="1: one node; 2: a plate of N nodes")
    ap.add_argument("--alpha", type=int, choices=[0, 1], default=0, help="2D: 0 plane strain, 1 axisymmetric (x = r)")
    ap.add_argument("--nodes", type=int, default=11, help="2D: nodes along the plate (at least 2)")
    ap.add_argument("--x0", type=float, default=0.0, help="2D: x of the first node, m")
    ap.add_argument("--x1", type=float, default=1.0, help="2D: x of the last node, m")
    ap.add_argument("--y-front", type=float, default=0.0, help="2D: y of the wet face in the fluid's frame, m")
    a = ap.parse_args()
    if a.dimension == 2 and not (a.nodes >= 2 and a.x1 > a.x0 and (a.alpha == 0 or a.x0 >= 0)):
        ap.error("--dimension 2 needs --nodes >= 2, --x1 > --x0 and, with --alpha 1, --x0 >= 0")
    if a.proto_dir:
        sys.path.insert(0, a.proto_dir)
    import zmq
    import coupling_pb2 as pb

    version = 1
    ctx = zmq.Context()
    sock = ctx.socket(zmq.PAIR)
    sock.setsockopt(zmq.LINGER, 2000)
    sock.connect(a.couple)

    def send(step, **body):
        e = pb.Envelope(protocol=version, step=step)
        for name, msg in body.items():
            getattr(e, name).CopyFrom(msg)
        sock.send(e.SerializeToString())

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
                continue
            if body == "error":
                raise RuntimeError(f"the fluid solver stopped with an error at step {step}: {e.error.message}")
            if body == "stop":
                return e
            if body != kind or e.step != step:
                raise RuntimeError(f"the fluid solver sent {body} of step {e.step} where {kind} of step {step} "
                                   "was expected")
            return e

    step = 0
    history = open(a.history, "w") if a.history else None
    if history and a.dimension == 2:
        history.write("t,dt,u_I,y,work,dt_s," + ",".join(f"p_I_{k}" for k in range(a.nodes)) + "\n")
    elif history:
        history.write("t,dt,p_I,u_I,x,dt_s\n")
    try:
        if a.dimension == 2:
            return plate_2d(a, pb, send, receive, history)
        send(0, hello=pb.Hello(solver="rigid_plate.py", version="1", dimension=1, alpha=0, x=[0.0], y=[0.0],
                               normal_x=[1.0], normal_y=[0.0], area=[1.0]))
        w = receive(0, "welcome", max(a.timeout, 300))
        if w.WhichOneof("body") == "stop":
            return 0
        print(f"rigid_plate.py: coupled to {w.welcome.solver} {w.welcome.version}, end time {w.welcome.end_time} s",
              flush=True)
        t, x, v, last_dt = 0.0, 0.0, 0.0, 0.0
        while True:
            step += 1
            offered = a.dt[(step - 1) % len(a.dt)]
            send(step, offer=pb.Offer(dt=offered, x=[x], y=[0.0], velocity=[v]))
            g = receive(step, "grant", a.timeout)
            if g.WhichOneof("body") == "stop":
                print(f"rigid_plate.py: done at t = {t:.6g} s: {g.stop.reason}", flush=True)
                return 0
            g = g.grant
            dt = g.dt
            one_each = len(g.p_L) == len(g.u_L) == len(g.Z_L) == len(g.geometric) == 1
            if not (0 < dt <= offered) or not one_each:
                raise RuntimeError(f"the fluid solver sent a Grant at step {step} with dt = {dt} (offered {offered}) "
                                   "or not one value per interface node")
            # Central differences: m (v_new - v) = h (F + p_I), h the mean of the last two steps (half a step
            # at the start); p_I = p_L - Z (v_new - u_L) - geometric from the fluid's characteristic.
            h = 0.5 * dt if step == 1 else 0.5 * (dt + last_dt)
            force = -a.back_pressure - a.stiffness * x - a.damping * v
            pL, uL, Z, geo = g.p_L[0], g.u_L[0], g.Z_L[0], g.geometric[0]
            v_new = (a.mass * v + h * (force + pL + Z * uL - geo)) / (a.mass + h * Z)
            p_I = pL - Z * (v_new - uL) - geo
            if p_I < g.p_floor:  # the water cannot pull harder than its cavitation pressure
                p_I = g.p_floor
                v_new = v + h * (force + p_I) / a.mass
            v = v_new
            x += dt * v
            if not (math.isfinite(v) and math.isfinite(x)):
                raise RuntimeError(f"non-finite plate state at step {step}")
            send(step, answer=pb.Answer(p_I=[p_I], u_I=[v], x=[x], y=[0.0]))
            if history:
                history.write(f"{t!r},{dt!r},{p_I!r},{v!r},{x!r},{offered!r}\n")
            t += dt
            last_dt = dt
    except RuntimeError as err:
        print(f"rigid_plate.py: error: coupling: {err}", file=sys.stderr, flush=True)
        try:
            send(step, error=pb.Error(message=str(err)))
        except Exception:
            pass
        return 3
    finally:
        if history:
            history.close()
        sock.close()
        ctx.term()


def area_vectors(xs, ys, alpha):
    """Area vector of each node of one face (nodes in order, normal to the left of the direction of travel):
    Σ over its segments of n_s ∫ N_k r ds, r = x in axisymmetry, 1 in plane strain."""
    a = [[0.0, 0.0] for _ in xs]
    for i in range(len(xs) - 1):
        nx, ny = -(ys[i + 1] - ys[i]), xs[i + 1] - xs[i]  # n_s L
        if alpha:
            wa, wb = (2 * xs[i] + xs[i + 1]) / 6, (xs[i] + 2 * xs[i + 1]) / 6
        else:
            wa = wb = 0.5
        a[i][0] += nx * wa
        a[i][1] += ny * wa
        a[i + 1][0] += nx * wb
        a[i + 1][1] += ny * wb
    return a


def plate_2d(a, pb, send, receive, history):
    """The 2D rigid plate (see the top of the file). Returns the exit code."""
    n = a.nodes
    xs = [a.x0 + (a.x1 - a.x0) * k / (n - 1) for k in range(n)]
    av = area_vectors(xs, [a.y_front] * n, a.alpha)
    area = [math.hypot(*v) for v in av]
    total = sum(area)
    mass = a.mass * total
    send(0, hello=pb.Hello(solver="rigid_plate.py", version="1", dimension=2, alpha=a.alpha, x=xs, y=[a.y_front] * n,
                           normal_x=[v[0] / A for v, A in zip(av, area)], normal_y=[v[1] / A for v, A in zip(av, area)],
                           area=area, face=[0] * n))
    w = receive(0, "welcome", max(a.timeout, 300))
    if w.WhichOneof("body") == "stop":
        return 0
    print(f"rigid_plate.py: 2D plate of {n} nodes coupled to {w.welcome.solver} {w.welcome.version}, "
          f"end time {w.welcome.end_time} s", flush=True)
    t, d, v, last_dt, step = 0.0, 0.0, 0.0, 0.0, 0
    while True:
        step += 1
        offered = a.dt[(step - 1) % len(a.dt)]
        send(step, offer=pb.Offer(dt=offered, x=xs, y=[a.y_front + d] * n, velocity=[v] * n))
        g = receive(step, "grant", a.timeout)
        if g.WhichOneof("body") == "stop":
            print(f"rigid_plate.py: done at t = {t:.6g} s: {g.stop.reason}", flush=True)
            return 0
        g = g.grant
        dt = g.dt
        if not (0 < dt <= offered) or not (len(g.p_L) == len(g.u_L) == len(g.Z_L) == len(g.geometric) == n):
            raise RuntimeError(f"the fluid solver sent a Grant at step {step} with dt = {dt} (offered {offered}) "
                               f"or not one value per interface node ({n})")
        h = 0.5 * dt if step == 1 else 0.5 * (dt + last_dt)
        force = (-a.back_pressure - a.stiffness * d - a.damping * v) * total
        # Nodes coupled to the body: A_k (p_L + Z u_L − g) enters the force, A_k Z the mass; nodes at the floor
        # add A_k p_floor. Start with none at the floor; v only grows as nodes join the floor, so at most n rounds.
        floor = [False] * n
        while True:
            num, den = mass * v + h * force, mass
            for k in range(n):
                if floor[k]:
                    num += h * area[k] * g.p_floor
                else:
                    num += h * area[k] * (g.p_L[k] + g.Z_L[k] * g.u_L[k] - g.geometric[k])
                    den += h * area[k] * g.Z_L[k]
            v_new = num / den
            p_I = [g.p_floor if floor[k] else g.p_L[k] - g.Z_L[k] * (v_new - g.u_L[k]) - g.geometric[k] for k in range(n)]
            below = [k for k in range(n) if p_I[k] < g.p_floor]
            if not below:
                break
            for k in below:
                floor[k] = True
        v = v_new
        d += dt * v
        if not (math.isfinite(v) and math.isfinite(d)):
            raise RuntimeError(f"non-finite plate state at step {step}")
        send(step, answer=pb.Answer(p_I=p_I, u_I=[v] * n, x=xs, y=[a.y_front + d] * n))
        if history:
            work = sum(p * v * A * dt for p, A in zip(p_I, area))
            history.write(f"{t!r},{dt!r},{v!r},{d!r},{work!r},{offered!r}," + ",".join(repr(p) for p in p_I) + "\n")
        t += dt
        last_dt = dt


if __name__ == "__main__":
    sys.exit(main())
