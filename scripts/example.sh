#!/usr/bin/env bash
# Fresh Debian 12: install the packages, build, and mesh the bundled ONERA M6 wing with a
# surface boundary layer on its leading edge (Edge21, continued over the tip by Edge6).
# Writes out/m6.msh (Gmsh 4.1), out/m6.vtu, out/m6.json (report), out/m6.png (the whole wing)
# and out/m6_leading_edge.png (a close-up of the layer).
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/install-deps.sh
bash scripts/build.sh
mkdir -p out
MODEL=tests/data/AileM6_with_sharp_TE.stp
build/bin/paramesh mesh "$MODEL" --params examples/m6_leading_edge.json \
  -o out/m6.msh -o out/m6.vtu --report out/m6.json --png out/m6.png --view 30,40
build/bin/paramesh mesh "$MODEL" --params examples/m6_leading_edge.json --quiet \
  --png out/m6_leading_edge.png --focus 250,400,-45,360,520,45 --view 200,15
echo "wrote out/m6.msh out/m6.vtu out/m6.json out/m6.png out/m6_leading_edge.png"
