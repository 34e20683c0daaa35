"""What the Python tests over real processes share: the tally of their checks, the status of an output file,
and the time-step rule and output times of a coupled run from both sides' records (coupled_steps), a case
run from its text (run_case), and the wet face's histories of a 1D or 2D coupled run (wet_face_histories)."""
import os
import subprocess
import sys

import h5py

failures = []
passed = 0


def check(ok, what, detail=""):
    """Counts one check and prints it (with detail when it fails)."""
    global passed
    if ok:
        passed += 1
        print(f"ok: {what}")
    else:
        failures.append(what)
        print(f"FAIL: {what}\n{detail}")


def finish():
    """Prints the tally and exits, with status 1 when a check failed."""
    print(f"{passed} passed, {len(failures)} failed")
    sys.exit(1 if failures else 0)


def status_of(h5):
    """The status of an output file, which must open (the last complete output stays readable)."""
    try:
        with h5py.File(h5, "r") as f:
            return f["status"][()].decode()
    except Exception as e:  # noqa: BLE001 - any failure to read is the finding
        return f"unreadable: {e}"


def requested_times(end_time, interval):
    """The output times a case asks for with output.interval: k · interval below end_time, then end_time."""
    times = [k * interval for k in range(1, int(end_time / interval) + 2) if k * interval < end_time * (1 - 1e-12)]
    return times + [end_time]


def _structure_record(structure):
    """t, dt, dt_s of every step from the structure's own record: solid.h5 /coupling or a CSV with those columns
    (tests/coupling/rigid_plate.py --history, written with repr)."""
    import numpy as np
    if structure.endswith(".h5"):
        with h5py.File(structure, "r") as f:
            c = f["coupling"]
            t, dt, dt_s = c["t"][:], c["dt"][:], c["dt_s"][:]
        # undex-solid in 2D writes one row per step and wet node: the first row of each step (t increases).
        first = np.sort(np.unique(t, return_index=True)[1])
        return t[first], dt[first], dt_s[first]
    lines = open(structure).read().splitlines()
    cols = lines[0].split(",")
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]]).reshape(-1, len(cols))
    return rows[:, cols.index("t")], rows[:, cols.index("dt")], rows[:, cols.index("dt_s")]


def coupled_steps(out_dir, structure, end_time, requested, complete=True):
    """The time-step rule of a coupled run (physics.md §7, docs/protocol.md §3) from BOTH sides' records, and
    the output times. Returns a list of problems (empty when all hold) and a one-line summary.

    out_dir/fluid.h5 /interface holds per step t, dt, the fluid's own stable step dt_f and the offer dt_s it
    received; `structure` (solid.h5 or a CSV) holds t, dt and the dt_s it offered (None: a structure that keeps
    no record, e.g. tests/coupling/bad_peer.py; then only the fluid's record is checked). Checked:
    - both sides took the same steps: t and dt bitwise equal, and the offer received bitwise the offer made;
    - Δt = min(Δt_f, Δt_s) bitwise at every step, except a step shortened to end on a requested output time
      (then Δt < min(Δt_f, Δt_s) and t + Δt is that time within 1e-12 · end_time);
    - t starts at 0 and advances by the granted Δt (1e-12 · end_time);
    and for a complete run: the last step ends on end_time, and each side's field outputs (fluid.h5 and, when
    it writes fields, solid.h5 /fields/NNNNNN attribute time, after the initial one) sit at exactly the
    requested times (1e-12 · end_time: the clock's last step is target − t, a few ulps of drift; a step off
    would be 1e-4 of end_time or more). A failed run (complete=False) is checked over the steps both recorded.
    """
    import numpy as np
    tol = 1e-12 * end_time
    req = np.array(requested)
    problems = []
    try:
        with h5py.File(os.path.join(out_dir, "fluid.h5"), "r") as f:
            i = f["interface"]
            t, dt, dt_f, dt_s = i["t"][:], i["dt"][:], i["dt_f"][:], i["dt_s"][:]
    except (OSError, KeyError) as e:
        return [f"{out_dir}/fluid.h5 holds no readable /interface record ({e})"], "no record"
    try:
        ts, dts, offered = _structure_record(structure) if structure else (t, dt, dt_s)
    except (OSError, KeyError, ValueError) as e:
        return [f"{structure} holds no readable step record ({e})"], "no record"
    n = min(len(t), len(ts))
    if complete and len(t) != len(ts):
        problems.append(f"the fluid recorded {len(t)} steps, the structure {len(ts)}")
    if n == 0:
        return problems + ["no coupled step recorded"], "no steps"
    bits = lambda a: a[:n].view(np.uint64)  # noqa: E731
    for name, a, b in (("t", t, ts), ("dt", dt, dts), ("dt_s (received, offered)", dt_s, offered)):
        k = np.nonzero(bits(a) != bits(b))[0]
        if len(k):
            problems.append(f"step {k[0] + 1}: {name} differs between the structure ({b[k[0]]!r}) and the fluid "
                            f"({a[k[0]]!r}) ({len(k)} steps)")
    t, dt, dt_f, dt_s, offered = t[:n], dt[:n], dt_f[:n], dt_s[:n], offered[:n]
    lim = np.minimum(dt_f, offered)
    ends = t + dt
    on_output = np.min(np.abs(ends[:, None] - req[None, :]), axis=1) <= tol
    bad = np.nonzero(~((dt == lim) | ((dt < lim) & on_output)))[0]
    if len(bad):
        k = bad[0]
        problems.append(f"step {k + 1} (t = {t[k]!r} s): dt = {dt[k]!r} s is not min(dt_f = {dt_f[k]!r}, dt_s = "
                        f"{offered[k]!r}) and does not end on an output time ({len(bad)} steps)")
    gaps = np.abs(np.diff(t) - dt[:-1])
    if abs(t[0]) > tol or (len(gaps) and np.max(gaps) > tol):
        problems.append(f"the step times do not start at 0 and advance by dt (t[0] = {t[0]!r} s, largest gap "
                        f"{np.max(gaps, initial=0):.3g} s)")
    clipped = int(np.count_nonzero(dt < lim))
    summary = (f"{n} steps, {int(np.count_nonzero(dt_f < offered))} limited by dt_f and "
               f"{int(np.count_nonzero(offered < dt_f))} by dt_s, {clipped} shortened to an output time")
    if not complete:
        return problems, summary
    if abs(ends[-1] - end_time) > tol:
        problems.append(f"the last step ends at {ends[-1]!r} s, not at end_time {end_time!r} s")
    files = [os.path.join(out_dir, "fluid.h5")]
    if structure and structure.endswith(".h5"):
        files.append(structure)
    for path in files:
        with h5py.File(path, "r") as f:
            if "fields" not in f:
                continue
            written = sorted(float(g.attrs["time"]) for g in f["fields"].values())[1:]
        if len(written) != len(req) or np.max(np.abs(np.array(written) - req)) > tol:
            problems.append(f"{os.path.basename(path)}: outputs at {written} s, requested {list(req)} s")
    return problems, summary


def run_case(bin_dir, out, text, label):
    """Writes case text `text` to OUT/case.case and runs it with `undex run --force`; exits with the run's
    output on a failure. Returns OUT."""
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "case.case")
    with open(path, "w") as f:
        f.write(text)
    r = subprocess.run([os.path.join(bin_dir, "undex"), "run", path, "--force"], capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"FAIL: {label}: run failed ({r.returncode})\n{r.stdout[-3000:]}{r.stderr[-2000:]}")
    return out


def wet_face_histories(out, dim):
    """t, u_I, p_I of a coupled run's wet face: in 1D the fluid's /interface record, in 2D the structure's
    /coupling record of its centre wet node."""
    import numpy as np

    if dim == 1:
        with h5py.File(os.path.join(out, "fluid.h5")) as f:
            i = f["interface"]
            return i["t"][:], i["u_I"][:], i["p_I"][:]
    with h5py.File(os.path.join(out, "solid.h5")) as f:
        c = f["coupling"]
        t, u, p = c["t"][:], c["u_I"][:], c["p_I"][:]
    per = len(t) // len(np.unique(t))  # rows per step: one per wet node
    mid = per // 2
    return t[mid::per], u[mid::per], p[mid::per]
