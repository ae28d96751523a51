#!/usr/bin/python3
"""Byte-for-byte comparison of two ParaMesh builds on the shared models (refactorings must not
change a single output byte).

usage: tests/tools/compare_builds.py --old OLD/paramesh --new NEW/paramesh [--out DIR] [--jobs N]
                                     [--sets default,curvature,deviation,quads,order2,layers]
                                     [--models a.step,b.brep]

Runs every case with both executables and compares the MSH files with `cmp`, and the run reports
with their timings removed (every "seconds" entry). Cases (h = bounding-box diagonal / div, the
diagonal as `paramesh info` prints it):
  default    every model at h = d/100 and d/200
  curvature  the same with --curvature-angle 10
  deviation  every model at d/50 with --max-deviation 0.001
  quads      every model at d/100 with --quads
  order2     every model at d/100 with --order 2
  layers     the boundary-layer cases of tests/python/test_boundary_layer*.py (CLI form)
Prints one line per differing case and a summary; exits 1 when any case differs.
"""
import argparse, json, os, re, subprocess, sys
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MODELS = os.path.abspath(os.path.join(ROOT, '..', 'shared', 'models'))
if not os.path.isdir(MODELS):
    MODELS = os.path.join(ROOT, 'tests', 'data')

# (name, model, size, extra CLI arguments): the layers of tests/python/test_boundary_layer*.py
LAYER_CASES = [
    ('m6_le', 'AileM6_with_sharp_TE.stp', 16.75, '--bl-edges 21 --bl-first-height 0.5 --bl-growth 1.2 --bl-layers 20'),
    ('m6_tip', 'AileM6_with_sharp_TE.stp', 16.75, '--bl-edges 21,6 --bl-first-height 0.5 --bl-growth 1.2 --bl-layers 20'),
    ('wing', 'wing.brep', 0.0503, '--bl-edges 3,5,11,13 --bl-first-height 0.001 --bl-growth 1.2 --bl-layers 20'),
    ('propeller', 'Propeller.brep', 6.7934, '--bl-edges 64,68,72,76 --bl-first-height 0.15 --bl-growth 1.2 --bl-layers 20'),
    ('ps_blade', 'propeller_and_shaft.iges', 1904.9886655946982 / 200,
     '--nearest-face-budget 0 --bl-edges 42 --bl-first-height 0.2 --bl-growth 1.2 --bl-layers 10'),
    ('nist_326', 'nist_ctc_01.brep', 18.60107524375957, '--bl-edges 326 --bl-first-height 0.62 --bl-growth 1.2 --bl-layers 8'),
    ('bottle_89', 'bottle.brep', 1.8979771361014846,
     '--bl-edges 89 --bl-first-height %r --bl-growth 1.2 --bl-layers 10' % (1.8979771361014846 / 20)),
    ('m6_15', 'AileM6_with_sharp_TE.stp', 33.500098860449405,
     '--bl-edges 15 --bl-first-height %r --bl-growth 1.2 --bl-layers 10' % (33.500098860449405 / 20)),
    ('screw_12', 'screw.step', 2.0620488559318572,
     '--bl-edges 12 --bl-first-height %r --bl-growth 1.2 --bl-layers 10' % (2.0620488559318572 / 20)),
    ('screw_12_tri', 'screw.step', 2.0620488559318572,
     '--bl-edges 12 --bl-first-height %r --bl-growth 1.2 --bl-layers 6 --bl-triangles' % (2.0620488559318572 / 60)),
    ('crankarm', 'CrankArm.brep', 1.7449074614308635,
     '--bl-edges 28,42,53,58,77,114,115,124 --bl-first-height 0.3577962419905549 --bl-growth 1.2 --bl-layers 4'),
    ('m6_auto', 'AileM6_with_sharp_TE.stp', 16.75, '--bl-auto'),
]


def diagonal(exe, model):
    out = subprocess.run([exe, 'info', model], capture_output=True, text=True).stdout
    return float(re.search(r'diagonal ([0-9.eE+-]+)', out).group(1))


def cases(exe, sets, models):
    out = []
    for m in models:
        path = os.path.join(MODELS, m)
        d = diagonal(exe, path)
        stem = os.path.splitext(m)[0]
        if 'default' in sets:
            out += [('%s_d%d' % (stem, k), path, d / k, []) for k in (100, 200)]
        if 'curvature' in sets:
            out += [('%s_d%d_curv10' % (stem, k), path, d / k, ['--curvature-angle', '10']) for k in (100, 200)]
        if 'deviation' in sets:
            out.append(('%s_d50_dev001' % stem, path, d / 50, ['--max-deviation', '0.001']))
        if 'quads' in sets:
            out.append(('%s_d100_quads' % stem, path, d / 100, ['--quads']))
        if 'order2' in sets:
            out.append(('%s_d100_order2' % stem, path, d / 100, ['--order', '2']))
    if 'layers' in sets:
        for name, m, h, extra in LAYER_CASES:
            if m in models:
                out.append(('bl_' + name, os.path.join(MODELS, m), h, extra.split()))
    return out


def strip_seconds(x):
    if isinstance(x, dict):
        return {k: strip_seconds(v) for k, v in x.items() if 'seconds' not in k}
    if isinstance(x, list):
        return [strip_seconds(v) for v in x]
    return x


def run(exe, case, outdir):
    name, model, h, extra = case
    msh, rep = os.path.join(outdir, name + '.msh'), os.path.join(outdir, name + '.json')
    p = subprocess.run([exe, 'mesh', model, '-o', msh, '--report', rep, '--size', repr(h), '--quiet'] + extra,
                       capture_output=True, text=True)
    return p.returncode, (p.stderr or '').strip()[-200:], msh, rep


def compare(case, a, b):
    (ra, ea, ma, ja), (rb, eb, mb, jb) = a, b
    if ra != rb or ea != eb:
        return 'exit %d / %d (%s | %s)' % (ra, rb, ea, eb)
    if ra != 0:
        return None  # refused alike
    if subprocess.run(['cmp', '-s', ma, mb]).returncode != 0:
        return 'MSH differs'
    with open(ja) as f, open(jb) as g:
        if strip_seconds(json.load(f)) != strip_seconds(json.load(g)):
            return 'report differs'
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--old', required=True)
    ap.add_argument('--new', required=True)
    ap.add_argument('--out', default='/tmp/compare_builds')
    ap.add_argument('--jobs', type=int, default=os.cpu_count() or 1)
    ap.add_argument('--sets', default='default,curvature,deviation,quads,order2,layers')
    ap.add_argument('--models', default='')
    a = ap.parse_args()
    models = a.models.split(',') if a.models else sorted(
        f for f in os.listdir(MODELS) if f.lower().endswith(('.step', '.stp', '.iges', '.igs', '.brep')))
    todo = cases(a.old, set(a.sets.split(',')), models)
    dirs = {k: os.path.join(a.out, k) for k in ('old', 'new')}
    for d in dirs.values():
        os.makedirs(d, exist_ok=True)

    def one(case):
        return case, compare(case, run(a.old, case, dirs['old']), run(a.new, case, dirs['new']))

    bad = 0
    with ThreadPoolExecutor(a.jobs) as pool:
        for case, why in pool.map(one, todo):
            if why:
                bad += 1
                print('DIFF %-32s %s' % (case[0], why), flush=True)
    print('%d of %d cases byte-identical (%s)' % (len(todo) - bad, len(todo), a.sets))
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
