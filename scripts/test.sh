#!/bin/bash
# Builds (Release) and runs every test with CTest; then builds the libFuzzer harnesses (clang, ASan, UBSan) in
# build-fuzz and fuzzes each for 30 s from its seed corpus (tests/bench/fuzz.sh fuzzes longer).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
(cd build && ctest --output-on-failure -j"$(nproc)")
bash tests/bench/fuzz.sh 30 build-fuzz
