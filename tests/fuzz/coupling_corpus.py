#!/usr/bin/python3
"""Writes the seed corpus of tests/fuzz/fuzz_coupling.cpp: one valid serialised coupling Envelope of each
kind (proto/coupling.proto), small, as a solver would send it.

    coupling_corpus.py PYTHON_DIR OUT_DIR      (PYTHON_DIR: build/python, which holds coupling_pb2.py)
"""
import os
import sys

sys.path.insert(0, sys.argv[1])
import coupling_pb2 as pb  # noqa: E402

out = sys.argv[2]
os.makedirs(out, exist_ok=True)
messages = {
    "hello": (0, dict(hello=pb.Hello(solver="undex-solid", version="0.1.0", dimension=1, alpha=0, x=[0.0], y=[0.0],
                                     normal_x=[1.0], normal_y=[0.0], area=[1.0]))),
    "welcome": (0, dict(welcome=pb.Welcome(solver="undex-fluid", version="0.1.0", end_time=1e-3))),
    "offer": (3, dict(offer=pb.Offer(dt=1.2e-7, x=[1e-6], y=[0.0], velocity=[0.5]))),
    "grant": (3, dict(grant=pb.Grant(dt=1e-7, time=2e-7, p_L=[1e7], u_L=[1.0], Z_L=[1.5e6], geometric=[0.0],
                                     p_floor=2338.0, output=True))),
    "answer": (3, dict(answer=pb.Answer(p_I=[9.9e6], u_I=[0.9], x=[1e-7], y=[0.0]))),
    "stop": (4, dict(stop=pb.Stop(reason="end time reached"))),
    "error": (3, dict(error=pb.Error(message="element 12 inverted"))),
    "heartbeat": (3, dict(heartbeat=pb.Heartbeat())),
}
for name, (step, body) in messages.items():
    e = pb.Envelope(protocol=1, step=step)
    for k, v in body.items():
        getattr(e, k).CopyFrom(v)
    open(os.path.join(out, name), "wb").write(e.SerializeToString())
