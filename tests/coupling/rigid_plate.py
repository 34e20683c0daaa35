#!/usr/bin/python3
"""A rigid-plate structure solver written in Python: the test of the coupling protocol's claim that any
program speaking it can replace undex-solid (docs/protocol.md). It uses only Debian's python3-zmq and
python3-protobuf and the generated build/python/coupling_pb2.py (on PYTHONPATH or --proto-dir).

    rigid_plate.py --mass M [--stiffness K] [--damping C] [--back-pressure P] [--dt DT[,DT...]] [--history CSV]
                   --couple ENDPOINT

A plate per unit area, m du/dt = p_I - p_back - k x - c du/dt, with the interface condition of physics.md §5
solved together with the plate's central-difference equation of motion (written here from the formula, not
from the C++ code). Exit codes: 0 when the fluid ends the run, 3 on a coupling failure.
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
    a = ap.parse_args()
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
    if history:
        history.write("t,dt,p_I,u_I,x,dt_s\n")
    try:
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


if __name__ == "__main__":
    sys.exit(main())
