#!/bin/bash
# One run per output directory (base/run_lock.hpp) and a broken stdout, over real processes and signals:
#  1. a second run into the directory of a live coupled `undex run` is refused at once (exit status 1) with a
#     message naming the first (pid, host, start time, command), --force included, and touches no file of the
#     first (checksums taken while the first is held with SIGSTOP); the first then completes;
#  2. a solver started alone and stopped by SIGTERM or SIGHUP removes its lock; killed with SIGKILL it leaves a
#     stale lock: refused without --force (the file and the lock unchanged), taken over with --force, and
#     removed when that run ends;
#  3. a lock file written by a process that has exited is stale as well (a coupled run takes it with --force);
#  4. `undex run CASE | head -1` completes the run (a single-field run and a coupled one): exit status 0,
#     status `complete`, the logs written to the end; so does a run with stdout and stderr closed;
#  5. a run refused after taking the lock (a bad region) leaves neither the lock nor the directory it made.
# Every run here takes at most a few seconds (short end times).
set -u
undex=$1
bin=$2
cases=$3
dir=$(mktemp -d)
pids=()
trap 'for p in "${pids[@]}"; do kill -KILL -- "$p" 2>/dev/null; done; rm -rf "$dir"' EXIT
pass=0 fail=0
check() { if eval "$2"; then echo "ok: $1"; pass=$((pass + 1)); else echo "FAIL: $1"; fail=$((fail + 1)); fi; }
status_of() { /usr/bin/python3 -c "import h5py,sys; print(h5py.File(sys.argv[1],'r')['status'][()].decode().rstrip(chr(0)))" "$1" 2>&1; }
# Waits (up to 30 s) until the command $1 is true.
wait_for() { for _ in $(seq 300); do eval "$1" && return 0; sleep 0.1; done; return 1; }
sums() { (cd "$1" && sha256sum ./*); }

# 1. A live coupled run and a second one into its directory.
one=$dir/one
"$undex" run "$cases/taylor_plate_1d.case" --set end_time=4e-4 -o "$one" >"$dir/one.out" 2>&1 &
first=$!
pids+=("$first")
wait_for '[ -f "$one/fluid.log" ] && grep -q "coupled to" "$one/fluid.log" && [ -f "$one/solid.h5" ]'
children=$(pgrep -P "$first" | tr '\n' ' ')
kill -STOP "$first" $children
before=$(sums "$one")
lock_text=$(cat "$one/undex.lock")
t0=$(date +%s%N)
"$undex" run "$cases/taylor_plate_1d.case" -o "$one" >"$dir/second.out" 2>&1
second=$?
took_ms=$((($(date +%s%N) - t0) / 1000000))
"$undex" run "$cases/taylor_plate_1d.case" -o "$one" --force >"$dir/forced.out" 2>&1
forced=$?
"$bin/undex-fluid" "$cases/sod_1d.case" -o "$one" >"$dir/alone.out" 2>&1
alone=$?
after=$(sums "$one")
cat "$dir/second.out"
start=$(sed -n 's/^start=//p' <<<"$lock_text")
check "second run refused with exit status 1 (got $second) in $took_ms ms (bound 3000: a check, no run)" \
    '[ $second -eq 1 ] && [ $took_ms -lt 3000 ]'
check "the message names the first run: pid, host, start time, command" \
    'grep -q "is in use by another run: pid $first on host $(hostname) since $start (.*undex run .*taylor_plate_1d.case --set end_time=4e-4 -o $one)" "$dir/second.out"'
check "--force does not take a live lock (got $forced)" '[ $forced -eq 1 ] && grep -q "in use by another run: pid $first" "$dir/forced.out"'
check "a solver alone is refused as well (got $alone)" '[ $alone -eq 1 ] && grep -q "in use by another run: pid $first" "$dir/alone.out"'
check "no file of the first run touched (checksums while it is stopped)" '[ "$before" = "$after" ] && [ "$(cat "$one/undex.lock")" = "$lock_text" ]'
kill -CONT "$first" $children
wait "$first"
rc=$?
check "the first run completes (exit $rc), both outputs complete, its lock removed" \
    '[ $rc -eq 0 ] && [ "$(status_of "$one/fluid.h5")" = complete ] && [ "$(status_of "$one/solid.h5")" = complete ] && [ ! -e "$one/undex.lock" ]'

# 2a. A solver alone stopped by SIGTERM or SIGHUP (its terminal closed): last good state, exit 4, lock removed.
for sig in TERM HUP; do
    "$bin/undex-fluid" "$cases/sod_1d.case" --set domain.cells_x=3000 -o "$dir/sig$sig" >"$dir/sig.out" 2>&1 &
    victim=$!
    pids+=("$victim")
    wait_for '[ -f "$dir/sig$sig/fluid.h5" ] && grep -q "^pid=$victim" "$dir/sig$sig/undex.lock" 2>/dev/null'
    kill -$sig "$victim"
    wait "$victim"
    rc=$?
    check "SIG$sig to a solver alone: exit $rc (4), status says so, lock removed" \
        '[ $rc -eq 4 ] && [ "$(status_of "$dir/sig$sig/fluid.h5")" = "failed: stopped by a signal (SIG$sig)" ] && [ ! -e "$dir/sig$sig/undex.lock" ]'
done

# 2b. A solver alone killed with SIGKILL: a stale lock.
two=$dir/two
"$bin/undex-fluid" "$cases/sod_1d.case" --set domain.cells_x=3000 -o "$two" >"$dir/two.out" 2>&1 &
victim=$!
pids+=("$victim")
wait_for '[ -f "$two/fluid.h5" ] && grep -q "^pid=$victim" "$two/undex.lock" 2>/dev/null'
kill -KILL "$victim"
wait "$victim" 2>/dev/null
before=$(sums "$two")
"$undex" run "$cases/sod_1d.case" -o "$two" >"$dir/stale.out" 2>&1
stale=$?
cat "$dir/stale.out"
check "stale lock refused without --force (exit $stale), the message says stale, names pid $victim and --force" \
    '[ $stale -eq 1 ] && grep -q "holds the stale lock of a run that ended without removing it.*pid $victim on host $(hostname).*undex-fluid.*--force takes the lock over" "$dir/stale.out"'
check "the refused run touched nothing" '[ "$before" = "$(sums "$two")" ]'
"$undex" run "$cases/sod_1d.case" -o "$two" --force >"$dir/force.out" 2>&1
rc=$?
check "--force takes the stale lock over, saying whose: exit $rc, status complete, lock removed" \
    '[ $rc -eq 0 ] && grep -q "took over the stale lock of pid $victim on host" "$dir/force.out" && [ "$(status_of "$two/fluid.h5")" = complete ] && [ ! -e "$two/undex.lock" ]'

# 3. A lock file left by a process that has exited, on a coupled run.
three=$dir/three
mkdir -p "$three"
sh -c 'printf "pid=%s\nhost=%s\nstart=2026-01-01T00:00:00Z\ncommand=undex run old.case\n" $$ "$(hostname)"' >"$three/undex.lock"
"$undex" run "$cases/taylor_plate_1d.case" --set end_time=1e-4 -o "$three" >"$dir/three.out" 2>&1
rc=$?
check "a lock of an exited process is stale: refused (exit $rc), naming its command" \
    '[ $rc -eq 1 ] && grep -q "stale lock.*since 2026-01-01T00:00:00Z (undex run old.case)" "$dir/three.out" && [ ! -e "$three/fluid.log" ]'
"$undex" run "$cases/taylor_plate_1d.case" --set end_time=1e-4 -o "$three" --force >"$dir/three.out" 2>&1
rc=$?
check "coupled run with --force takes it: exit $rc, both complete, lock removed" \
    '[ $rc -eq 0 ] && [ "$(status_of "$three/fluid.h5")" = complete ] && [ "$(status_of "$three/solid.h5")" = complete ] && [ ! -e "$three/undex.lock" ]'

# 4. A broken stdout: progress lines every step after head has gone.
"$undex" run "$cases/sod_1d.case" --set output.progress_seconds=1e-6 -o "$dir/pipe1" | head -1 >/dev/null
rc=("${PIPESTATUS[@]}")
check "undex run (single field) | head -1: exit ${rc[0]}, status complete" \
    '[ ${rc[0]} -eq 0 ] && [ "$(status_of "$dir/pipe1/fluid.h5")" = complete ] && [ ! -e "$dir/pipe1/undex.lock" ]'
"$undex" run "$cases/taylor_plate_1d.case" --set end_time=1e-4 --set output.progress_seconds=1e-6 -o "$dir/pipe2" |
    head -1 >/dev/null
rc=("${PIPESTATUS[@]}")
check "undex run (coupled) | head -1: exit ${rc[0]}, both complete, logs to the end" \
    '[ ${rc[0]} -eq 0 ] && [ "$(status_of "$dir/pipe2/fluid.h5")" = complete ] && [ "$(status_of "$dir/pipe2/solid.h5")" = complete ] && grep -q "undex-fluid: done" "$dir/pipe2/fluid.log" && grep -q "undex-rigid: done" "$dir/pipe2/solid.log"'

# Closed stdout and stderr: no file opened later (the lock, whose descriptor the solvers inherit) takes their
# place.
"$undex" run "$cases/taylor_plate_1d.case" --set end_time=1e-4 -o "$dir/closed" >&- 2>&-
rc=$?
check "undex run (coupled) >&- 2>&-: exit $rc, both complete, logs to the end" \
    '[ $rc -eq 0 ] && [ "$(status_of "$dir/closed/fluid.h5")" = complete ] && [ "$(status_of "$dir/closed/solid.h5")" = complete ] && grep -q "undex-rigid: done" "$dir/closed/solid.log"'

# A structure solver started through a program in between (structure.command running a shell that does not
# exec it): undex is not its parent, so it must not take that for undex's death and stop.
"$undex" run "$cases/taylor_plate_1d.case" --set end_time=1e-4 -o "$dir/wrapped" \
    --set "structure.command=/bin/sh -c '\"$bin/undex-rigid\" \"$cases/taylor_plate_1d.case\" --set end_time=1e-4 -o \"$dir/wrapped\" \"\$@\"; exit \$?' wrapper" \
    >"$dir/wrapped.out" 2>&1
rc=$?
check "a structure solver behind a wrapper (exit $rc): both complete" \
    '[ $rc -eq 0 ] && [ "$(status_of "$dir/wrapped/fluid.h5")" = complete ] && [ "$(status_of "$dir/wrapped/solid.h5")" = complete ]'

# 5. A case refused after the lock was taken leaves nothing behind.
"$bin/undex-fluid" "$cases/sod_1d.case" --set regions[1].rho=-1 -o "$dir/new/out" >"$dir/bad.out" 2>&1
rc=$?
check "a bad case (exit $rc) leaves no directory and no lock" '[ $rc -eq 1 ] && [ ! -e "$dir/new" ]'

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
