#!/usr/bin/python3
"""Outputs that cannot be written, and long texts (issue 12, class 1), over real files and processes.

    output_failures.py BIN_DIR CASES_DIR PYTHON_DIR WORK_DIR

1. A disk that fills during a run. A fluid run (sod_1d, an output every 0.01 s), a structure run
   (sandwich_column_1d) and a coupled run (taylor_plate_1d: undex-fluid and undex-rigid) write into
   - a small tmpfs mounted for the test (`mount -t tmpfs -o size=...`: CI runs as root), too small for the
     run ("No space left on device"); where mount is refused this part says so and relies on the next;
   - a directory under RLIMIT_FSIZE (a file may not grow past the limit: its write fails with EFBIG, "File
     too large"; the solvers ignore SIGXFSZ), which needs no privilege.
   Each kind of run is made at several sizes, so that the first write to fail is a dataset's in some and a
   flush's or the XDMF file's in others. Each run must exit 2 (a failed output is a failure of the run,
   docs/protocol.md; the coupled run 2 or 3: the side that fills the disk first exits 2, its partner 3, and
   undex returns the fluid's status), not 0 and not 139 (a crash closing the file); say "done" nowhere;
   name in its error line the file and the cause (and the dataset when a dataset's write failed: some run
   of each kind must); leave its .h5 readable by h5py, every dataset readable, the status `failed: ...`
   (and some run of each kind at least one output: the last good state), or no .h5 at all when the error
   line says it could not be created; and leave the XDMF file absent or complete: parsable, never empty,
   naming only outputs the .h5 holds, no .tmp left.
2. A case with a 3 000-point pressure table (a case text of about 170 kB, over HDF5's 64 kB limit of an
   attribute) runs and stores its case text and its status.
3. A peer's Error message of 200 000 characters: undex-rigid exits 3 and its status quotes the message's
   start and its length (coupler/messages.hpp quote).
"""
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import threading
import xml.etree.ElementTree as ET

import h5py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from checks import check, finish  # noqa: E402

BIN, CASES, PYDIR, WORK = [os.path.abspath(p) for p in sys.argv[1:5]]
sys.path.insert(0, PYDIR)


def text(dataset):
    v = dataset[()]
    return v.decode() if isinstance(v, bytes) else str(v)


def h5_findings(path):
    """(status, number of outputs, problems) of an output file; every dataset is read."""
    problems = []
    try:
        with h5py.File(path, "r") as f:
            status = text(f["status"])
            outputs = len(f["fields"]) if "fields" in f else 0
            if "gauges/plate/t" in f:  # undex-rigid: the rows of the plate's history
                outputs = len(f["gauges/plate/t"])

            def visit(name, obj):
                try:
                    if isinstance(obj, h5py.Dataset):
                        obj[()]
                    else:
                        dict(obj.attrs)
                except Exception as e:  # noqa: BLE001 - any failure to read is the finding
                    problems.append(f"{name}: {e}")

            f.visititems(visit)
            return status, outputs, problems
    except Exception as e:  # noqa: BLE001
        return f"unreadable: {e}", 0, [str(e)]


def xdmf_findings(out):
    """Problems of the XDMF files of an output directory (absent is fine)."""
    problems = [f"{n} left behind" for n in os.listdir(out) if n.endswith(".tmp")]
    for name in ("fluid.xmf", "solid.xmf"):
        path = os.path.join(out, name)
        if not os.path.exists(path):
            continue
        if os.path.getsize(path) == 0:
            problems.append(f"{name} is empty")
            continue
        try:
            items = [e.text.strip() for e in ET.parse(path).iter("DataItem") if e.get("Format") == "HDF"]
            with h5py.File(os.path.join(out, name.replace(".xmf", ".h5")), "r") as f:
                for item in items:
                    f[item.split(":", 1)[1]][()]
        except Exception as e:  # noqa: BLE001
            problems.append(f"{name}: {e}")
    return problems


# Runs filling the disk: (name, case, overrides, output files, tmpfs sizes in KiB, RLIMIT_FSIZE limits in
# bytes). The sizes run from a file that takes its first output only in part to one that takes most of the
# run (measured: sod_1d 470 kB in all, sandwich_column_1d 4.3 MB, taylor_plate_1d 360 kB), so that the first
# write to fail is, in one run or another, a dataset's, a flush's (the groups and links of an output) and the
# XDMF file's; at 40 KiB the coupled run's fluid fills the disk before undex-rigid can create solid.h5.
RUNS = [
    ("fluid", "sod_1d.case", ["output.interval=0.01"], ["fluid.h5"], [12, 24, 48, 96, 136, 200, 300],
     [10_000, 30_000, 60_000, 150_000, 300_000]),
    ("structure", "sandwich_column_1d.case", [], ["solid.h5"], [12, 16, 20, 24, 32, 64, 256, 1024],
     [10_000, 20_000, 30_000, 100_000, 1_000_000]),
    ("coupled", "taylor_plate_1d.case", ["end_time=2e-4", "output.interval=5e-5"], ["fluid.h5", "solid.h5"],
     [40, 100, 250], [200_000]),
]


def full_disk_run(how, name, case, sets, files, out, limit=None):
    """Checks one run; returns (whether its error line named a dataset, outputs kept in its first file)."""
    args = [os.path.join(BIN, "undex"), "run", os.path.join(CASES, case), "-o", out]
    for s in sets:
        args += ["--set", s]

    def cap():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    r = subprocess.run(args, capture_output=True, text=True, timeout=120, preexec_fn=cap if limit else None)
    said = r.stdout + r.stderr
    label = f"{how}: {name}"
    cause = "No space left on device" if how == "tmpfs" else "File too large"
    ok_status = (2, 3) if name == "coupled" else (2,)
    check(r.returncode in ok_status, f"{label}: exit status {' or '.join(map(str, ok_status))} (got {r.returncode})",
          said)
    check(not re.search(r": done:", said), f"{label}: nothing says done", said)
    # undex returns the fluid's status: each side's own exit code (in undex's lines) is 2 or 3, never a crash.
    sides = re.findall(r"undex: (\w+) ended with exit code (\d+)", said)
    check(all(int(c) in (2, 3) for _, c in sides), f"{label}: no side crashed ({sides})", said)
    names = "|".join(re.escape(f) for f in files + [f.replace(".h5", ".xmf") for f in files])
    error = re.search(rf"error: {re.escape(out)}/({names})(: /\S+)?: cannot [^:]+: {cause}", said)
    check(error, f"{label}: the error names the file and '{cause}'", said)
    kept = []
    for f in files:
        if not os.path.exists(os.path.join(out, f)) and f"error: {out}/{f}: " in said:
            # A file that could not take its case text and status is removed (its partner filled the disk).
            check(True, f"{label}: {f} could not be created, and is not there")
            kept.append(0)
            continue
        status, outputs, problems = h5_findings(os.path.join(out, f))
        kept.append(outputs)
        check(status.startswith("failed: ") and not problems,
              f"{label}: {f} readable with {outputs} output(s), status failed", f"{status}\n{problems}")
    problems = xdmf_findings(out)
    check(not problems, f"{label}: XDMF absent or complete", "\n".join(problems))
    return bool(error and error.group(2)), kept[0]


def sweep(how, name, case, sets, files, sizes, run):
    named, kept = False, 0
    for size in sizes:
        n, k = run(size)
        named, kept = named or n, max(kept, k)
    check(named, f"{how}: {name}: a run names the dataset whose write failed")
    check(kept >= 1, f"{how}: {name}: a run keeps its last good state ({kept} outputs)")


# 1a. A full tmpfs.
mnt = tempfile.mkdtemp(prefix="undex-full-")
mounted = True


def on_tmpfs(name, case, sets, files, kib):
    global mounted
    m = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={kib}k", "tmpfs", mnt], capture_output=True, text=True)
    if m.returncode != 0:
        mounted = False
        raise RuntimeError(m.stderr.strip())
    try:
        return full_disk_run("tmpfs", name, case, sets, files, os.path.join(mnt, "out"))
    finally:
        subprocess.run(["umount", mnt])


try:
    for name, case, sets, files, sizes, _ in RUNS:
        sweep("tmpfs", name, case, sets, files, sizes, lambda kib: on_tmpfs(name, case, sets, files, kib))
except RuntimeError as e:
    print(f"note: mount refused ({e}): the full disk is tested with RLIMIT_FSIZE alone")
os.rmdir(mnt)

# 1b. RLIMIT_FSIZE.
for name, case, sets, files, _, limits in RUNS:
    def capped(limit):
        out = os.path.join(WORK, "fsize", f"{name}-{limit}")
        shutil.rmtree(out, ignore_errors=True)
        return full_disk_run("RLIMIT_FSIZE", name, case, sets, files, out, limit)

    sweep("RLIMIT_FSIZE", name, case, sets, files, limits, capped)

# 2. A 3 000-point pressure table on the structure's front face (p falling linearly from 1 MPa to 0 in 2 ms).
n = 3000
case = open(os.path.join(CASES, "sandwich_column_1d.case")).read()
table = ("table_t: [" + ", ".join(f"{2e-3 * k / (n - 1):.9e}" for k in range(n)) + "] table_p: [" +
         ", ".join(f"{1e6 * (1 - k / (n - 1)):.9e}" for k in range(n)) + "]")
case, found = re.subn(r"front \{ type: PRESSURE pressure \{[^}]*\} \}",
                      f"front {{ type: PRESSURE pressure {{ p_ambient: 0 {table} }} }}", case)
assert found == 1
out = os.path.join(WORK, "table")
shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)
path = os.path.join(out, "table.case")
open(path, "w").write(case)
r = subprocess.run([os.path.join(BIN, "undex"), "run", path, "--set", "end_time=2e-4", "-o", out],
                   capture_output=True, text=True, timeout=120)
check(r.returncode == 0, f"3000-point table: the run completes (got {r.returncode})", r.stdout + r.stderr)
with h5py.File(os.path.join(out, "solid.h5"), "r") as f:
    stored = text(f["case"])
    check(len(stored) > 65536 and stored.count("table_t:") == n and stored.count("table_p:") == n,
          f"3000-point table: the case text is stored whole ({len(stored)} characters, {n} rows)")
    check(text(f["status"]) == "complete", f"3000-point table: status complete (got {text(f['status'])[:80]!r})")
g = subprocess.run([os.path.join(BIN, "undex"), "gauges", out, "--name", "back"], capture_output=True, text=True)
check(g.returncode == 0 and g.stdout.startswith("t,"), "3000-point table: undex gauges reads the output back",
      g.stderr)

# 3. A fluid peer whose Error message is 200 000 characters long, to undex-rigid.
import zmq  # noqa: E402
import coupling_pb2 as pb  # noqa: E402

long_message = "".join(f"line {k}: the fluid reports a long story. " for k in range(5000))[:200_000]
endpoint = f"ipc://{tempfile.gettempdir()}/undex-output-failures-{os.getpid()}.ipc"
ctx = zmq.Context()
sock = ctx.socket(zmq.PAIR)
sock.setsockopt(zmq.LINGER, 2000)
sock.bind(endpoint)


def fluid_peer():
    def send(step, **body):
        e = pb.Envelope(protocol=1, step=step)
        for k, v in body.items():
            getattr(e, k).CopyFrom(v)
        sock.send(e.SerializeToString())

    if sock.poll(20000):
        sock.recv()  # Hello
        send(0, welcome=pb.Welcome(solver="output_failures.py", version="1", end_time=1.0))
        if sock.poll(20000):
            sock.recv()  # the Offer of step 1
            send(1, error=pb.Error(message=long_message))


peer = threading.Thread(target=fluid_peer)
peer.start()
out = os.path.join(WORK, "long_error")
shutil.rmtree(out, ignore_errors=True)
r = subprocess.run([os.path.join(BIN, "undex-rigid"), os.path.join(CASES, "taylor_plate_1d.case"), "-o", out,
                    "--couple", endpoint], capture_output=True, text=True, timeout=60)
peer.join()
sock.close()
ctx.term()
check(r.returncode == 3, f"long Error: undex-rigid exits 3 (got {r.returncode})", r.stderr[-2000:])
status, _, problems = h5_findings(os.path.join(out, "solid.h5"))
# The peer's text is quoted bounded (coupler/messages.hpp quote: its first 1000 characters and its length).
check(status.startswith("failed: coupling: ") and long_message[:900] in status and
      f"{len(long_message)} bytes in all" in status and not problems,
      f"long Error: the status quotes its start and its length ({len(status)} characters)", status[:300])

finish()
