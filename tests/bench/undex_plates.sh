#!/bin/bash
# The paper's application (cases/undex_steel_plate.case, cases/undex_sandwich_plate.case) at one fluid
# resolution, each run timed with /usr/bin/time -v, and where its time goes:
#   wall       the run's wall time (/usr/bin/time), peak memory the larger process's maximum resident set;
#   fluid      undex-fluid's own wall time, of which coupling (inside the coupling library: waiting for the
#              structure and the messages) and wet faces (rebuilding φ_s and the ghost bands);
#   structure  undex-solid's own steps.
# Usage: tests/bench/undex_plates.sh BUILD_DIR OUT_DIR CELLS_X CELLS_Y [THREADS] [extra --set ...]
#   e.g. tests/bench/undex_plates.sh build out/res 250 600        (fluid cells 0.02 m, two fluid threads)
# THREADS (default 2) are the fluid's; the structure runs on one thread (its steps are under 4 % of a run
# and it waits for the fluid otherwise, so a second structure thread would only take a core from the fluid).
# The runs stay in OUT_DIR/steel_CELLS_X and OUT_DIR/sandwich_CELLS_X for undex_findings.py and
# undex_convergence.py. Both plates run one after the other (on 2 cores, running them side by side with one
# thread each is faster in all but shares the memory bandwidth: say which in a report).
set -euo pipefail
build=$1 out=$2 nx=$3 ny=$4 threads=${5:-2}
shift $(( $# > 5 ? 5 : $# ))
mkdir -p "$out"
for plate in steel sandwich; do
    dir=$out/${plate}_$nx
    /usr/bin/time -v -o "$dir.time" "$build/bin/undex" run "cases/undex_${plate}_plate.case" \
        --set domain.cells_x="$nx" --set domain.cells_y="$ny" --set numerics.threads="$threads" \
        --set structure.threads=1 -o "$dir" --force "$@" > "$dir.out" 2>&1
    wall=$(sed -n 's/.*Elapsed (wall clock) time (h:mm:ss or m:ss): //p' "$dir.time")
    rss=$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$dir.time")
    fluid=$(sed -n 's/.*undex-fluid: done: \([0-9]*\) steps, wall \([0-9.]*\) s (coupling \([0-9.]*\) s, [0-9.]* %; wet faces \([0-9.]*\) s.*/\1 steps, fluid \2 s (coupling \3 s, wet faces \4 s)/p' "$dir/fluid.log")
    solid=$(sed -n 's/.*undex-solid: done: .*(structure steps \([0-9.]*\) s.*/structure steps \1 s/p' "$dir/solid.log")
    echo "$plate, fluid cells $nx x $ny, $threads fluid thread(s): wall $wall, peak memory $((rss / 1024)) MiB; $fluid; $solid"
done
