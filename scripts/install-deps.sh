#!/usr/bin/env bash
# Installs the Debian 12 packages bakesim needs to build, test and run.
# Idempotent: does nothing (and prints nothing) when every package is present.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev          # linear algebra
  nlohmann-json3-dev     # scene files
  libcli11-dev           # command line
  libtbb-dev             # parallel loops
  libspdlog-dev libfmt-dev  # logging, formatting
  libnanoflann-dev       # kd-tree neighbour search
  libtinyobjloader-dev   # OBJ meshes
  libqhull-dev           # convex hulls (surface particle detection)
  libgtest-dev libgmock-dev libbenchmark-dev  # tests and benchmarks
  libopenvdb-dev libboost-dev  # level sets and meshing (OpenVDB's headers need Boost's)
  libembree-dev          # ray casting for pictures
  libstb-dev             # PNG writing, TrueType text for plots and colour bars
  fonts-dejavu-core      # the font plots and colour bars are labelled with
  ffmpeg                 # bakesim render --movie
  libopenvdb-tools       # vdb_print: the test that .vdb frames open in OpenVDB's own tools (tests only)
  chromium               # headless browser: the test of bakesim report loads the page in it (tests only)
  pybind11-dev python3-dev python3-numpy  # the Python module (python/)
  python3-scipy python3-distributed       # its examples (calibration) and sweeps on Dask
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq >/dev/null
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
