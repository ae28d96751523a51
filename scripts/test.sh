#!/usr/bin/env bash
# Fresh Debian 12: install the packages, build, and run every test tier.
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/install-deps.sh
bash scripts/build.sh
(cd build && ctest --output-on-failure -j"$(nproc)")
echo "all tests passed"
