#!/usr/bin/env bash
# Installs texsim's build and test dependencies from Debian packages (run as root or with sudo).
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update
$SUDO apt-get install -y --no-install-recommends \
  build-essential cmake pkg-config git \
  libglm-dev libopenimageio-dev openimageio-tools libpng-dev libhidapi-dev \
  ccache lld libcli11-dev libtomlplusplus-dev libtinyobjloader-dev libassimp-dev libsqlite3-dev libmpfr-dev zlib1g-dev libisal-dev nettle-dev libhwy-dev nlohmann-json3-dev \
  libgtest-dev libgmock-dev googletest libbenchmark-dev \
  clang clang-format clang-tidy libclang-rt-14-dev verilator iverilog yosys nextpnr-ice40 fpga-icestorm gnuplot-nox parallel sqlite3 bc slurm-wlm munge \
  python3 libsquish-dev libnvtt-dev astcenc libastcenc-dev glmark2-data python-matplotlib-data \
  libegl-dev libgl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri \
  python3-dev pybind11-dev python3-pybind11 python3-numpy python3-matplotlib help2man dpkg-dev file
