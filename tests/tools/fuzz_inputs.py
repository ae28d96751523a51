#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Mutation fuzzing of the CLI's CAD readers and mesher: corrupt copies of real CAD files.

usage: fuzz_inputs.py PARAMESH MODEL [MODEL...] [--cases N] [--seed S] [--timeout SEC] [--out DIR]
                      [--args "--size 5 ..."]
       fuzz_inputs.py python MODEL [MODEL...] ...

With `python` in place of the CLI, each case goes through the Python API instead
(`freecad.paramesh.mesh_file` in a /usr/bin/python3 process of its own, which, unlike the CLI,
has no signal handler to turn a reader crash into an error): a ParaMeshError is a one-line
reason (exit 2), a result is written as MSH (exit 0), anything else is a failure.

Each case is a copy of a model with one mutation: truncated at a random byte, a random line
deleted or duplicated, two lines swapped, a random number replaced (by another, 0, a huge
value, -1, nan) or a run of random bytes written over it. `PARAMESH mesh CASE -o out.msh` then
runs with a time limit. Every outcome must be one of: exit 0 with a mesh (checked: every
triangle edge used at most twice, no unused or coincident-index node, finite coordinates), or
an exit code 1-5 with a one-line reason on stderr. A signal (crash), a sanitizer report, a
time-out or a reason that is not one line is a failure, and the case is kept in DIR.
Prints JSON: counts per outcome and the failures. Exit status 1 when any failed.
"""
import argparse
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np

NUM = re.compile(rb'[-+]?\d+\.?\d*(?:[eE][-+]?\d+)?')


def mutate(data, rng):
    kind = rng.choice(['truncate', 'delete_line', 'dup_line', 'swap_lines', 'number', 'bytes'])
    if kind == 'truncate':
        return kind, data[:rng.randrange(len(data))]
    lines = data.split(b'\n')
    if kind in ('delete_line', 'dup_line', 'swap_lines') and len(lines) > 2:
        i = rng.randrange(len(lines))
        if kind == 'delete_line':
            del lines[i]
        elif kind == 'dup_line':
            lines.insert(i, lines[i])
        else:
            j = rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
        return kind, b'\n'.join(lines)
    if kind == 'number':
        nums = list(NUM.finditer(data))
        if nums:
            m = nums[rng.randrange(len(nums))]
            new = rng.choice([b'0', b'-1', b'1e300', b'nan', b'1e-300', b'7',
                              str(rng.uniform(-1e3, 1e3)).encode()])
            return kind, data[:m.start()] + new + data[m.end():]
    n = rng.randint(1, 16)
    i = rng.randrange(max(1, len(data) - n))
    return 'bytes', data[:i] + bytes(rng.randrange(256) for _ in range(n)) + data[i + n:]


def check_mesh(path):
    """'' when the MSH is sane, else what is wrong."""
    try:
        import meshio
        m = meshio.read(path)
    except Exception as e:  # noqa: BLE001 - any reader failure is a finding
        return 'unreadable mesh: %s' % e
    P = np.asarray(m.points, float)
    if not np.isfinite(P).all():
        return 'non-finite coordinates'
    # corner nodes of the triangles and quads (of either order: mid-edge nodes follow the corners)
    tris = [c.data[:, :3] for c in m.cells if c.type.startswith('triangle')]
    quads = [c.data[:, :4] for c in m.cells if c.type.startswith('quad')]
    if not tris and not quads:
        return ''
    edges = []
    if tris:
        T = np.concatenate(tris)
        if (T[:, 0] == T[:, 1]).any() or (T[:, 1] == T[:, 2]).any() or (T[:, 0] == T[:, 2]).any():
            return 'triangle with a repeated node'
        edges += [T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]
    if quads:
        Q = np.concatenate(quads)
        edges += [Q[:, [0, 1]], Q[:, [1, 2]], Q[:, [2, 3]], Q[:, [3, 0]]]
    e = np.sort(np.concatenate(edges), axis=1)
    _, cnt = np.unique(e, axis=0, return_counts=True)
    if cnt.max() > 2:
        return 'non-manifold edge (used %d times)' % cnt.max()
    used = np.zeros(len(P), bool)
    for c in m.cells:
        used[c.data.ravel()] = True
    if not used.all():
        return '%d unused nodes' % int((~used).sum())
    return ''


ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PY_DRIVER = """
import sys
import freecad.paramesh as pm
try:
    r = pm.mesh_file(sys.argv[1])
except pm.ParaMeshError as e:
    sys.stderr.write(str(e).replace(chr(10), ' ') + chr(10))
    sys.exit(2)
r.write(sys.argv[2])
"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('paramesh')
    ap.add_argument('models', nargs='+')
    ap.add_argument('--cases', type=int, default=50)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--timeout', type=float, default=120)
    ap.add_argument('--out', default='fuzz_failures')
    ap.add_argument('--args', default='')
    a = ap.parse_args()
    rng = random.Random(a.seed)
    counts = {}
    failures = []
    work = tempfile.mkdtemp(prefix='pmfuzz')
    env = dict(os.environ, ASAN_OPTIONS='detect_leaks=0:abort_on_error=0',
               UBSAN_OPTIONS='print_stacktrace=1:halt_on_error=1', PYTHONPATH=ROOT)
    for k in range(a.cases):
        model = a.models[k % len(a.models)]
        data = open(model, 'rb').read()
        kind, bad = mutate(data, rng)
        case = os.path.join(work, 'case%04d%s' % (k, os.path.splitext(model)[1]))
        open(case, 'wb').write(bad)
        out = os.path.join(work, 'out.msh')
        if os.path.exists(out):
            os.remove(out)
        if a.paramesh == 'python':
            cmd = ['/usr/bin/python3', '-c', PY_DRIVER, case, out]
        else:
            cmd = [a.paramesh, 'mesh', case, '-o', out, '--quiet'] + a.args.split()
        try:
            p = subprocess.run(cmd, capture_output=True, timeout=a.timeout, env=env)
            rc, err = p.returncode, p.stderr.decode(errors='replace')
        except subprocess.TimeoutExpired:
            rc, err = 'timeout', ''
        why = ''
        if rc == 'timeout':
            why = 'time-out after %g s' % a.timeout
        elif rc < 0 or rc > 5:
            why = 'signal or abnormal exit %s' % rc
        elif 'Sanitizer' in err or 'runtime error' in err:
            why = 'sanitizer report'
        elif rc == 0:
            why = check_mesh(out) if os.path.exists(out) else 'exit 0 without a mesh'
        else:
            lines = [l for l in err.strip().split('\n') if l.strip()]
            if len(lines) != 1:
                why = 'reason is %d lines' % len(lines)
        outcome = 'failure' if why else ('meshed' if rc == 0 else 'error %d' % rc)
        counts[outcome] = counts.get(outcome, 0) + 1
        if why:
            os.makedirs(a.out, exist_ok=True)
            keep = os.path.join(a.out, os.path.basename(case))
            shutil.copy(case, keep)
            failures.append({'case': keep, 'model': os.path.basename(model), 'mutation': kind,
                             'why': why, 'stderr': err[-2000:]})
    shutil.rmtree(work, ignore_errors=True)
    print(json.dumps({'cases': a.cases, 'outcomes': counts, 'failures': failures}, indent=1))
    sys.exit(1 if failures else 0)


if __name__ == '__main__':
    main()
