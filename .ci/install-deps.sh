#!/usr/bin/env bash
# Installs every Debian 12 package ParaMesh needs to build, test, benchmark and run in FreeCAD.
# (clang, libclang-rt-14-dev: libFuzzer and clang's sanitizer runtimes for fuzz/; llvm: the
# llvm-symbolizer that puts file:line into sanitizer reports; openfoam: surfaceCheck reads the
# named multi-solid STL in tests/python/test_groups.py; python3-dolfinx: its Poisson check of our
# volume MSH; tmux: the progress-line capture.)
# Run as root (or with sudo). Idempotent.
set -euo pipefail
SUDO=""
if [ "$(id -u)" != "0" ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
PKGS=(
  build-essential cmake ninja-build pkg-config
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev
  libocct-data-exchange-dev libocct-ocaf-dev libocct-visualization-dev libtbb-dev
  libeigen3-dev pybind11-dev python3-pybind11 python3-dev
  libgtest-dev
  libnglib-dev netgen
  python3-numpy python3-pytest python3-meshio python3-matplotlib
  freecad-python3 freecad
  gmsh python3-gmsh
  calculix-ccx
  xvfb xauth
  clang libclang-rt-14-dev llvm
  openfoam tmux python3-dolfinx
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
