#!/bin/bash
# The main job: install what is missing, build (Release), run the paper's case 4.2 and plot it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
build/bin/undex run cases/cavitation_tube_1d.case
/usr/bin/python3 cases/plot_profiles.py out/cavitation_tube_1d --output out/cavitation_tube_1d/profiles.png
echo "results: out/cavitation_tube_1d/fluid.h5 (ParaView: fluid.xmf), plot: out/cavitation_tube_1d/profiles.png"
