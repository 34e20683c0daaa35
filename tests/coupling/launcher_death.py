#!/usr/bin/python3
"""The launcher of a coupled run dies or hangs up (issue 12, class 4), over real processes and signals:

1. SIGKILL to `undex run` mid-run: both solvers notice (PR_SET_PDEATHSIG, launcher/children.cpp) and end
   within 5 s, each with its last good state written (the last field output has last_good = 1) and a status
   saying why (`failed: stopped by a signal (SIGHUP): undex (pid N), which started this solver, ended`), the
   same in their logs (which they append to themselves once the launcher is gone); the lock undex held is
   then stale: a new run is refused without --force and runs with it.
2. SIGHUP to `undex run` mid-run: undex passes it on as a stop, both sides write their last good state with
   status `failed: stopped by a signal (SIGHUP)...`, undex exits with status 4 within 5 s and removes its lock.

The 5 s bound: a solver checks for a stop at every step (well under a millisecond here) or is woken from its
wait for the partner by the signal; the rest is writing one output (milliseconds) and process exit.

    launcher_death.py BIN_DIR CASES_DIR WORK_DIR
"""
import os
import shutil
import signal
import subprocess
import sys
import time

import h5py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from checks import check, coupled_steps, finish, requested_times  # noqa: E402

BIN, CASES, WORK = [os.path.abspath(p) for p in sys.argv[1:4]]
UNDEX = os.path.join(BIN, "undex")
CASE = os.path.join(CASES, "sandwich_shock_1d.case")  # undex-fluid and undex-solid
# Ten times the case's cells: about 28 s to the end (2 s as shipped, which a loaded host can finish before
# the signal is sent); the signals come about a second into the run.
CELLS = ["--set", "domain.cells_x=3500"]
END, INTERVAL = 1.6e-3, 5e-4  # the case's end_time and output.interval


def steps_ok(out, what, end=END, complete=False):
    """The time-step rule over the steps both sides recorded (tests/support/checks.py)."""
    problems, steps = coupled_steps(out, os.path.join(out, "solid.h5"), end, requested_times(end, INTERVAL), complete)
    check(not problems, f"{what}: time steps from both records ({steps})", "\n".join(problems))


def last_state(h5):
    """The status and whether the last field output is the last good state (the file must open)."""
    try:
        with h5py.File(h5, "r") as f:
            g = f["fields"][sorted(f["fields"])[-1]]
            return f["status"][()].decode(), int(g.attrs.get("last_good", 0)) == 1
    except Exception as e:  # noqa: BLE001 - any failure to read is the finding
        return f"unreadable: {e}", False


def alive(pid):
    """Whether pid runs (a zombie the new parent has not reaped yet has ended)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except FileNotFoundError:
        return False


def start(name):
    """undex run of CASE into WORK/name, once both sides step; returns the launcher, the solvers' pids, out."""
    out = os.path.join(WORK, name)
    shutil.rmtree(out, ignore_errors=True)
    launcher = subprocess.Popen([UNDEX, "run", CASE, "-o", out] + CELLS, stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, start_new_session=True)
    log = os.path.join(out, "fluid.log")
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not (os.path.exists(log) and "coupled to" in open(log).read()):
        time.sleep(0.1)
    time.sleep(0.5)  # into the stepping
    kids = subprocess.run(["pgrep", "-P", str(launcher.pid)], capture_output=True, text=True).stdout.split()
    return launcher, [int(k) for k in kids], out


# 1. SIGKILL to undex run.
launcher, kids, out = start("kill")
check(len(kids) == 2, f"undex run started two solvers ({kids})")
t0 = time.monotonic()
launcher.kill()
launcher.wait()
while any(alive(k) for k in kids) and time.monotonic() - t0 < 30:
    time.sleep(0.05)
took = time.monotonic() - t0
check(not any(alive(k) for k in kids) and took < 5, f"SIGKILL to undex: both solvers ended in {took:.2f} s (bound 5 s)")
why = f"stopped by a signal (SIGHUP): undex (pid {launcher.pid}), which started this solver, ended"
for side, solver in (("fluid", "undex-fluid"), ("solid", "undex-solid")):
    st, good = last_state(os.path.join(out, f"{side}.h5"))
    log = open(os.path.join(out, f"{side}.log")).read()
    check(st.startswith("failed: " + why) and good, f"{side}.h5 holds its last good state, status says why", st)
    check(f"{solver}: error: {why}" in log and f"{solver}: the last good state" in log,
          f"{side}.log ends with why and where the last good state is", log[-600:])
steps_ok(out, "SIGKILL to undex")
lock_path = os.path.join(out, "undex.lock")
lock = open(lock_path).read() if os.path.exists(lock_path) else "(no lock file)"
r = subprocess.run([UNDEX, "run", CASE, "-o", out, "--set", "end_time=1e-4"] + CELLS, capture_output=True,
                   text=True)
check(r.returncode == 1 and "stale lock" in r.stderr and f"pid {launcher.pid} " in r.stderr and lock.startswith(
    f"pid={launcher.pid}\n"), "the killed undex's lock is stale: a new run refused, naming it", r.stderr + lock)
r = subprocess.run([UNDEX, "run", CASE, "-o", out, "--set", "end_time=1e-4", "--force"] + CELLS,
                   capture_output=True, text=True)
check(r.returncode == 0 and last_state(os.path.join(out, "fluid.h5"))[0] == "complete" and
      not os.path.exists(os.path.join(out, "undex.lock")), "--force takes it over and the run completes",
      r.stdout[-800:] + r.stderr)
steps_ok(out, "the run with --force", 1e-4, complete=True)

# 2. SIGHUP to undex run.
launcher, kids, out = start("hangup")
t0 = time.monotonic()
launcher.send_signal(signal.SIGHUP)
text = launcher.communicate(timeout=60)[0].decode(errors="replace")
took = time.monotonic() - t0
check(launcher.returncode == 4 and took < 5 and not any(alive(k) for k in kids),
      f"SIGHUP to undex: exit status {launcher.returncode} (4) in {took:.2f} s (bound 5 s), both solvers ended",
      text[-1500:])
for side in ("fluid", "solid"):
    st, good = last_state(os.path.join(out, f"{side}.h5"))
    check(st.startswith("failed: stopped by a signal (SIGHUP)") and good,
          f"{side}.h5 holds its last good state, status '{st[:60]}'", st)
steps_ok(out, "SIGHUP to undex")
check("undex: hangup (SIGHUP): stopping both sides" in text and not os.path.exists(os.path.join(out, "undex.lock")),
      "undex says so and removes its lock", text[-1500:])

finish()
