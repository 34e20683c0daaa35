#!/bin/bash
# Fuzzes each libFuzzer harness of tests/fuzz for a given time, all at once (one per core):
#   fuzz_case      arbitrary text as a case file, through the loader and every check of `undex check`
#   fuzz_coupling  arbitrary bytes as a coupling message, through the decoder and the checks of both sides
# under AddressSanitizer and UndefinedBehaviorSanitizer, with leak detection, a 10 s limit per input and
# 2 GiB of memory. Builds them first (clang-14, libfuzzer-14-dev) in BUILD_DIR.
# Usage (from the source directory): tests/bench/fuzz.sh [SECONDS] [BUILD_DIR]   (default 600 s, build-fuzz)
# Exits with status 1 when any harness finds something; findings are in BUILD_DIR/bin/fuzz-artifacts.
set -euo pipefail
seconds=${1:-600}
build=${2:-build-fuzz}
CC=clang-14 CXX=clang++-14 cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DUNDEX_FUZZ=ON \
    -DUNDEX_FUZZ_SECONDS="$seconds" > /dev/null
targets=$(sed -n 's/^undex_fuzzer(\(fuzz_[a-z_]*\) .*/\1/p' tests/fuzz/CMakeLists.txt)
cmake --build "$build" -j"$(nproc)" --target $targets
cd "$build" && ctest -L fuzz -j"$(nproc)" --output-on-failure
