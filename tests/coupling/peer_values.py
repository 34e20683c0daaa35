#!/usr/bin/python3
"""A peer is not trusted (issue 12, class 3), over real sockets against all three solvers:

- a value out of range in a Grant (p_floor inf or NaN, time NaN) or a Welcome (end_time < 0): undex-solid
  and undex-rigid refuse it with exit status 3 and a message naming the field and the step;
- a structure offering Δt = 5e-324: undex-fluid refuses it (status 3) instead of stepping forever;
- a peer that only sends Heartbeats: the other side gives up after heartbeat_limit = 10 timeouts;
- an Error of 1 MB that is not UTF-8: quoted bounded, the run ends with status 3 and its status written;
- SIGTERM during the handshake: exit status 4 (stopped), as docs/protocol.md says, on each solver.

The coupling timeout is 2 s here, so a heartbeat-only peer must be given up on after 20 s (+ 10 s of
start-up, + 5 s of launcher grace with undex run; the three run at once); every other failure must end
within 10 s (15 s with undex run).

    peer_values.py BIN_DIR CASES_DIR PYTHON_DIR WORK_DIR
"""
import os
import re
import signal
import subprocess
import sys
import time


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from checks import check, coupled_steps, finish, requested_times, status_of  # noqa: E402

BIN, CASES, PYDIR, WORK = [os.path.abspath(p) for p in sys.argv[1:5]]
BAD = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bad_peer.py")
TIMEOUT = 2.0  # bad_peer.py answers and beats every 0.1 s or faster: a loaded CI machine may delay it
LIMIT = 10 * TIMEOUT  # coupler/channel.hpp heartbeat_limit


def make_case(name, source, structure=None):
    out = os.path.join(WORK, name)
    os.makedirs(out, exist_ok=True)
    for f in ("fluid.h5", "solid.h5"):
        if os.path.exists(os.path.join(out, f)):
            os.remove(os.path.join(out, f))
    text = open(os.path.join(CASES, source)).read()
    if structure is not None:
        start = text.index("\nstructure {")
        stop = text.index("\n}\n", start) + 3
        text = text[:start] + "\nstructure { " + structure + " }\n" + text[stop:]
    text = re.sub(r"^output\s*\{.*\}$", f'output {{ interval: 1e-4 progress_seconds: 30 directory: "{out}" }}', text,
                  flags=re.M)
    text += f"\ncoupling {{ timeout: {TIMEOUT} handshake_timeout: 20 }}\n"
    path = os.path.join(out, "case.case")
    open(path, "w").write(text)
    return out, path


class Job:
    """One solver against one misbehaving peer: started, then checked when it ends."""

    def __init__(self, what, command, peer, out, h5, pattern, limit, log=None):
        self.what, self.out, self.h5, self.pattern, self.limit, self.log = what, out, h5, pattern, limit, log
        self.peer = subprocess.Popen(peer) if peer else None
        self.t0 = time.monotonic()
        self.proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)

    def finish(self, no_file=False):
        text = self.proc.communicate(timeout=120)[0]
        took = time.monotonic() - self.t0
        if self.peer:
            self.peer.kill()
            self.peer.wait()
        if self.log:
            text = open(os.path.join(self.out, self.log)).read()
        path = os.path.join(self.out, self.h5)
        st = status_of(path)
        # A failed handshake leaves no output file; after it the status says why, bounded.
        st_ok = not os.path.exists(path) if no_file else st.startswith("failed: coupling: ") and len(st) < 2000
        check(self.proc.returncode == 3 and re.search(self.pattern, text) is not None and st_ok and took < self.limit,
              f"{self.what}: status {self.proc.returncode}, refused in {took:.1f} s; {self.h5} '{st[:50]}'",
              text[-1500:])
        if self.h5 == "fluid.h5":  # the steps before the refusal keep the time-step rule (the peer keeps no record)
            problems, steps = coupled_steps(self.out, None, 6e-4, requested_times(6e-4, 1e-4), complete=False)
            check(not problems, f"{self.what}: time steps from the fluid's record ({steps})", "\n".join(problems))


def fluid_peer(solver, source, mode, pattern):
    out, path = make_case(f"{solver}_{mode}", source)
    endpoint = f"ipc://{WORK}/{solver}_{mode}.ipc"
    return Job(f"{solver}, fluid peer {mode}", [os.path.join(BIN, solver), path, "--couple", endpoint],
               ["/usr/bin/python3", BAD, "--role", "fluid", "--mode", mode, "--proto-dir", PYDIR, "--couple",
                endpoint], out, "solid.h5", pattern, LIMIT + 10 if mode == "heartbeats" else 10)


def structure_peer(mode, pattern):
    cmd = f"/usr/bin/python3 {BAD} --role structure --mode {mode} --proto-dir {PYDIR}"
    out, path = make_case(f"fluid_{mode}", "taylor_plate_1d.case",
                          f'command: "{cmd}" front {{ type: FLUID }} back {{ type: FREE }}')
    # Through undex run; after the fluid fails the launcher gives the structure 5 s before SIGTERM.
    return Job(f"undex-fluid, structure peer {mode}", [os.path.join(BIN, "undex"), "run", path], None, out,
               "fluid.h5", pattern, LIMIT + 15 if mode == "heartbeats" else 15, log="fluid.log")


SOLVERS = (("undex-solid", "sandwich_shock_1d.case"), ("undex-rigid", "taylor_plate_1d.case"))

# 1. A fluid peer sending a bad value or a long Error: the structure solvers refuse it.
expected = {
    "pfloor-inf": r"the fluid solver sent Grant\.p_floor = inf at step 3: must be finite",
    "pfloor-nan": r"the fluid solver sent Grant\.p_floor = nan at step 3: must be finite",
    "time-nan": r"the fluid solver sent Grant\.time = nan s at step 3",
    "end-negative": r"the fluid solver \(bad_peer\.py 1\) sent Welcome\.end_time = -1 at step 0",
    "long-error": r"the fluid solver stopped with an error at step 3: \\xFF\\xFE not UTF-8 \\x0Axxx",
}
for solver, source in SOLVERS:
    for mode, pattern in expected.items():
        fluid_peer(solver, source, mode, pattern).finish(no_file=mode == "end-negative")

# 2. A structure peer offering Δt = 5e-324 or a long Error: undex-fluid refuses it.
structure_peer("tiny-dt", r"the structure solver sent a time step Offer\.dt = 5e-324 s at step 3: must be finite "
                          r"and at least [0-9.e+-]+ s \(1e-12 × end_time\)").finish()
structure_peer("long-error",
               r"the structure solver stopped with an error at step 3: \\xFF\\xFE not UTF-8 \\x0Axxx").finish()

# 3. A peer that only sends heartbeats, to each solver at once (each takes LIMIT).
jobs = [fluid_peer(solver, source, "heartbeats",
                   r"the fluid solver sent only Heartbeats for [0-9.]+ s at step 3 \(waiting for Grant\)")
        for solver, source in SOLVERS]
jobs.append(structure_peer("heartbeats",
                           r"the structure solver sent only Heartbeats for [0-9.]+ s at step 3 \(waiting for Offer\)"))
for job in jobs:
    job.finish()


# 4. SIGTERM while a solver waits for its peer's handshake: stopped (4), at once, as docs/protocol.md says.
def sigterm_in_handshake(solver, source):
    out, path = make_case(f"{solver}_sigterm", source)
    endpoint = f"ipc://{WORK}/{solver}_sigterm.ipc"  # nobody on the other side
    p = subprocess.Popen([os.path.join(BIN, solver), path, "--couple", endpoint], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True)
    time.sleep(1.5)  # set up and waiting (the handshake timeout is 20 s)
    t0 = time.monotonic()
    p.send_signal(signal.SIGTERM)
    text = p.communicate(timeout=30)[0]
    took = time.monotonic() - t0
    check(p.returncode == 4 and "stopped by a signal" in text and took < 3,
          f"SIGTERM to {solver} during the handshake: status {p.returncode} in {took:.1f} s", text[-1000:])


sigterm_in_handshake("undex-fluid", "taylor_plate_1d.case")
sigterm_in_handshake("undex-solid", "sandwich_shock_1d.case")
sigterm_in_handshake("undex-rigid", "taylor_plate_1d.case")

finish()
