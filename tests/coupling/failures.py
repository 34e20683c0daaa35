#!/usr/bin/python3
"""Socket-level failure tests of the coupling (issue: a peer that dies, hangs, or sends a malformed,
out-of-order or wrong-version message ends the run on both sides with a clear message naming the peer, the
step and the cause, within the timeout, and both sides keep their last complete output readable).

Real processes over real sockets: undex run with a misbehaving structure (tests/coupling/bad_peer.py as
structure.command), undex-solid against a misbehaving fluid, SIGKILL of either side mid-run, and an ipc://
endpoint already in use. The coupling timeout is 2 s here; every failure must end within it plus 5 s of
start-up and launcher grace.

    failures.py BIN_DIR CASES_DIR PYTHON_DIR WORK_DIR
"""
import os
import re
import shutil
import signal
import subprocess
import sys
import time

import h5py


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from checks import check, coupled_steps, finish, requested_times, status_of  # noqa: E402

BIN, CASES, PYDIR, WORK = [os.path.abspath(p) for p in sys.argv[1:5]]
HERE = os.path.dirname(os.path.abspath(__file__))
BAD = os.path.join(HERE, "bad_peer.py")
TIMEOUT = 2.0


def make_case(name, source, structure=None, extra="", refine=1):
    """The case file SOURCE written for this test; REFINE multiplies its fluid cells (a run stopped by a
    signal mid-way must still be stepping a second or two after it started)."""
    out = os.path.join(WORK, name)
    # A fresh directory: the waits below read the run's log and output, and an older run's (a test run
    # before this one) would end them before this run has written its own.
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    text = open(os.path.join(CASES, source)).read()
    text = re.sub(r"cells_x: (\d+)", lambda m: f"cells_x: {int(m.group(1)) * refine}", text)
    if structure is not None:
        start = text.index("\nstructure {")
        stop = text.index("\n}\n", start) + 3
        text = text[:start] + "\nstructure { " + structure + " }\n" + text[stop:]
    text = re.sub(r"^output\s*\{.*\}$", f'output {{ interval: 1e-4 progress_seconds: 30 directory: "{out}" }}', text,
                  flags=re.M)
    text += f"\ncoupling {{ timeout: {TIMEOUT} handshake_timeout: 20 }}\n" + extra
    path = os.path.join(out, "case.case")
    open(path, "w").write(text)
    return out, path


# 1. A structure that misbehaves at step 3: the fluid names it, the step and the cause, and exits 3.
expected = {
    "garbage": r"the structure solver sent a malformed message at step 3",
    "wrong-type": r"the structure solver sent Answer of step 3 where Offer of step 3 was expected",
    "wrong-version": r"the structure solver speaks protocol version 99, this side version 1 at step 3",
    "silent": r"the structure solver did not answer within 2(\.0+)? s at step 3 \(waiting for Offer\)",
}
for mode, pattern in expected.items():
    cmd = f"/usr/bin/python3 {BAD} --role structure --mode {mode} --proto-dir {PYDIR}"
    out, path = make_case(f"structure_{mode}", "taylor_plate_1d.case",
                          f'command: "{cmd}" front {{ type: FLUID }} back {{ type: FREE }}')
    t0 = time.monotonic()
    r = subprocess.run([os.path.join(BIN, "undex"), "run", path], capture_output=True, text=True, timeout=120)
    took = time.monotonic() - t0
    log = open(os.path.join(out, "fluid.log")).read()
    st = status_of(os.path.join(out, "fluid.h5"))
    check(r.returncode != 0 and re.search(pattern, log) is not None and st.startswith("failed: coupling: ")
          and took < TIMEOUT + 8,
          f"structure sends {mode}: fluid stops naming peer, step and cause in {took:.1f} s; fluid.h5 '{st[:60]}...'",
          r.stdout[-1500:])

# 2. A fluid that misbehaves at step 3: undex-solid names it, the step and the cause, exits 3, keeps solid.h5.
expected_fluid = {
    "garbage": r"the fluid solver sent a malformed message at step 3",
    "wrong-type": r"the fluid solver sent Welcome of step 3 where Grant of step 3 was expected",
    "wrong-version": r"the fluid solver speaks protocol version 99, this side version 1 at step 3",
    "silent": r"the fluid solver did not answer within 2(\.0+)? s at step 3 \(waiting for Grant\)",
}
for mode, pattern in expected_fluid.items():
    out, path = make_case(f"fluid_{mode}", "sandwich_shock_1d.case")
    endpoint = f"ipc://{WORK}/fluid_{mode}.ipc"
    peer = subprocess.Popen(["/usr/bin/python3", BAD, "--role", "fluid", "--mode", mode, "--proto-dir", PYDIR,
                             "--couple", endpoint])
    t0 = time.monotonic()
    r = subprocess.run([os.path.join(BIN, "undex-solid"), path, "--couple", endpoint], capture_output=True,
                       text=True, timeout=120)
    took = time.monotonic() - t0
    peer.kill()
    peer.wait()
    st = status_of(os.path.join(out, "solid.h5"))
    check(r.returncode == 3 and re.search(pattern, r.stdout + r.stderr) is not None and
          st.startswith("failed: coupling: ") and took < TIMEOUT + 8,
          f"fluid sends {mode}: undex-solid stops naming peer, step and cause in {took:.1f} s; solid.h5 '{st[:60]}...'",
          r.stdout[-1000:] + r.stderr[-1000:])


def has_record(out, victim):
    """Whether the victim's output holds the step record the checks below read."""
    path, group = (("fluid.h5", "interface") if victim == "undex-fluid" else ("solid.h5", "coupling"))
    try:
        with h5py.File(os.path.join(out, path), "r") as f:
            return group in f
    except Exception:  # noqa: BLE001 - not written yet
        return False


# 3. SIGKILL of either side mid-run: the other notices the closed connection at once, names the peer and the
# step, writes its last good state; the killed side's output stays readable.
def kill_mid_run(victim, source, name, refine):
    out, path = make_case(name, source, refine=refine)
    launcher = subprocess.Popen([os.path.join(BIN, "undex"), "run", path], stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True)
    # Wait until both sides step (the fluid's first progress line), then kill the victim.
    pid = None
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and pid is None:
        time.sleep(0.2)
        log = os.path.join(out, "fluid.log")
        if os.path.exists(log) and "coupled to" in open(log).read():
            # Well into the stepping: once the victim's output holds its step record (its first output
            # written; under load that can take longer than the 1 s waited before), then 1 s more.
            while time.monotonic() < deadline and not has_record(out, victim):
                time.sleep(0.2)
            time.sleep(1.0)
            p = subprocess.run(["pgrep", "-f", f"{victim} {path}"], capture_output=True, text=True)
            pid = int(p.stdout.split()[0]) if p.stdout.split() else None
    if pid is None:
        launcher.kill()
        check(False, f"SIGKILL {victim}: the run never started", launcher.communicate()[0][-1500:])
        return
    time.sleep(0.5)
    # While the run goes on, both outputs open (no HDF5 file lock) and say so.
    running = [status_of(os.path.join(out, f"{side}.h5")) for side in ("fluid", "solid")]
    check(running == ["running", "running"], f"outputs readable during the run ({victim} case)", str(running))
    t0 = time.monotonic()
    os.kill(pid, signal.SIGKILL)
    text = launcher.communicate(timeout=120)[0]
    took = time.monotonic() - t0
    other = "solid" if victim == "undex-fluid" else "fluid"
    peer = "the fluid solver" if victim == "undex-fluid" else "the structure solver"
    other_log = open(os.path.join(out, f"{other}.log")).read()
    ok_msg = re.search(peer + r" closed the connection at step \d+ .*its process ended or was killed", other_log)
    st_other = status_of(os.path.join(out, f"{other}.h5"))
    st_victim = status_of(os.path.join(out, ("fluid" if other == "solid" else "solid") + ".h5"))
    check(launcher.returncode != 0 and ok_msg is not None and st_other.startswith("failed: coupling: ")
          and not st_victim.startswith("unreadable") and took < TIMEOUT + 8,
          f"SIGKILL {victim} mid-run: {other} stops in {took:.1f} s naming the peer and step; "
          f"{other}.h5 '{st_other[:40]}...', killed side's file '{st_victim[:20]}'",
          text[-1500:] + other_log[-800:])
    # The steps both sides recorded (the killed side's up to its last output) keep the time-step rule.
    end = float(re.search(r"^end_time:\s*(\S+)", open(path).read(), flags=re.M).group(1))
    problems, steps = coupled_steps(out, os.path.join(out, "solid.h5"), end, requested_times(end, 1e-4),
                                    complete=False)
    check(not problems, f"SIGKILL {victim}: time steps from both records ({steps})", "\n".join(problems))


kill_mid_run("undex-rigid", "taylor_plate_1d.case", "kill_structure", 2)  # 1.2 s as shipped, 4.3 s refined
kill_mid_run("undex-fluid", "sandwich_shock_1d.case", "kill_fluid", 10)  # 1.0 s as shipped

# 4. An endpoint already in use: the second fluid refuses it and the first keeps it.
out, path = make_case("endpoint", "taylor_plate_1d.case")
endpoint = f"ipc://{WORK}/busy.ipc"
first = subprocess.Popen([os.path.join(BIN, "undex-fluid"), path, "--couple", endpoint], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True)
time.sleep(1.0)
# (into another output directory: the first run's is locked)
r = subprocess.run([os.path.join(BIN, "undex-fluid"), path, "--couple", endpoint, "-o", out + "_second"],
                   capture_output=True, text=True, timeout=30)
time.sleep(1.5)  # a probe of the path must not end the first run later either
alive = first.poll() is None
first.send_signal(signal.SIGTERM)
first.communicate()
check(r.returncode == 3 and f"endpoint {endpoint} is already in use by another process" in r.stderr and alive,
      "endpoint already in use: refused with the endpoint named, the first run unharmed", r.stdout + r.stderr)
import socket  # noqa: E402

holder = socket.socket()
holder.bind(("127.0.0.1", 0))
holder.listen()
busy = f"tcp://127.0.0.1:{holder.getsockname()[1]}"
r = subprocess.run([os.path.join(BIN, "undex"), "run", path, "--endpoint", busy], capture_output=True,
                   text=True, timeout=60)
holder.close()
check(r.returncode != 0 and f"cannot bind endpoint {busy}" in r.stdout,
      "undex run on a tcp port it cannot bind: both sides stop, the cause named", r.stdout[-1500:])

# 5. SIGINT to undex run (Ctrl-C): both sides stop at their next step and write their last good state.
out, path = make_case("interrupt", "sandwich_shock_1d.case", refine=10)
launcher = subprocess.Popen([os.path.join(BIN, "undex"), "run", path], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
deadline = time.monotonic() + 60
while time.monotonic() < deadline and not (os.path.exists(os.path.join(out, "fluid.log")) and
                                           "coupled to" in open(os.path.join(out, "fluid.log")).read()):
    time.sleep(0.2)
time.sleep(1.0)
t0 = time.monotonic()
launcher.send_signal(signal.SIGINT)
text = launcher.communicate(timeout=60)[0]
took = time.monotonic() - t0
st = [status_of(os.path.join(out, f"{side}.h5")) for side in ("fluid", "solid")]
check(launcher.returncode != 0 and "stopped by a signal" in st[0] and "stopped by a signal" in st[1] and took < 5,
      f"SIGINT to undex run: both sides stop in {took:.1f} s with their last good state ('{st[0][:45]}...')",
      text[-1500:])

# 6. Timeouts the coupling cannot use are refused before anything runs.
for value in ("-1", "0", "inf"):
    r = subprocess.run([os.path.join(BIN, "undex"), "check", os.path.join(CASES, "taylor_plate_1d.case"), "--set",
                        f"coupling.timeout={value}"], capture_output=True, text=True)
    check(r.returncode == 1 and "coupling.timeout: must" in r.stderr and "(0, 86400]" in r.stderr,
          f"coupling.timeout = {value} refused by undex check", r.stderr)

finish()
