#!/usr/bin/env bash
# Fresh Debian 12: install the packages, build, and run every test tier.
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/install-deps.sh
bash scripts/build.sh
(cd build && ctest --output-on-failure -j"$(nproc)")
# Python API (no FreeCAD) and FreeCAD App bridge (no GUI), with Debian's interpreter
/usr/bin/python3 -m pytest -q tests/python tests/freecad
# The workbench in a real FreeCAD window under Xvfb (screenshots and summary in out/gui)
bash tests/gui/run.sh
# ASan + UBSan build (build-asan/, clang++): C++ tests, seeded parameter sweep and input fuzz of the CLI
bash scripts/sanitize.sh
# libFuzzer harnesses (the same build-asan/): regressions replayed, then a short run of each (docs/fuzzing.md)
bash scripts/fuzz.sh ci
echo "all tests passed"
