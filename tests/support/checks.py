"""What the Python tests over real processes share: the tally of their checks and the status of an output
file."""
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
