#!/usr/bin/python3
"""Wall time of two ParaMesh builds on the benchmark's 30 default cases (every shared model at
h = diagonal / 100 and / 200, one thread), run in turn (old, new, old, new, ...) so that the
machine's drift falls on both; prints each pass's totals and the median ratio new / old.

usage: tests/tools/time_builds.py --old OLD/paramesh --new NEW/paramesh [--runs 5] [--threads 1]
"""
import argparse, os, statistics, subprocess, sys, tempfile, time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import compare_builds as cb  # the same case list


def total(exe, cases, threads, out):
    t0 = time.monotonic()
    for name, model, h, extra in cases:
        subprocess.run([exe, 'mesh', model, '-o', out, '--size', repr(h), '--threads', str(threads), '--quiet'] + extra,
                       check=True, capture_output=True)
    return time.monotonic() - t0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--old', required=True)
    ap.add_argument('--new', required=True)
    ap.add_argument('--runs', type=int, default=5)
    ap.add_argument('--threads', type=int, default=1)
    a = ap.parse_args()
    models = sorted(f for f in os.listdir(cb.MODELS) if f.lower().endswith(('.step', '.stp', '.brep', '.iges', '.igs')))
    cases = cb.cases(a.old, ['default'], models)
    out = os.path.join(tempfile.mkdtemp(prefix='paramesh_time_'), 'm.msh')
    total(a.new, cases, a.threads, out)  # warm-up (file cache)
    ratios = []
    for r in range(a.runs):
        told = total(a.old, cases, a.threads, out)
        tnew = total(a.new, cases, a.threads, out)
        ratios.append(tnew / told)
        print('pass %d: old %.2f s, new %.2f s, new/old %.4f' % (r + 1, told, tnew, ratios[-1]), flush=True)
    print('%d cases, %d passes: median new/old %.4f (min %.4f, max %.4f)' %
          (len(cases), a.runs, statistics.median(ratios), min(ratios), max(ratios)))


if __name__ == '__main__':
    main()
