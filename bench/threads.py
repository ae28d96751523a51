#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Thread scaling and determinism: meshes every case of a bench/compare.py run with 1 and with N
threads, alternately, --repeat times each, and compares the fastest seconds (the report's total)
and the written MSH files byte for byte (with each other and with the run's own MSH).

usage: bench/threads.py RESULTS.json RUN_DIR [--threads 2] [--repeat 3] [--out DIR] [--paramesh EXE]
RESULTS.json / RUN_DIR: results.json of a bench/compare.py run (e.g. a --no-check timing run) and
the directory holding its MSH files (MODEL_DIV.paramesh.msh); its cases and sizes are used.
"""
import argparse, filecmp, json, os

from compare import MODELS, ROOT, run_ours  # bench/ is on sys.path when run as bench/threads.py


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('results')
    ap.add_argument('run_dir')
    ap.add_argument('--threads', type=int, default=2)
    ap.add_argument('--repeat', type=int, default=3)
    ap.add_argument('--out', default=os.path.join(ROOT, 'out', 'bench_threads'))
    ap.add_argument('--paramesh', default=os.path.join(ROOT, 'build', 'bin', 'paramesh'))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    tot1 = totn = 0.0
    ratios, diff = [], []
    print(f"| model | h | 1 thread s | {a.threads} threads s | speed-up | same mesh |")
    print("|---|---|---|---|---|---|")
    for r in json.load(open(a.results)):
        tag = f"{r['model']}_{r['div']}"
        best = {}
        for _ in range(a.repeat):
            for n in (1, a.threads):
                out, rep = os.path.join(a.out, f'{tag}_{n}.msh'), os.path.join(a.out, f'{tag}_{n}.json')
                o = run_ours(os.path.join(MODELS, r['model']), r['h'], out, rep, n, [], a.paramesh)
                if o['exit'] != 0:
                    raise SystemExit(f"{tag}, {n} threads: exit {o['exit']}: {o['stderr']}")
                best[n] = min(best.get(n, 1e300), o['mesh_s'])
        s1, sn = best[1], best[a.threads]
        ref = os.path.join(a.run_dir, tag + '.paramesh.msh')
        same = all(filecmp.cmp(os.path.join(a.out, f'{tag}_{n}.msh'), ref, shallow=False) for n in (1, a.threads))
        tot1 += s1
        totn += sn
        ratios.append(s1 / sn)
        if not same:
            diff.append(tag)
        print(f"| {r['model']} | d/{r['div']} | {s1:.3f} | {sn:.3f} | {s1 / sn:.2f}× | {'yes' if same else 'NO'} |")
    ratios.sort()
    print(f"\n- summed: {tot1:.2f} s -> {totn:.2f} s ({tot1 / totn:.2f}×); per case {ratios[0]:.2f}× to "
          f"{ratios[-1]:.2f}× (median {ratios[len(ratios) // 2]:.2f}×)")
    print(f"- meshes identical to the 1-thread run: {len(ratios) - len(diff)} of {len(ratios)} {diff}")


if __name__ == '__main__':
    main()
