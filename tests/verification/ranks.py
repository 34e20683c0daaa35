#!/usr/bin/python3
"""The fluid on many MPI ranks (`undex run --ranks N`, fluid/ranks.hpp, docs/scale_out.md) gives the answer
of one rank to the last bit: every floating-point dataset and attribute of fluid.h5 (fields with their DG
coefficients, mass and energy, gauges) is compared with np.array_equal against the run on one rank. On many
ranks the field datasets of fluid.h5 join the rows each rank wrote to fluid.parts/rankNNNN.h5 (HDF5 virtual
datasets); checked: they are virtual on many ranks, one block per rank covering every row, and stored in
fluid.h5 on one; `undex sample` of a copied 4-rank run directory, from another working directory, prints the
one-rank run's text. Bitwise, not to a tolerance: each cell
is computed by one rank with the same operations in the same order as on one rank, halos are copies, and
the one reduction per step (Δt, the gauges) is a maximum, exact in any order.

Runs (one thread per rank; 4 ranks oversubscribe this host's 2 cores):
  riemann_2d, 64 x 64 cells at degree 2 with the WENO limiter, to t = 0.05, on 1, 2 and 4 ranks;
  tests/cases/still_water_2d.case (one fluid: a ball of water moving at (100, 40) m/s in water at rest,
    120 x 120 cells at degree 1, to 2e-4 s, three outputs, a gauge on a rank boundary), on 1 and 3 ranks: the still water is skipped (the halo carries the still-water test's reach) and the rows
    are divided again at outputs as the updated cells grow (the log must say so);
  free_field_2d (case 4.4: a gas bubble in water, level set and ghost fluid) at 80 x 80 as shipped on 1, 2
    and 4 ranks, and at 64 x 64 with the paper's setting (real GFM, WENO, degree 2) on 1 and 2 ranks: the
    level set and the interface treatment are every rank's, from the cell averages near the interface
    gathered from their owners.
  coupled to the structure (rank 0 talks to it): case 4.5 at 100 x 116 to 3e-4 s over ipc:// and over
    tcp://, and the application (steel plate) at 0.04 m to 1.8e-4 s, on 1 and 2 ranks: fluid.h5 and solid.h5.
Faults and refusals, on 2 ranks:
  a state the method cannot hold in one rank's rows (positivity and limiter off on a strong jump): exit
    status 2 with a message naming the rank, the cell and the step, the output kept with the last good state;
  case 4.4 at 64 x 64 with the bubble in rank 1's rows (y = 0.5, r = 0.3, 1e11 Pa; positivity and limiter
    off): the water fails in rank 1's rows in step 45, every rank ends with status 2, and fluid.h5 (the last
    good state included) is bitwise the one-rank run's, which fails alike;
  rank 1 killed (SIGKILL) during case 4.4 at 400 x 400: the run ends within 60 s with a message naming
    rank 1 and the step, fluid.h5 readable with the outputs written before;
  rank 1 killed during case 4.5 (coupled): the structure ends too, both files readable;
  rank 1 frozen (SIGSTOP: a hang) with numerics.rank_wait_seconds=3: rank 0 ends the run with exit status 3
    and a message naming rank 1 and the step, fluid.h5 readable;
  a case the ranks cannot run yet (1D) is refused before anything is written, naming numerics.ranks, and
    the error is told once (by rank 0), not once per rank.

    ranks.py BIN_DIR CASES_DIR WORK_DIR
"""
import os
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

bin_dir, cases, work = sys.argv[1:4]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []


def check(what, ok):
    print(("ok: " if ok else "FAIL: ") + what, flush=True)
    if not ok:
        failures.append(what)


def run(case, name, ranks, sets, more=()):
    args = [os.path.join(bin_dir, "undex"), "run", os.path.join(cases, case), "-o", os.path.join(work, name),
            "--set", "numerics.threads=1"] + list(more)
    if ranks > 1:
        args += ["--ranks", str(ranks)]
    for s in sets:
        args += ["--set", s]
    try:  # a rank left waiting for another would hang the run: a hang fails here
        p = subprocess.run(args, capture_output=True, text=True, timeout=120)
    except subprocess.TimeoutExpired as e:
        subprocess.run(["pkill", "-9", "-f", os.path.join(work, name)])
        return -1, "timed out after 120 s: %s" % (e.stdout or "")
    return p.returncode, p.stdout + p.stderr


def datasets(path):
    """The float datasets and the float attributes (time, mass, energy, ...) of a file, by name."""
    out = {}

    def visit(n, o):
        if isinstance(o, h5py.Dataset) and o.dtype.kind == "f":
            out[n] = o[()]
        for k, v in o.attrs.items():
            if np.asarray(v).dtype.kind == "f":
                out[n + "@" + k] = np.asarray(v)
    with h5py.File(path, "r") as f:
        f.visititems(visit)
    return out


def same(name, reference, other, side="fluid"):
    a, b = (datasets(os.path.join(work, d, side + ".h5")) for d in (reference, other))
    differ = [k for k in a if k not in b or a[k].shape != b[k].shape or not np.array_equal(a[k], b[k])]
    sets = sum("@" not in k for k in a)
    check("%s: %d float datasets and %d float attributes of %s.h5 bitwise the same as one rank%s" % (
        name, sets, len(a) - sets, side, "; differ: " + ", ".join(differ[:5]) if differ else ""),
        sets > 10 and not differ)


def joined(tag, ranks):
    """Whether every field dataset of TAG's fluid.h5 joins the ranks' rows from fluid.parts/rankNNNN.h5 (an
    HDF5 virtual dataset: one block of rows per rank, together all the rows) on many ranks, and is stored in
    fluid.h5 itself on one."""
    with h5py.File(os.path.join(work, tag, "fluid.h5"), "r") as f:
        for g in f["fields"].values():
            for d in g.values():
                if ranks == 1:
                    if d.is_virtual:
                        return False
                    continue
                if not d.is_virtual:
                    return False
                blocks = d.virtual_sources()
                files = sorted(b.file_name for b in blocks)
                rows = sum(b.vspace.get_select_npoints() for b in blocks)
                if files != ["fluid.parts/rank%04d.h5" % r for r in range(ranks)] or rows != d.size:
                    return False
    return True


riemann = ["domain.cells_x=64", "domain.cells_y=64", "end_time=0.05", "output.times[0]=0.025",
           "numerics.limiter=weno"]
for n in (1, 2, 4):
    status, log = run("riemann_2d.case", "riemann_%d" % n, n, riemann)
    check("riemann_2d on %d rank(s): exit status 0 (got %d)" % (n, status), status == 0)
    if status:
        print(log)
for n in (2, 4):
    same("riemann_2d on %d ranks" % n, "riemann_1", "riemann_%d" % n)

still = []
logs = {}
for n in (1, 3):
    status, logs[n] = run("../tests/cases/still_water_2d.case", "still_%d" % n, n, still)
    check("still water on %d rank(s): exit status 0 (got %d)" % (n, status), status == 0)
    if status:
        print(logs[n])
same("still water on 3 ranks", "still_1", "still_3")
check("still water: cell updates skipped", "cell updates skipped (still water)" in logs[1])
check("still water on 3 ranks: the rows divided again at an output", "rows divided again" in logs[3])

status, log = run("riemann_2d.case", "failure", 2, riemann[:4] + [
    "numerics.indicator=none", "numerics.positivity=false", "regions[3].p=1e4", "regions[3].rho=1e-3"])
print(log)
check("failure on 2 ranks: exit status 2 (got %d)" % status, status == 2)
check("failure on 2 ranks: the message names the rank, the cell and the step",
      "fluid rank " in log and "in cell (" in log and "in step " in log)
with h5py.File(os.path.join(work, "failure", "fluid.h5"), "r") as f:
    g = f["fields"][sorted(f["fields"])[-1]]
    check("failure on 2 ranks: status failed, the last good state written and finite",
          f["status"][()].decode().startswith("failed: fluid rank") and g.attrs["last_good"] == 1
          and np.isfinite(g["p"][()]).all())

bubble = ["domain.cells_x=80", "domain.cells_y=80"]
paper = ["domain.cells_x=64", "domain.cells_y=64", "interface.method=real_gfm", "numerics.limiter=weno",
         "numerics.degree=2", "numerics.cfl=0.2"]
for tag, sets, counts in (("bubble", bubble, (1, 2, 4)), ("bubble_paper", paper, (1, 2))):
    for n in counts:
        status, log = run("free_field_2d.case", "%s_%d" % (tag, n), n, sets)
        check("%s on %d rank(s): exit status 0 (got %d)" % (tag, n, status), status == 0)
        if status:
            print(log)
    for n in counts[1:]:
        same("case 4.4 (%s) on %d ranks" % (tag, n), "%s_1" % tag, "%s_%d" % (tag, n))
    for n in counts:
        check("case 4.4 (%s) on %d rank(s): fields %s" % (
            tag, n, "in fluid.h5" if n == 1 else "joined from the ranks' files"), joined("%s_%d" % (tag, n), n))
# A reader elsewhere (another working directory, a copy of the run directory) sees what one rank wrote.
copy = os.path.join(work, "copied", "bubble_4")
shutil.copytree(os.path.join(work, "bubble_4"), copy)
sample = [os.path.join(bin_dir, "undex"), "sample", "--time", "1", "--line", "0,0 1,1", "--points", "7"]
one, four = (subprocess.run(sample + [d], capture_output=True, text=True, cwd="/")
             for d in (os.path.join(work, "bubble_1"), copy))
check("case 4.4: undex sample of a copy of the run on 4 ranks, from /, prints what it does of one rank",
      one.returncode == 0 and four.returncode == 0 and one.stdout == four.stdout and len(one.stdout) > 100)


# Coupled to the structure: case 4.5 (a water-backed sandwich plate, one fluid on each side of it) at 0.02 m,
# over ipc:// and over tcp://; the application (a bubble under a steel plate: two fluids and a structure) at
# 0.04 m. Both files bitwise: the structure sees the same samples, so its answers are the same too.
plate = ["domain.cells_x=100", "domain.cells_y=116", "end_time=3e-4"]
app = ["domain.cells_x=125", "domain.cells_y=300", "end_time=1.8e-4"] + [
    "output.times[%d]=%g" % (k, 2e-5 * (k + 1)) for k in range(9)]
for tag, case, sets, more, n in (("plate", "sandwich_plate_water_backed_2d.case", plate, (), 1),
                                 ("plate", "sandwich_plate_water_backed_2d.case", plate, (), 2),
                                 ("plate_tcp", "sandwich_plate_water_backed_2d.case", plate, ("--tcp",), 2),
                                 ("app", "undex_steel_plate.case", app, (), 1),
                                 ("app", "undex_steel_plate.case", app, (), 2)):
    status, log = run(case, "%s_%d" % (tag, n), n, sets, more)
    check("%s on %d rank(s): exit status 0 (got %d)" % (tag, n, status), status == 0)
    if status:
        print(log)
    if tag == "plate_tcp":
        check("plate_tcp: coupled over tcp://", "coupled run over tcp://" in log)
    # structure.threads is 0 in the case: undex run gives the structure one thread beside the fluid's ranks.
    solid_log = open(os.path.join(work, "%s_%d" % (tag, n), "solid.log")).read()
    check("%s on %d rank(s): the structure on one thread" % (tag, n), ", 1 thread(s)," in solid_log)
    if n == 2:
        check("%s on 2 ranks: the summary gives each rank's waits" % tag,
              all("rank %d waited " % r in log for r in (0, 1)) and "(halo " in log)
for tag, reference in (("plate_2", "plate_1"), ("plate_tcp_2", "plate_1"), ("app_2", "app_1")):
    for side in ("fluid", "solid"):
        same("coupled %s on 2 ranks" % tag, reference, tag, side)
    check("coupled %s: fields joined from the ranks' files" % tag, joined(tag, 2))


def rank_pid(rank, tag):
    """The PID of the fluid's rank `rank` of the run writing to work/tag (by its MPI environment)."""
    for pid in os.listdir("/proc"):
        try:
            with open("/proc/%s/cmdline" % pid, "rb") as f:
                cmd = f.read()
            if b"undex-fluid" not in cmd or os.path.join(work, tag).encode() not in cmd:
                continue
            with open("/proc/%s/environ" % pid, "rb") as f:
                if ("OMPI_COMM_WORLD_RANK=%d" % rank).encode() in f.read().split(b"\0"):
                    return int(pid)
        except OSError:
            continue
    return None


def fault(tag, sig, sets, case="free_field_2d.case"):
    """Case 4.4 at 400 x 400 (or `case`) on 2 ranks; once its first output is written, `sig` to rank 1."""
    args = [os.path.join(bin_dir, "undex"), "run", os.path.join(cases, case), "-o",
            os.path.join(work, tag), "--ranks", "2", "--set", "numerics.threads=1"]
    for s in sets:
        args += ["--set", s]
    p = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    start = time.time()
    pid = None
    while time.time() - start < 60 and p.poll() is None:
        pid = rank_pid(1, tag)
        if pid and os.path.exists(os.path.join(work, tag, "fluid.xmf")) and time.time() - start > 2:
            break
        time.sleep(0.1)
    if pid and p.poll() is None:
        os.kill(pid, sig)
    sent = time.time()
    try:
        out, _ = p.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        p.kill()
        out, _ = p.communicate()
        subprocess.run(["pkill", "-9", "-f", os.path.join(work, tag)])
        return -1, out + " (timed out)", 1e9
    if pid:
        try:
            os.kill(pid, signal.SIGKILL)  # a frozen rank left behind, if any
        except OSError:
            pass
    return p.returncode, out, time.time() - sent


def readable(tag, side="fluid"):
    try:
        with h5py.File(os.path.join(work, tag, side + ".h5"), "r") as f:
            g = f["fields"][sorted(f["fields"])[-1]]
            field = "p" if side == "fluid" else "displacement"
            return len(f["fields"]) >= 1 and np.isfinite(g[field][()]).all()
    except (OSError, KeyError):
        return False


burst = ["domain.cells_x=64", "domain.cells_y=64", "numerics.positivity=false", "numerics.indicator=none",
         "regions[1].ball.y=0.5", "regions[1].ball.radius=0.3", "regions[1].p=1e11"]
for n in (1, 2):
    status, log = run("free_field_2d.case", "burst_%d" % n, n, burst)
    check("two fluids failing on %d rank(s): exit status 2 (got %d)" % (n, status), status == 2)
    if n == 2:
        print(log)
        check("two fluids failing on 2 ranks: rank 1's water, named", "fluid rank 1: water: " in log)
same("two fluids failing on 2 ranks (the last good state)", "burst_1", "burst_2")

status, log, took = fault("killed", signal.SIGKILL, [])
print(log)
check("rank 1 killed: the run ends (status %d) in %.1f s" % (status, took), status not in (0, -1) and took < 60)
check("rank 1 killed: the message names rank 1 and the step", "rank 1 " in log and " in step " in log)
check("rank 1 killed: fluid.h5 readable with the outputs written before", readable("killed"))

status, log, took = fault("killed_coupled", signal.SIGKILL, [], "sandwich_plate_water_backed_2d.case")
print(log)
check("rank 1 killed in a coupled run: the run ends (status %d) in %.1f s" % (status, took),
      status not in (0, -1) and took < 60)
check("rank 1 killed in a coupled run: the message names rank 1 and the step, the structure is stopped",
      "rank 1 " in log and " in step " in log and "undex: solid ended" in log)
check("rank 1 killed in a coupled run: fluid.h5 and solid.h5 readable with the outputs written before",
      readable("killed_coupled") and readable("killed_coupled", "solid"))

status, log, took = fault("hung", signal.SIGSTOP, ["numerics.rank_wait_seconds=3"])
print(log)
check("rank 1 hangs: rank 0 ends the run with status 3 (got %d) in %.1f s" % (status, took),
      status == 3 and took < 30)
check("rank 1 hangs: the message names rank 1 and the step",
      "fluid rank 0 has waited 3 s on rank 1" in log and " in step " in log)
check("rank 1 hangs: fluid.h5 readable with the outputs written before", readable("hung"))

status, log = run("sod_1d.case", "refused", 2, [])
check("1D on 2 ranks: refused naming numerics.ranks (exit status %d)" % status,
      status != 0 and "numerics.ranks" in log and not os.path.exists(os.path.join(work, "refused", "fluid.h5")))
check("1D on 2 ranks: the case error told once, not once per rank (%d times)" % log.count("numerics.ranks:"),
      log.count("numerics.ranks:") == 1)

print("%d failed" % len(failures))
sys.exit(1 if failures else 0)
