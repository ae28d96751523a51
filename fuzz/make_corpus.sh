#!/usr/bin/env bash
# Seed corpora of the libFuzzer harnesses: make_corpus.sh BUILD_DIR OUT_DIR
#   OUT_DIR/step, iges, brep: OpenCASCADE primitives and up to 6 single faces of each real model
#     (fuzz_make_seeds), plus the real models of tests/data and ../shared/models themselves when
#     they fit the harness's -max_len (fuzz.sh: 256 kB; the IGES models are 1.2 and 3.4 MB)
#   OUT_DIR/stl: fuzz/seeds/stl/*.stl (small binary and ASCII STLs)
#   OUT_DIR/params_json: fuzz/seeds/params/*.json and examples/*.json
#   OUT_DIR/geometry: 32 fixed pseudo-random byte strings (Python's random, seed 1)
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
BUILD="$1"
OUT="$2"
MAXLEN="${PARAMESH_FUZZ_MAX_LEN:-262144}"
# models larger than this give no single-face seeds (reading them under ASan costs 10-40 s; CI sets
# 1 MB: their faces' kinds are among the other models' faces, written in all three formats)
FACE_MAX="${PARAMESH_FUZZ_FACE_MODEL_MAX:-100000000}"
rm -rf "$OUT"
mkdir -p "$OUT"/{step,iges,brep,stl,params_json,geometry}
models=()
for d in "$ROOT/tests/data" "$ROOT/../shared/models"; do
  [ -d "$d" ] || continue
  for f in "$d"/*.step "$d"/*.stp "$d"/*.iges "$d"/*.igs "$d"/*.brep; do
    [ -f "$f" ] || continue
    b="$(basename "$f")"
    # tests/data holds copies of ../shared/models: each model once
    for m in "${models[@]:-}"; do [ "$(basename "$m")" = "$b" ] && continue 2; done
    models+=("$f")
  done
done
small=()
for f in "${models[@]}"; do if [ "$(stat -c %s "$f")" -le "$FACE_MAX" ]; then small+=("$f"); fi; done
"$BUILD/bin/fuzz_make_seeds" "$OUT" "${small[@]}" >/dev/null
for f in "${models[@]}"; do
  [ "$(stat -c %s "$f")" -le "$MAXLEN" ] || continue
  case "${f,,}" in
    *.step|*.stp) cp "$f" "$OUT/step/";;
    *.iges|*.igs) cp "$f" "$OUT/iges/";;
    *.brep) cp "$f" "$OUT/brep/";;
  esac
done
cp "$ROOT"/fuzz/seeds/params/*.json "$ROOT"/examples/*.json "$OUT/params_json/"
cp "$ROOT"/fuzz/seeds/stl/*.stl "$OUT/stl/"
/usr/bin/python3 - "$OUT/geometry" <<'PY'
import os, random, sys
rng = random.Random(1)
for i in range(32):
    n = rng.choice([16, 32, 64, 128, 256])
    open(os.path.join(sys.argv[1], 'g%02d' % i), 'wb').write(bytes(rng.randrange(256) for _ in range(n)))
PY
for d in step iges brep stl params_json geometry; do
  printf '%s: %s files, %s bytes\n' "$d" "$(ls "$OUT/$d" | wc -l)" "$(du -sb "$OUT/$d" | cut -f1)"
done
