#!/usr/bin/python3
"""Checkpoints and `undex run CASE --resume DIR` on a real coupled run: cases/undex_sandwich_plate.case, coarse
(fluid cells of 0.1 m) to 0.8 ms: the shock reaches the plate at about 0.64 ms, the water behind the front face
cavitates and the foam begins to crush (730 steps, about 20 s).

1. The run uninterrupted: the reference.
2. The same run with output.checkpoint_seconds = 2, stopped by SIGTERM to undex once the shock has reached
   the plate: both sides stop (exit status 4) and write a checkpoint at one step; `--resume` continues it to
   the end.
3. The same, killed (SIGKILL to undex and both solvers) after a periodic checkpoint: nothing is written at
   the kill, so the outputs written after the checkpoint are dropped and written again; `--resume --force`
   (the lock is stale) continues it.
4. A fluid alone (a 2D Riemann problem), killed after a checkpoint and resumed.
In 2 to 4 every dataset and attribute of fluid.h5 and solid.h5 (fields with their DG coefficients, level
sets, frames, gauges, the interface and coupling tables, energies) is bitwise that of the reference; only
the case text differs (the output directory and checkpoint_seconds). A checkpoint of another case is refused.

    resume.py BIN_DIR SOURCE_DIR WORK_DIR
"""
import os
import shutil
import signal
import subprocess
import sys
import glob
import time

import h5py
import numpy as np

BIN, SRC, WORK = sys.argv[1:4]
UNDEX = os.path.join(BIN, "undex")
CASE = os.path.join(SRC, "cases", "undex_sandwich_plate.case")
END = 8e-4
SETS = ["--set", "domain.cells_x=50", "--set", "domain.cells_y=120", "--set", f"end_time={END}",
        "--set", "numerics.threads=1", "--set", "structure.threads=1",
        "--set", "output.progress_seconds=0.2"]
for k in range(9):  # the case's picture times, within END
    SETS += ["--set", f"output.times[{k}]={END * (k + 1) / 10:.6g}"]
failures = 0


def check(ok, what, detail=""):
    global failures
    print(("ok: " if ok else "FAIL: ") + what)
    if not ok:
        failures += 1
        if detail:
            print(detail)


def start(out, *more):
    return subprocess.Popen([UNDEX, "run", CASE, *SETS, *more, "-o", out], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, start_new_session=True)


def fluid_time(out):
    """The fluid's time on its last progress line."""
    try:
        lines = [l for l in open(os.path.join(out, "fluid.log")) if l.startswith("step ")]
        return float(lines[-1].split("t = ")[1].split()[0]) if lines else 0.0
    except OSError:
        return 0.0


def wait_until(out, t, proc):
    deadline = time.monotonic() + 120
    while fluid_time(out) < t and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.1)


def newest_checkpoint(out, side):
    files = sorted(glob.glob(os.path.join(out, f"{side}.checkpoint.*.h5")))
    return files[-1] if files else None


def contents(path):
    out = {}
    with h5py.File(path, "r") as f:
        for k, v in f.attrs.items():
            out["@" + k] = v

        def visit(name, obj):
            for k, v in obj.attrs.items():
                out[name + "@" + k] = v
            if isinstance(obj, h5py.Dataset) and name != "case":
                out[name] = obj[()]
        f.visititems(visit)
    return out


def same_as_reference(out, what):
    differences = []
    for side in ("fluid.h5", "solid.h5"):
        a, b = contents(os.path.join(ref, side)), contents(os.path.join(out, side))
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                differences.append(f"{side}:{k} only in {'the reference' if k in a else 'the resumed run'}")
                continue
            x, y = np.asarray(a[k]), np.asarray(b[k])
            if x.shape != y.shape or x.dtype != y.dtype or x.tobytes() != y.tobytes():
                differences.append(f"{side}:{k} differs")
    check(not differences, f"{what}: fluid.h5 and solid.h5 bitwise those of the uninterrupted run",
          "\n".join(differences[:20]) + f"\n({len(differences)} differences)")


def run_to_end(proc, what):
    text = proc.communicate(timeout=600)[0]
    check(proc.returncode == 0, f"{what} completes", text[-3000:])
    return text


os.makedirs(WORK, exist_ok=True)
ref = os.path.join(WORK, "reference")
shutil.rmtree(ref, ignore_errors=True)
t0 = time.monotonic()
run_to_end(start(ref, "--set", "output.checkpoint_seconds=0"), "the reference run")
print(f"   ({time.monotonic() - t0:.1f} s)")

# 2. SIGTERM once the shock has reached the plate.
out = os.path.join(WORK, "sigterm")
shutil.rmtree(out, ignore_errors=True)
p = start(out, "--set", "output.checkpoint_seconds=2")
wait_until(out, 6.8e-4, p)
p.send_signal(signal.SIGTERM)
text = p.communicate(timeout=120)[0]
logs = {s: open(os.path.join(out, f"{s}.log")).read() for s in ("fluid", "solid")}
steps = {}
for s in logs:
    for line in logs[s].splitlines():
        if "checkpoint at step" in line:
            steps[s] = int(line.split("checkpoint at step ")[1].split()[0])
check(p.returncode == 4 and steps.get("fluid") is not None and steps.get("fluid") == steps.get("solid"),
      f"SIGTERM: both sides stopped (exit {p.returncode}) with their last checkpoint at one step ({steps})",
      text[-2000:])
with h5py.File(os.path.join(out, "fluid.h5"), "r") as f:
    status = f["status"][()].decode().rstrip("\0")
check(status.startswith("failed: stopped by a signal (SIGTERM)"), f"fluid.h5 says why it stopped ('{status[:50]}')")
# Resumed with other progress and checkpoint intervals (they may differ; the case may not).
resumed = start(out, "--set", "output.checkpoint_seconds=3", "--set", "output.progress_seconds=0.3", "--resume", out)
text = run_to_end(resumed, "--resume after SIGTERM")
left = glob.glob(os.path.join(out, "*.checkpoint.*"))
check(not left, "the completed run removed its checkpoints", str(left))
check(f"resuming from {out}/fluid.checkpoint" in text and "(step " in text, "undex says where it resumes from",
      text[:1500])
same_as_reference(out, "SIGTERM, then --resume")

# 3. SIGKILL to everything after a periodic checkpoint, once frames were written after it.
def last_checkpoint(out):
    try:
        lines = [l for l in open(os.path.join(out, "fluid.log")) if "checkpoint at step" in l]
        return float(lines[-1].split("(t = ")[1].split()[0]) if lines else None
    except OSError:
        return None


out = os.path.join(WORK, "sigkill")
shutil.rmtree(out, ignore_errors=True)
p = start(out, "--set", "output.checkpoint_seconds=2")
deadline = time.monotonic() + 120
while time.monotonic() < deadline and p.poll() is None:
    t_last = last_checkpoint(out)
    if t_last is not None and fluid_time(out) > max(6.8e-4, t_last + 4e-5):
        break
    time.sleep(0.05)
kids = subprocess.run(["pgrep", "-P", str(p.pid)], capture_output=True, text=True).stdout.split()
for pid in [p.pid] + [int(k) for k in kids]:
    try:
        os.kill(pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
p.communicate()
time.sleep(0.5)
with h5py.File(newest_checkpoint(out, "fluid"), "r") as c:
    t_checkpoint = c.attrs["time"]
with h5py.File(os.path.join(out, "fluid.h5"), "r") as f:
    written = len(f["fields"])
    after = sum(1 for g in f["frames"].values() if g.attrs["time"] > t_checkpoint)
check(after > 0, f"killed {after} frame(s) after the last checkpoint (t = {t_checkpoint:.4g} s): to be dropped")
r = subprocess.run([UNDEX, "run", CASE, *SETS, "--set", "output.checkpoint_seconds=2", "--resume", out],
                   capture_output=True, text=True)
check(r.returncode == 1 and "stale lock" in r.stderr, "killed: the lock is stale, --resume without --force refused",
      r.stdout[-800:] + r.stderr)
# A checkpoint of another case: refused, naming the line, nothing run.
r = subprocess.run([UNDEX, "run", CASE, *SETS, "--set", "output.checkpoint_seconds=2", "--set", "numerics.cfl=0.15",
                    "--resume", out, "--force"], capture_output=True, text=True)
check(r.returncode != 0 and "the checkpoint is of another case" in (r.stdout + r.stderr) and "cfl" in (r.stdout + r.stderr),
      "a checkpoint of another case (numerics.cfl changed) is refused, naming the line", (r.stdout + r.stderr)[-1500:])

text = run_to_end(start(out, "--set", "output.checkpoint_seconds=2", "--resume", out, "--force"),
                  f"--resume --force after SIGKILL ({written} field outputs written before it)")
same_as_reference(out, "SIGKILL, then --resume --force")
killed = out

# 4. A fluid alone (cases/riemann_2d.case, 60 x 60 cells): undex becomes undex-fluid, which checkpoints
# every 0.2 s; killed after its second, resumed with --force.
solo = [os.path.join(SRC, "cases", "riemann_2d.case"), "--set", "domain.cells_x=60", "--set", "domain.cells_y=60",
        "--set", "numerics.threads=1"]
solo_ref, out = os.path.join(WORK, "solo_reference"), os.path.join(WORK, "solo")
for d in (solo_ref, out):
    shutil.rmtree(d, ignore_errors=True)
r = subprocess.run([UNDEX, "run", *solo, "--set", "output.checkpoint_seconds=0", "-o", solo_ref], capture_output=True,
                   text=True)
check(r.returncode == 0, "the fluid alone: the reference run completes", r.stdout[-1000:] + r.stderr)
p = subprocess.Popen([UNDEX, "run", *solo, "--set", "output.checkpoint_seconds=0.2", "-o", out],
                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
deadline = time.monotonic() + 60
seen = set()
while time.monotonic() < deadline and p.poll() is None and len(seen) < 2:
    seen |= set(glob.glob(os.path.join(out, "fluid.checkpoint.*.h5")))
    time.sleep(0.02)
p.kill()
p.wait()
r = subprocess.run([UNDEX, "run", *solo, "--set", "output.checkpoint_seconds=0.2", "--resume", out, "--force"],
                   capture_output=True, text=True)
check(r.returncode == 0 and "resuming from" in r.stdout, "the fluid alone: killed, then --resume --force completes",
      r.stdout[-1000:] + r.stderr)
a, b = contents(os.path.join(solo_ref, "fluid.h5")), contents(os.path.join(out, "fluid.h5"))
differences = [k for k in sorted(set(a) | set(b)) if k not in a or k not in b or
               np.asarray(a[k]).tobytes() != np.asarray(b[k]).tobytes()]
check(not differences, "the fluid alone: fluid.h5 bitwise that of the uninterrupted run", str(differences[:20]))

print(f"{failures} failure(s)")
sys.exit(1 if failures else 0)
