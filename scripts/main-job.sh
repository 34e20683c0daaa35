#!/bin/bash
# The main job: install what is missing, build (Release), run the paper's case 4.3 (a plane shock in water on
# a sandwich plate: the fluid and the structure as two processes coupled over ZeroMQ) and plot it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
build/bin/undex run cases/sandwich_shock_1d.case
/usr/bin/python3 cases/plot_sandwich_shock.py out/sandwich_shock_1d
echo "results: out/sandwich_shock_1d/fluid.h5 and solid.h5 (logs fluid.log, solid.log), plot: out/sandwich_shock_1d/sandwich_shock.png"
