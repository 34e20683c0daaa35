# The run of the PID benches (pid.sh, pid_alternate.sh), sourced by them: cases/riemann_2d.case at n × n
# cells to t_end, degree 2, pinned to the WENO limiter on the cells the TVB indicator marks, every cell
# solved (skip_rest off), so that the figure stays comparable whatever the case file's defaults.
# Uses the caller's build, n, t_end, out (a scratch directory) and pin (true: taskset to CPUS).

# one_run THREADS CPUS TAG: prints "STEPS WALL"
one_run() {
    local cmd=("$build/bin/undex-fluid" cases/riemann_2d.case --set domain.cells_x="$n" --set domain.cells_y="$n"
               --set end_time="$t_end" --set output.times[0]="$t_end" --set numerics.threads="$1"
               --set output.directory="$out/run$3" --set output.progress_seconds=1000
               --set numerics.limiter=weno --set numerics.indicator=tvb --set numerics.skip_rest=false)
    if $pin; then cmd=(taskset -c "$2" "${cmd[@]}"); fi
    "${cmd[@]}" | sed -n 's/.*done: \([0-9]*\) steps, wall \([0-9.]*\) s.*/\1 \2/p'
}
median() { sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
