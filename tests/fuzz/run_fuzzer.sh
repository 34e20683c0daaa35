#!/bin/bash
# Runs one libFuzzer harness for a given time from its seed corpora.
#   run_fuzzer.sh FUZZER SECONDS DICT SEED_DIR...
# New inputs go to a work corpus next to the fuzzer (corpus-NAME/, kept between runs), findings to
# fuzz-artifacts/NAME-*; the log to NAME.log there. Exits non-zero on any finding: a crash, a sanitizer
# report, a leak, an uncaught exception, an input over 10 s (-timeout) or over 2 GiB (-rss_limit_mb).
set -euo pipefail
fuzzer=$1 seconds=$2 dict=$3
shift 3
dir=$(dirname "$fuzzer")
name=$(basename "$fuzzer")
mkdir -p "$dir/corpus-$name" "$dir/fuzz-artifacts"
options=(-max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1
         -artifact_prefix="$dir/fuzz-artifacts/$name-")
[ -n "$dict" ] && options+=(-dict="$dict")
status=0
ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=0 UBSAN_OPTIONS=print_stacktrace=1 \
    "$fuzzer" "${options[@]}" "$dir/corpus-$name" "$@" > "$dir/$name.log" 2>&1 || status=$?
grep -E '^(#[0-9]+ +DONE|stat::number_of_executed_units|stat::peak_rss_mb|Done )' "$dir/$name.log" || true
if [ "$status" -ne 0 ]; then
    echo "$name: FINDING (exit $status); the end of $dir/$name.log:"
    tail -40 "$dir/$name.log"
    ls "$dir/fuzz-artifacts" | grep "^$name-" || true
    exit 1
fi
echo "$name: no finding in $seconds s"
