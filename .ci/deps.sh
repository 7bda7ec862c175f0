#!/usr/bin/env bash
# Installs everything multicage needs to build, test and run, from Debian bookworm's archive.
# Run as root (or with sudo available). Safe to run again: apt skips what is installed.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends \
    ca-certificates cmake ninja-build g++ pkg-config \
    libopencv-dev libopencv-contrib-dev opencv-data \
    libglm-dev libepoxy-dev libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri \
    libeigen3-dev libcli11-dev \
    libgif-dev \
    libgtest-dev libgmock-dev libbenchmark-dev \
    python3-dev pybind11-dev python3-numpy python3-opencv python3-pytest \
    python3-dask python3-distributed \
    python3-torch python3-torchvision \
    libglfw3-dev libimgui-dev xvfb xauth \
    > /dev/null
echo "deps.sh: build and test dependencies installed"
