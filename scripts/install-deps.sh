#!/bin/bash
# Installs what is missing of the Debian packages the project builds and runs with.
set -euo pipefail
packages=(cmake g++ make pkg-config libzmq3-dev cppzmq-dev libhdf5-dev libprotobuf-dev
          protobuf-compiler libgtest-dev python3 python3-numpy python3-h5py python3-matplotlib
          python3-zmq python3-protobuf libcli11-dev clang-14 libfuzzer-14-dev libomp-14-dev
          openmpi-bin libopenmpi-dev)
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
    echo "installing: ${missing[*]}"
    sudo=""
    [ "$(id -u)" -ne 0 ] && sudo=sudo
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}"
fi
