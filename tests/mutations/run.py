#!/usr/bin/python3
"""Mutation register runner: does the test suite catch realistic bugs?

Each entry of register.toml names a source file, a piece of its text (which must occur exactly once), a
replacement (one small, realistic bug) and the CTest tests expected to catch it. For each entry this script
applies the change in a scratch copy of the source tree, rebuilds it incrementally, runs the named tests and
reports `caught` (some test failed) or `survived` (all passed). The source tree itself is never written.

    /usr/bin/python3 tests/mutations/run.py [--only ID ...] [--scratch DIR] [--jobs N] [--report FILE]
    /usr/bin/python3 tests/mutations/run.py --check BUILD_DIR   # register well-formed (a CTest test)

A benchmark, not a CI test: a full run rebuilds once per mutant (about 22 minutes on 2 cores for 61 mutants).
Exit status 1 when a mutant does not build or survives without a reason in the register.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
REGISTER = Path(__file__).resolve().parent / "register.toml"
FIELDS = {"id", "file", "find", "replace", "tests", "bug"}
OPTIONAL = {"survives"}


def load(path=REGISTER):
    """The register's entries, each checked for its fields; errors name the entry."""
    with open(path, "rb") as f:
        entries = tomllib.load(f).get("mutation", [])
    seen = set()
    errors = []
    good = []
    for n, m in enumerate(entries, 1):
        where = f"{path.name}: mutation {n} ({m.get('id', '?')})"
        missing = FIELDS - m.keys()
        extra = m.keys() - FIELDS - OPTIONAL
        if missing:
            errors.append(f"{where}: missing {', '.join(sorted(missing))}")
            continue
        if extra:
            errors.append(f"{where}: unknown field(s) {', '.join(sorted(extra))}")
        if m["id"] in seen:
            errors.append(f"{where}: id used twice")
        seen.add(m["id"])
        if m["find"] == m["replace"]:
            errors.append(f"{where}: the replacement equals the text")
        if not m["tests"]:
            errors.append(f"{where}: no tests named")
        good.append(m)
    return good, errors


def source_errors(entries, root=ROOT):
    """Each entry's text must occur exactly once in its file (so that the mutant is the one meant)."""
    errors = []
    for m in entries:
        path = root / m["file"]
        if not path.is_file():
            errors.append(f"{m['id']}: no file {m['file']}")
            continue
        count = path.read_text().count(m["find"])
        if count != 1:
            errors.append(f"{m['id']}: the text occurs {count} times in {m['file']} (must be once): {m['find']!r}")
    return errors


def ctest_names(build):
    out = subprocess.run(["ctest", "-N"], cwd=build, capture_output=True, text=True, check=True).stdout
    return set(re.findall(r"Test\s+#\d+: (\S+)", out))


def check(build):
    entries, errors = load()
    errors += source_errors(entries)
    names = ctest_names(build)
    for m in entries:
        for t in m["tests"]:
            if t not in names:
                errors.append(f"{m['id']}: no CTest test named {t}")
    for e in errors:
        print(f"register.toml: {e}", file=sys.stderr)
    areas = {}
    for m in entries:
        areas[m["file"].split("/")[0]] = areas.get(m["file"].split("/")[0], 0) + 1
    print(f"{len(entries)} mutations ({', '.join(f'{k} {v}' for k, v in sorted(areas.items()))}); "
          f"{len(errors)} error(s)")
    return 1 if errors else 0


def sync(scratch):
    """Copy the tracked and new source files into `scratch` (the copy's build goes to scratch/build, laid out
    like the source tree's, so that a compiler cache hits), writing only files whose content differs (so that
    the incremental build stays incremental)."""
    if scratch.resolve().is_relative_to(ROOT):
        raise SystemExit(f"--scratch {scratch} lies inside the source tree: choose a directory beside it")
    marker = scratch / ".undex-mutants"  # files of the copy are deleted below: never in another directory
    if scratch.exists() and any(scratch.iterdir()) and not marker.exists():
        raise SystemExit(f"--scratch {scratch} exists and is not a scratch copy of this runner: choose another")
    scratch.mkdir(parents=True, exist_ok=True)
    marker.touch()
    files = subprocess.run(["git", "ls-files", "-z", "-co", "--exclude-standard"], cwd=ROOT, capture_output=True,
                           text=True, check=True).stdout.split("\0")
    files = {f for f in files if f and (ROOT / f).is_file()}
    for f in files:
        a, b = ROOT / f, scratch / f
        if b.is_file() and b.read_bytes() == a.read_bytes():
            continue
        b.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(a, b)  # a new mtime: the build must see the change even if the source is older
    # Files gone from the tree go from the copy too (its build directory aside).
    for b in scratch.rglob("*"):
        rel = b.relative_to(scratch)
        if b.is_file() and rel.parts[0] != "build" and b != marker and rel.as_posix() not in files:
            b.unlink()
    return scratch


def build(src, bld, jobs):
    if not (bld / "CMakeCache.txt").exists():
        cmd = ["cmake", "-S", str(src), "-B", str(bld), "-DCMAKE_BUILD_TYPE=Release"]
        if shutil.which("ccache"):
            cmd.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            return False, r.stdout[-3000:] + r.stderr[-3000:]
    r = subprocess.run(["cmake", "--build", str(bld), "-j", str(jobs)], capture_output=True, text=True)
    return r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]


def run_tests(bld, tests, jobs):
    """Names of the failed tests among `tests` (empty: all passed)."""
    # A parametrised GoogleTest's CTest name goes on with "  # GetParam() = ...": the register names the part
    # before it.
    regex = "^(" + "|".join(re.escape(t) for t in tests) + ")( .*)?$"
    r = subprocess.run(["ctest", "-R", regex, "-j", str(jobs), "--timeout", "900"], cwd=bld,
                       capture_output=True, text=True)
    ran = re.findall(r"Test\s+#\d+: (\S+)", r.stdout)
    listed = r.stdout.split("The following tests FAILED:")[-1] if "The following tests FAILED:" in r.stdout else ""
    failed = set(re.findall(r"^\s*\d+ - (\S+)", listed, flags=re.M))
    if r.returncode != 0 and not failed:
        failed = {"(ctest: " + r.stdout.strip().splitlines()[-1] + ")"} if r.stdout.strip() else {"(ctest)"}
    missing = set(tests) - set(ran)
    if missing:
        raise SystemExit(f"the tests {', '.join(sorted(missing))} did not run: the register names tests "
                         "that do not exist")
    return sorted(failed)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", metavar="BUILD_DIR", help="only check the register against the sources and "
                    "the tests of BUILD_DIR")
    ap.add_argument("--only", nargs="+", metavar="ID", help="run these entries only")
    ap.add_argument("--scratch", default=str(ROOT.parent / (ROOT.name + "-mutants")),
                    help="scratch copy and its build (default: beside the source tree)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--report", help="write the result table (Markdown) here")
    a = ap.parse_args()
    if a.check:
        return check(Path(a.check))

    entries, errors = load()
    errors += source_errors(entries)
    if a.only:
        unknown = set(a.only) - {m["id"] for m in entries}
        if unknown:
            errors.append(f"no entries {', '.join(sorted(unknown))}")
        entries = [m for m in entries if m["id"] in a.only]
    if errors:
        for e in errors:
            print(f"register.toml: {e}", file=sys.stderr)
        return 2

    scratch = Path(a.scratch)
    src, bld = sync(scratch), scratch / "build"
    t0 = time.monotonic()
    ok, log = build(src, bld, a.jobs)
    if not ok:
        print(log, file=sys.stderr)
        raise SystemExit("the unmutated scratch copy does not build")
    baseline = run_tests(bld, sorted({t for m in entries for t in m["tests"]}), a.jobs)
    if baseline:
        raise SystemExit(f"the unmutated code fails {', '.join(baseline)}: fix that before measuring")
    print(f"baseline built and passing ({time.monotonic() - t0:.0f} s); {len(entries)} mutants", flush=True)

    rows = []
    for n, m in enumerate(entries, 1):
        t1 = time.monotonic()
        path = src / m["file"]
        original = path.read_text()
        try:
            path.write_text(original.replace(m["find"], m["replace"], 1))
            ok, log = build(src, bld, a.jobs)
            if not ok:
                result, detail = "no build", log.strip().splitlines()[-1] if log.strip() else ""
            else:
                failed = run_tests(bld, m["tests"], a.jobs)
                result = "caught" if failed else "survived"
                detail = ", ".join(failed) if failed else m.get("survives", "(no reason given: add one, or a test)")
                if failed and "survives" in m:
                    detail += " (the register still gives a reason to survive: remove it)"
        finally:
            path.write_text(original)
        rows.append((m, result, detail))
        print(f"[{n:2d}/{len(entries)}] {m['id']:<34} {result:<8} {time.monotonic() - t1:5.0f} s  {detail}",
              flush=True)
    build(src, bld, a.jobs)  # leave the scratch build unmutated

    valid = [r for r in rows if r[1] != "no build"]
    caught = sum(r[1] == "caught" for r in valid)
    lines = ["| mutation | file | bug | result | caught by / why it survives |", "|---|---|---|---|---|"]
    for m, result, detail in rows:
        cells = (m["id"], m["file"], m["bug"], result, detail)
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    summary = (f"caught {caught} of {len(valid)} mutants ({100.0 * caught / max(len(valid), 1):.0f} %)"
               + (f"; {len(rows) - len(valid)} did not build (fix the register)" if len(valid) < len(rows)
                  else "") + f"; {time.monotonic() - t0:.0f} s")
    print("\n" + "\n".join(lines) + "\n\n" + summary)
    if a.report:
        Path(a.report).write_text("\n".join(lines) + "\n\n" + summary + "\n")
    unexplained = [m["id"] for m, result, _ in rows if result == "survived" and "survives" not in m]
    if unexplained:
        print(f"survivors without a reason: {', '.join(unexplained)}")
    return 0 if len(valid) == len(rows) and not unexplained else 1


if __name__ == "__main__":
    sys.exit(main())
