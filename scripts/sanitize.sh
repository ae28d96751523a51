#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer tier of scripts/test.sh (docs/fuzzing.md):
# builds the library, the CLI, the C++ tests and the libFuzzer harnesses of fuzz/ with clang++
# -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all at -O1 into
# build-asan/ (no Python module; PARAMESH_FUZZ=ON, so that `PARAMESH_FUZZ_BUILD=build-asan
# scripts/fuzz.sh ci` needs no second sanitized build of the library), runs the C++ tests, then a
# seeded parameter sweep and a seeded input fuzz of the CLI (tests/tools). Any sanitizer report
# fails the step. Usage: scripts/sanitize.sh [cmake --build args]
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
cd "$ROOT"
BUILD="${PARAMESH_ASAN_BUILD:-$ROOT/build-asan}"
DATA="$ROOT/tests/data"
t0=$SECONDS

# Leak checking stays on, with OpenCASCADE's and TBB's static caches suppressed (fuzz/lsan.supp);
# halt_on_error: the first UBSan report ends the process with a non-zero status.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:detect_stack_use_after_return=0"
export LSAN_OPTIONS="suppressions=$ROOT/fuzz/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"

# configured as scripts/fuzz.sh configures it (clang++, ASan + UBSan, PARAMESH_FUZZ)
PARAMESH_FUZZ_BUILD="$BUILD" bash scripts/fuzz.sh configure
cmake --build "$BUILD" -j"$(nproc)" "$@"
echo "sanitize: build $((SECONDS - t0)) s"

# C++ tests. Under ASan a test costs 5-20x its release time; the five slowest (25-60 s each
# under ASan, together about 40 % of the suite's time) are left out here: they run in the
# release tier, and their code paths (large boundaries, thread flanks, stretched cells, every
# model's BREP text) are exercised by the faster tests, the sweep below and the fuzz harnesses.
SLOW='^(Curvature\.StretchedCellsSplitAcrossTheirLengthOnly|NarrowGaps\.BottleThreadFlanksGetGoodAngles|NarrowGaps\.M6TrailingEdgeStripsWithoutShortEdges|Triangulation\.LargeBoundariesInRandomisedOrderAreConstrainedDelaunay|InputChecks\.BrepPrecheckAcceptsEveryModelAsOpenCascadeWritesIt)$'
t1=$SECONDS
(cd "$BUILD" && ctest --output-on-failure -j"$(nproc)" --timeout 600 -E "$SLOW")
echo "sanitize: ctest $((SECONDS - t1)) s"

# The CLI under the tools' seeded random cases: a crash, a sanitizer report, a time-out or a
# garbled refusal fails them (they set ASAN_OPTIONS=detect_leaks=0 for the CLI themselves).
t1=$SECONDS
out="$(mktemp -d /tmp/paramesh-asan.XXXXXX)"
trap 'rm -rf "$out"' EXIT
/usr/bin/python3 tests/tools/param_sweep.py "$BUILD/bin/paramesh" "$DATA/screw.step" "$DATA/wing.brep" \
  "$DATA/occBSplCone.brep" --cases 10 --seed 11 --timeout 300 --out "$out/sweep" >"$out/sweep.json" ||
  { cat "$out/sweep.json"; echo "sanitize: param_sweep failed"; exit 1; }
echo "sanitize: param_sweep $((SECONDS - t1)) s: $(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["counts"])' "$out/sweep.json")"
t1=$SECONDS
/usr/bin/python3 tests/tools/fuzz_inputs.py "$BUILD/bin/paramesh" "$DATA/screw.step" "$DATA/wing.brep" \
  "$DATA/occBSplCone.brep" --cases 24 --seed 3 --timeout 300 --out "$out/fuzz" >"$out/fuzz.json" ||
  { cat "$out/fuzz.json"; echo "sanitize: fuzz_inputs failed"; exit 1; }
echo "sanitize: fuzz_inputs $((SECONDS - t1)) s: $(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["outcomes"])' "$out/fuzz.json")"
echo "sanitize: all steps passed in $((SECONDS - t0)) s"
