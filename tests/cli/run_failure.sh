#!/bin/bash
# `undex run` on a case driven into failure (limiter and positivity off on a strong shock): exit status 2,
# a message naming cell, time and step, and the output file kept readable with the last good state.
set -u
undex=$1
cases=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
pass=0 fail=0
check() { if eval "$2"; then echo "ok: $1"; pass=$((pass + 1)); else echo "FAIL: $1"; fail=$((fail + 1)); fi; }

"$undex" run "$cases/sod_1d.case" --set numerics.indicator=none --set numerics.positivity=false \
    --set regions[1].p=1e-6 --set regions[1].rho=1e-3 --set output.directory="$dir/out" >"$dir/log" 2>&1
status=$?
cat "$dir/log"
check "exit status 2 (got $status)" '[ $status -eq 2 ]'
check "message names the cell, time and step" 'grep -q "in cell (.*t = .*in step " "$dir/log"'
check "output file kept" '[ -f "$dir/out/fluid.h5" ]'
check "status says failed" \
    '/usr/bin/python3 -c "import h5py,sys; f=h5py.File(\"$dir/out/fluid.h5\",\"r\"); sys.exit(0 if f[\"status\"][()].decode().startswith(\"failed\") else 1)"'
check "last good state is finite" \
    '/usr/bin/python3 -c "import h5py,sys,numpy as np; f=h5py.File(\"$dir/out/fluid.h5\",\"r\"); g=f[\"fields\"][sorted(f[\"fields\"])[-1]]; sys.exit(0 if g.attrs[\"last_good\"]==1 and np.isfinite(g[\"p\"][:]).all() else 1)"'
# `undex sample` reads the same file.
"$undex" sample "$dir/out" --time 0 --line "0.1,0 0.9,0" --points 5 --fields rho,p >"$dir/sample" 2>&1
check "sample prints a header and 5 rows" '[ "$(grep -c "^x,y,rho,p$" "$dir/sample")" = 1 ] && [ "$(grep -vc "^[#x]" "$dir/sample")" = 5 ]'
# numerics.max_steps ends any solver's run the same way (the run driver, base/run_driver.cpp): exit status 2,
# the limit named, the last good state written at exactly that step, for the fluid and for a structure.
for spec in "sod_1d fluid.h5" "sandwich_column_1d solid.h5"; do
    read -r name file <<<"$spec"
    "$undex" run "$cases/$name.case" --set numerics.max_steps=7 -o "$dir/steps_$name" >"$dir/log_$name" 2>&1
    status=$?
    check "$name: max_steps gives exit status 2 (got $status)" '[ $status -eq 2 ]'
    check "$name: the message names numerics.max_steps" 'grep -q "numerics.max_steps = 7 reached" "$dir/log_$name"'
    check "$name: the last good state is step 7, status failed" \
        '/usr/bin/python3 -c "import h5py,sys; f=h5py.File(\"$dir/steps_$name/$file\",\"r\"); g=f[\"fields\"][sorted(f[\"fields\"])[-1]]; sys.exit(0 if g.attrs[\"last_good\"]==1 and g.attrs[\"step\"]==7 and f[\"status\"][()].decode().startswith(\"failed: stopped: numerics.max_steps\") else 1)"'
done
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
