#!/usr/bin/python3
"""A peer is not trusted (issue 12, class 3), over real sockets against all three solvers:

- a value out of range in a Grant (p_floor inf or NaN, time NaN) or a Welcome (end_time < 0): undex-solid
  and undex-rigid refuse it with exit status 3 and a message naming the field and the step;
- a structure offering Δt = 5e-324: undex-fluid refuses it (status 3) instead of stepping forever;
- a peer that only sends Heartbeats: the other side gives up after heartbeat_limit = 10 timeouts;
- an Error of 1 MB that is not UTF-8: quoted bounded, the run ends with status 3 and its status written;
- SIGTERM during the handshake: exit status 4 (stopped), as docs/protocol.md says, on each solver.

The coupling timeout is 0.5 s here, so a heartbeat-only peer must be given up on after 5 s (+ 5 s of
start-up and launcher grace); every other failure must end within 10 s.

    peer_values.py BIN_DIR CASES_DIR PYTHON_DIR WORK_DIR
"""
import os
import re
import signal
import subprocess
import sys
import time

import h5py

BIN, CASES, PYDIR, WORK = [os.path.abspath(p) for p in sys.argv[1:5]]
BAD = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bad_peer.py")
TIMEOUT = 0.5
LIMIT = 10 * TIMEOUT  # coupler/channel.hpp heartbeat_limit
failures, passed = [], 0


def check(ok, what, detail=""):
    global passed
    if ok:
        passed += 1
        print(f"ok: {what}")
    else:
        failures.append(what)
        print(f"FAIL: {what}\n{detail}")


def status_of(h5):
    try:
        with h5py.File(h5, "r") as f:
            s = f.attrs["status"]
            return s.decode() if isinstance(s, bytes) else str(s)
    except Exception as e:  # noqa: BLE001 - any failure to read is the finding
        return f"unreadable: {e}"


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


# 1. A fluid peer sending a bad value, a long Error or only heartbeats: the structure solvers refuse it.
expected = {
    "pfloor-inf": r"the fluid solver sent Grant\.p_floor = inf at step 3: must be finite",
    "pfloor-nan": r"the fluid solver sent Grant\.p_floor = nan at step 3: must be finite",
    "time-nan": r"the fluid solver sent Grant\.time = nan s at step 3",
    "end-negative": r"the fluid solver \(bad_peer\.py 1\) sent Welcome\.end_time = -1 at step 0",
    "heartbeats": r"the fluid solver sent only Heartbeats for [0-9.]+ s at step 3 \(waiting for Grant\)",
    "long-error": r"the fluid solver stopped with an error at step 3: \\xFF\\xFE not UTF-8 \\x0Axxx",
}
for solver, source in (("undex-solid", "sandwich_shock_1d.case"), ("undex-rigid", "taylor_plate_1d.case")):
    for mode, pattern in expected.items():
        out, path = make_case(f"{solver}_{mode}", source)
        endpoint = f"ipc://{WORK}/{solver}_{mode}.ipc"
        peer = subprocess.Popen(["/usr/bin/python3", BAD, "--role", "fluid", "--mode", mode, "--proto-dir", PYDIR,
                                 "--couple", endpoint])
        t0 = time.monotonic()
        r = subprocess.run([os.path.join(BIN, solver), path, "--couple", endpoint], capture_output=True, text=True,
                           timeout=120)
        took = time.monotonic() - t0
        peer.kill()
        peer.wait()
        text = r.stdout + r.stderr
        st = status_of(os.path.join(out, "solid.h5"))
        # A failed handshake leaves no output file; after it the status says why.
        st_ok = (not os.path.exists(os.path.join(out, "solid.h5")) if mode == "end-negative"
                 else st.startswith("failed: coupling: ") and len(st) < 2000)
        check(r.returncode == 3 and re.search(pattern, text) is not None and st_ok
              and took < (LIMIT if mode == "heartbeats" else 0) + 10,
              f"{solver}, fluid peer {mode}: status {r.returncode}, refused in {took:.1f} s; solid.h5 '{st[:50]}'",
              text[-1500:])

# 2. A structure peer offering Δt = 5e-324, only heartbeats or a long Error: undex-fluid refuses it.
expected = {
    "tiny-dt": r"the structure solver sent a time step Offer\.dt = 5e-324 s at step 3: must be finite and at "
               r"least [0-9.e+-]+ s \(1e-12 × end_time\)",
    "heartbeats": r"the structure solver sent only Heartbeats for [0-9.]+ s at step 3 \(waiting for Offer\)",
    "long-error": r"the structure solver stopped with an error at step 3: \\xFF\\xFE not UTF-8 \\x0Axxx",
}
for mode, pattern in expected.items():
    cmd = f"/usr/bin/python3 {BAD} --role structure --mode {mode} --proto-dir {PYDIR}"
    out, path = make_case(f"fluid_{mode}", "taylor_plate_1d.case",
                          f'command: "{cmd}" front {{ type: FLUID }} back {{ type: FREE }}')
    t0 = time.monotonic()
    r = subprocess.run([os.path.join(BIN, "undex"), "run", path], capture_output=True, text=True, timeout=120)
    took = time.monotonic() - t0
    log = open(os.path.join(out, "fluid.log")).read()
    st = status_of(os.path.join(out, "fluid.h5"))
    check(r.returncode == 3 and re.search(pattern, log) is not None and st.startswith("failed: coupling: ")
          and len(st) < 2000 and took < (LIMIT if mode == "heartbeats" else 0) + 10,
          f"undex-fluid, structure peer {mode}: status {r.returncode}, refused in {took:.1f} s; fluid.h5 '{st[:50]}'",
          log[-1500:])


# 3. SIGTERM while a solver waits for its peer's handshake: stopped (4), at once, as docs/protocol.md says.
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
    check(p.returncode == 4 and "stopped by a signal" in text and took < 2,
          f"SIGTERM to {solver} during the handshake: status {p.returncode} in {took:.1f} s", text[-1000:])


sigterm_in_handshake("undex-fluid", "taylor_plate_1d.case")
sigterm_in_handshake("undex-solid", "sandwich_shock_1d.case")
sigterm_in_handshake("undex-rigid", "taylor_plate_1d.case")

print(f"{passed} passed, {len(failures)} failed")
sys.exit(1 if failures else 0)
