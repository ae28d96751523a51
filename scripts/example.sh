#!/usr/bin/env bash
# Fresh Debian 12: install the packages, build, and mesh the bundled ONERA M6 wing.
# Writes out/m6.msh (Gmsh 4.1), out/m6.vtu, out/m6.json (report) and out/m6.png (picture).
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/install-deps.sh
bash scripts/build.sh
mkdir -p out
MODEL=tests/data/AileM6_with_sharp_TE.stp
build/bin/paramesh mesh "$MODEL" --size 16.75 --threads 0 \
  -o out/m6.msh -o out/m6.vtu --report out/m6.json --png out/m6.png --view 30,40
echo "wrote out/m6.msh out/m6.vtu out/m6.json out/m6.png"
