#!/usr/bin/python3
"""Digests of every output dataset of every case in cases/, for refactors that must not change results.

    output_digests.py BIN_DIR CASES_DIR WORK_DIR [--runs N] [--case NAME]... [--variant NAME]...

Runs each case of CASES_DIR with `undex run` at a short end time (one OpenMP thread per side), N times
(default 2), in variants that reach different parts of the run loop:

    short         output times dropped: only the start and the end are written
    outputs       two output times inside the run: steps cut to land on them, fields and histories there
    max_steps     numerics.max_steps = 7 (cases with a fluid, which owns the clock): the failure path, the
                  last good state, a coupled partner told
    original_gfm  interface.method = original_gfm (cases with two fluids)

and prints one line per dataset and attribute of fluid.h5 / solid.h5:

    CASE/VARIANT FILE OBJECT sha256

Texts that hold the path of the run (the case text names the output directory) are digested after the work
directory is replaced by a fixed name, the same way whether they are attributes or string datasets (the case
text and the status were attributes /@case, /@status before issue 12; they are datasets case, status now:
rename them to compare older lists). Exits 1 when the runs of one case disagree (the outputs do not
reproduce), so a digest list is only printed when it is worth comparing. Compare two lists with diff.
"""
import argparse
import hashlib
import os
import re
import subprocess
import sys

import h5py
import numpy as np

# Short end times: a few dozen steps of each case.
END_TIMES = {
    "bubble_1d_cylindrical": 2e-6,
    "bubble_1d_spherical": 2e-6,
    "cavitation_tube_1d": 1e-5,
    "free_field_2d": 2e-6,
    "riemann_2d": 0.02,
    "sandwich_column_1d": 1e-4,
    "sandwich_plate_axisymmetric": 1e-4,
    "sandwich_shock_1d": 2e-4,
    "sod_1d": 0.02,
    "taylor_plate_1d": 6e-5,
    "undex_1d": 2e-5,
}


def digest_file(path, work):
    lines = []

    def attrs(name, obj):
        for key in sorted(obj.attrs):
            value = obj.attrs[key]
            if isinstance(value, bytes):
                value = value.decode()
            if isinstance(value, str):
                data = value.replace(work, "WORK").encode()
            else:
                data = np.asarray(value).tobytes()
            lines.append((f"{name}@{key}", hashlib.sha256(data).hexdigest()))

    def visit(name, obj):
        attrs(name, obj)
        if isinstance(obj, h5py.Dataset):
            value = obj[()]
            if isinstance(value, bytes):  # a text (case, status): digested as a text attribute is
                data = value.decode().replace(work, "WORK").encode()
            else:
                data = np.ascontiguousarray(value).tobytes()
            lines.append((name, hashlib.sha256(data).hexdigest()))

    with h5py.File(path, "r", locking=False) as f:
        attrs("/", f)
        f.visititems(visit)
    return lines


# Variants: (applies to the case text, extra --set overrides, output times as fractions of the end time).
VARIANTS = {
    "short": (lambda text: True, [], []),
    "outputs": (lambda text: True, [], [1 / 3, 2 / 3]),
    "max_steps": (lambda text: re.search(r"^regions\b", text, re.M), ["numerics.max_steps=7"], []),
    "original_gfm": (lambda text: re.search(r"^interface\s*\{", text, re.M), ["interface.method=original_gfm"],
                     []),
}


def run_case(bin_dir, case_path, name, variant, work):
    text = open(case_path).read()
    text = re.sub(r"\btimes\s*:\s*\[[^\]]*\]", "", text)
    text = re.sub(r"\binterval\s*:\s*[0-9.eE+-]+", "", text)
    applies, overrides, fractions = VARIANTS[variant]
    if not applies(text):
        return None
    end = END_TIMES[name]
    if fractions:
        times = "times: [" + ", ".join(repr(f * end) for f in fractions) + "] "
        text, n = re.subn(r"^output\s*\{", "output { " + times, text, flags=re.M)
        if n == 0:
            text += "\noutput { " + times + "}\n"
    os.makedirs(work, exist_ok=True)
    case = os.path.join(work, name + ".case")
    with open(case, "w") as f:
        f.write(text)
    out = os.path.join(work, "out")
    env = dict(os.environ, OMP_NUM_THREADS="1")
    cmd = [os.path.join(bin_dir, "undex"), "run", case, "--set", f"end_time={end}",
           "--set", f"output.directory={out}"]
    for o in overrides:
        cmd += ["--set", o]
    r = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != (2 if variant == "max_steps" else 0):
        sys.exit(f"{name}: {' '.join(cmd)} failed ({r.returncode}):\n{r.stdout}")
    lines = []
    for file in ("fluid.h5", "solid.h5"):
        path = os.path.join(out, file)
        if os.path.exists(path):
            lines += [(file, obj, d) for obj, d in digest_file(path, work)]
    return lines


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bin_dir")
    ap.add_argument("cases_dir")
    ap.add_argument("work_dir")
    ap.add_argument("--runs", type=int, default=2)
    ap.add_argument("--case", action="append")
    ap.add_argument("--variant", action="append", choices=sorted(VARIANTS))
    a = ap.parse_args()
    names = a.case or sorted(f[:-5] for f in os.listdir(a.cases_dir) if f.endswith(".case"))
    for name in names:
        if name not in END_TIMES:
            sys.exit(f"{name}: no short end time in {__file__}: add one")
        for variant in a.variant or list(VARIANTS):
            work = os.path.abspath(os.path.join(a.work_dir, name, variant))
            runs = [run_case(a.bin_dir, os.path.join(a.cases_dir, name + ".case"), name, variant, work)
                    for _ in range(a.runs)]
            if runs[0] is None:
                continue
            if any(r != runs[0] for r in runs[1:]):
                sys.exit(f"{name}/{variant}: the {a.runs} runs give different outputs")
            for file, obj, d in runs[0]:
                print(f"{name}/{variant}", file, obj, d)
            print(f"{name}/{variant}: {len(runs[0])} digests, reproduced in {a.runs} runs", file=sys.stderr)


if __name__ == "__main__":
    main()
