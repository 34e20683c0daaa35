#!/usr/bin/python3
"""A misbehaving coupling peer for the socket-level failure tests (tests/coupling/failures.py).

    bad_peer.py --role structure|fluid --mode MODE --couple ENDPOINT [--proto-dir DIR] [--at STEP]

As the structure it connects and speaks the protocol correctly up to step --at (default 3), then:
    garbage        sends bytes that are no coupling Envelope
    wrong-type     sends an Answer where an Offer is due
    wrong-version  sends its Offer with protocol version 99
    silent         stops answering (sleeps)
    wrong-physics  (structure only) answers every step, but moves against the pressure and ignores the
                   interface condition: p_I = p_L, u_I = -0.01 m/s (for `undex conform` to catch)
    heartbeats     sends only Heartbeats, every 0.1 s
    long-error     sends an Error of 1 MB that is not UTF-8
    tiny-dt        (structure only) offers dt = 5e-324
    wrong-area-2d  (structure only) a 2D Hello of three nodes on a flat face whose end nodes claim the area
                   of an inner one (0.1 m instead of 0.05 m per unit depth)
    jumps-2d       (structure only) a correct 2D Hello and answers, but each Offer starts 1 mm away from
                   where the last Answer ended
As the fluid it binds, answers the Hello, and grants steps with a resting fluid state up to --at, then
misbehaves the same way (garbage, a Welcome where a Grant is due, version 99, silence, heartbeats, a long
Error) or grants with p_floor = inf (pfloor-inf), p_floor = NaN (pfloor-nan) or time = NaN (time-nan);
end-negative answers the Hello with end_time = -1.
"""
import argparse
import sys
import time


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--role", choices=["structure", "fluid"], default="structure")
    ap.add_argument("--mode", choices=["garbage", "wrong-type", "wrong-version", "silent", "wrong-physics", "heartbeats", "long-error",
                                     "tiny-dt", "wrong-area-2d", "jumps-2d", "pfloor-inf", "pfloor-nan", "time-nan", "end-negative"], required=True)
    ap.add_argument("--at", type=int, default=3)
    ap.add_argument("--proto-dir")
    ap.add_argument("--couple", required=True)
    a = ap.parse_args()
    if a.proto_dir:
        sys.path.insert(0, a.proto_dir)
    import zmq
    import coupling_pb2 as pb

    ctx = zmq.Context()
    s = ctx.socket(zmq.PAIR)
    s.setsockopt(zmq.LINGER, 1000)

    def send(step, version=1, **body):
        e = pb.Envelope(protocol=version, step=step)
        for k, v in body.items():
            getattr(e, k).CopyFrom(v)
        s.send(e.SerializeToString())

    def recv():  # the next message that is not a Heartbeat (a peer may send them while it works)
        while True:
            if not s.poll(10000):
                raise SystemExit("bad_peer: the other side went silent")
            e = pb.Envelope()
            e.ParseFromString(s.recv())
            if e.WhichOneof("body") != "heartbeat":
                return e

    def varint(n):
        out = b""
        while n > 0x7F:
            out += bytes([(n & 0x7F) | 0x80])
            n >>= 7
        return out + bytes([n])

    def spoil(**fields):
        def f(message):
            m = type(message)()
            m.CopyFrom(message)
            for k, v in fields.items():
                setattr(m, k, v)
            return m
        return f

    spoilt = {"tiny-dt": spoil(dt=5e-324), "pfloor-inf": spoil(p_floor=float("inf")),
              "pfloor-nan": spoil(p_floor=float("nan")), "time-nan": spoil(time=float("nan"))}

    def misbehave(step, proper):
        if a.mode == "garbage":
            s.send(b"\xff\x00 this is not a coupling envelope \x13\x37")
        elif a.mode == "wrong-version":
            send(step, version=99, **proper)
        elif a.mode == "silent":
            time.sleep(60)
            return
        elif a.mode == "heartbeats":
            for _ in range(600):  # a minute at most
                send(step, heartbeat=pb.Heartbeat())
                time.sleep(0.1)
            return
        elif a.mode == "long-error":  # encoded by hand: protobuf's Python API refuses a string that is no UTF-8
            text = b"\xff\xfe not UTF-8 \n" + b"x" * (1 << 20)
            error = b"\x0a" + varint(len(text)) + text
            s.send(b"\x08\x01\x10" + varint(step) + b"\x8a\x01" + varint(len(error)) + error)
        elif a.mode in spoilt:
            send(step, **{k: spoilt[a.mode](v) for k, v in proper.items()})
        time.sleep(2)  # let the frame leave before the socket closes

    if a.role == "structure" and a.mode in ("wrong-area-2d", "jumps-2d"):
        s.connect(a.couple)
        x = [0.0, 0.1, 0.2]
        area = [0.1, 0.1, 0.1] if a.mode == "wrong-area-2d" else [0.05, 0.1, 0.05]
        send(0, hello=pb.Hello(solver="bad_peer.py", version="1", dimension=2, alpha=0, x=x, y=[0.0] * 3,
                               normal_x=[0.0] * 3, normal_y=[1.0] * 3, area=area, face=[0] * 3))
        if recv().WhichOneof("body") != "welcome":
            return 0
        for step in range(1, 1000000):
            send(step, offer=pb.Offer(dt=1.0, x=x, y=[1e-3 * step] * 3, velocity=[0.0] * 3))
            g = recv()
            if g.WhichOneof("body") != "grant":
                return 0
            p = [pl + z * ul - ge for pl, z, ul, ge in zip(g.grant.p_L, g.grant.Z_L, g.grant.u_L, g.grant.geometric)]
            send(step, answer=pb.Answer(p_I=p, u_I=[0.0] * 3, x=x, y=[0.0] * 3))
        return 0
    if a.role == "structure":
        s.connect(a.couple)
        send(0, hello=pb.Hello(solver="bad_peer.py", version="1", dimension=1, alpha=0, x=[0.0], y=[0.0],
                               normal_x=[1.0], normal_y=[0.0], area=[1.0]))
        recv()  # Welcome
        for step in range(1, 1000000):
            offer = pb.Offer(dt=1.0, x=[0.0], y=[0.0], velocity=[0.0])
            if a.mode == "wrong-physics":
                send(step, offer=offer)
                g = recv()
                if g.WhichOneof("body") != "grant":
                    return 0
                send(step, answer=pb.Answer(p_I=[g.grant.p_L[0]], u_I=[-0.01], x=[0.0], y=[0.0]))
                continue
            if step == a.at:
                if a.mode == "wrong-type":
                    send(step, answer=pb.Answer(p_I=[1e5], u_I=[0.0], x=[0.0], y=[0.0]))
                    time.sleep(2)
                else:
                    misbehave(step, {"offer": offer})
                return 0
            send(step, offer=offer)
            g = recv()
            if g.WhichOneof("body") != "grant":
                return 0
            send(step, answer=pb.Answer(p_I=[g.grant.p_L[0]], u_I=[0.0], x=[0.0], y=[0.0]))
    else:
        s.bind(a.couple)
        recv()  # Hello
        send(0, welcome=pb.Welcome(solver="bad_peer.py", version="1", end_time=-1.0 if a.mode == "end-negative" else 1.0))
        if a.mode == "end-negative":
            time.sleep(2)
            return 0
        t = 0.0
        for step in range(1, 1000000):
            offer = recv()
            if offer.WhichOneof("body") != "offer":
                return 0
            dt = min(offer.offer.dt, 1e-7)
            grant = pb.Grant(dt=dt, time=t, p_L=[1e5], u_L=[0.0], Z_L=[1.5e6], geometric=[0.0], p_floor=2338.0)
            if step == a.at:
                if a.mode == "wrong-type":
                    send(step, welcome=pb.Welcome(solver="bad_peer.py", version="1", end_time=1.0))
                    time.sleep(2)
                else:
                    misbehave(step, {"grant": grant})
                return 0
            send(step, grant=grant)
            recv()  # Answer
            t += dt
    return 0


if __name__ == "__main__":
    sys.exit(main())
