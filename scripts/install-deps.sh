#!/usr/bin/env bash
# Installs every Debian (bookworm) package scanmesh needs to build, test and benchmark.
# Run as root. Idempotent: packages already present are left alone.
set -euo pipefail

packages=(
  build-essential cmake pkg-config      # compiler and build system
  libeigen3-dev                         # dense linear algebra (3x3 vectors, small solves)
  libflann-dev liblz4-dev               # FLANN radius/kNN search on face centroids and points
  libpcl-dev                            # point-cloud I/O, filters, normals, meshing
  libvtk9-dev                           # ray casting for the virtual scanner (also a PCL dependency)
  libopencv-dev                         # rendering report figures to PNG
  libyaml-cpp-dev                       # YAML pipelines
  libboost-dev                          # PCL's public headers need Boost
  libboost-program-options-dev          # command-line parsing of the scanmesh tool
  libgtest-dev libgmock-dev             # unit tests
  libbenchmark-dev                      # micro-benchmarks
  libomp-dev                            # OpenMP runtime headers (GCC uses libgomp, shipped with g++)
  clang libclang-rt-14-dev              # libFuzzer and the clang sanitizer runtimes (scripts/fuzz.sh)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps: missing packages (${missing[*]}); run this script as root" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
