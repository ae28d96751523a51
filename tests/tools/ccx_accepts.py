#!/usr/bin/python3
"""Does CalculiX accept a ParaMesh shell mesh? Runs a minimal linear static analysis on it.

usage: ccx_accepts.py MESH.inp --fix FACE [--thickness T] [--g 9810] [--dir 0,0,-1] [--keep DIR]

MESH.inp: ParaMesh's Abaqus output (*NODE, *ELEMENT TYPE=S3/S6/S4/S8, one ELSET FaceN per CAD face).
Adds: steel (E = 210000 MPa, nu = 0.3, rho = 7.9e-9 t/mm^3), a *SHELL SECTION of thickness T on
every element, the nodes of the elements of ELSET FaceFIX clamped (dofs 1-6), gravity of g mm/s^2
along --dir, one *STATIC step; runs `ccx`, then requires: exit status 0, no '*ERROR' in its output,
a .dat with one finite displacement per node of the mesh, and a non-zero maximum displacement.
Prints one JSON line; exit status 1 on failure.
"""
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time


def parse_inp(path):
    """Node ids, element ids per type, and the elements of each ELSET (GENERATE or listed)."""
    nodes, elems, types, elsets, conn = [], [], {}, {}, {}
    mode, cur = None, None
    with open(path) as f:
        lines = f.read().splitlines()
    i = 0
    while i < len(lines):
        ln = lines[i].strip()
        i += 1
        if not ln or ln.startswith('**'):
            continue
        if ln.startswith('*'):
            kw = ln.upper()
            if kw.startswith('*NODE') and not kw.startswith('*NODE '):
                mode = 'node'
            elif kw.startswith('*ELEMENT'):
                mode = 'elem'
                cur = re.search(r'TYPE=(\w+)', kw).group(1)
            elif kw.startswith('*ELSET'):
                mode = 'elset'
                cur = re.search(r'ELSET=([\w-]+)', ln, re.I).group(1)
                elsets[cur] = []
                gen = 'GENERATE' in kw
                mode = 'elset_gen' if gen else 'elset'
            else:
                mode = None
            continue
        vals = [v for v in ln.split(',') if v.strip()]
        if mode == 'node':
            nodes.append(int(vals[0]))
        elif mode == 'elem':
            ids = [int(v) for v in vals]
            elems.append(ids[0])
            conn[ids[0]] = ids[1:]
            types[cur] = types.get(cur, 0) + 1
        elif mode == 'elset_gen':
            a, b, s = (int(v) for v in vals[:3])
            elsets[cur].extend(range(a, b + 1, s))
        elif mode == 'elset':
            elsets[cur].extend(int(v) for v in vals)
    return nodes, elems, types, elsets, conn


def id_lines(ids, per=16):
    ids = list(ids)
    return '\n'.join(', '.join(str(x) for x in ids[k:k + per]) for k in range(0, len(ids), per))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('mesh')
    ap.add_argument('--fix', type=int, required=True, help='CAD face number whose nodes are clamped')
    ap.add_argument('--thickness', type=float, default=1.0)
    ap.add_argument('--g', type=float, default=9810.0, help='gravity, mm/s^2')
    ap.add_argument('--dir', default='0,0,-1')
    ap.add_argument('--keep', default=None, help='work directory to keep (default: a temporary one)')
    ap.add_argument('--fit-columns', action='store_true',
                    help='diagnostic only: rewrite *NODE coordinates with 13 significant digits, since ccx '
                         'reads each node coordinate from at most 20 characters (f20.0)')
    a = ap.parse_args()
    if shutil.which('ccx') is None:
        print(json.dumps({'ok': False, 'error': 'ccx not found'}))
        return 1
    nodes, elems, types, elsets, conn = parse_inp(a.mesh)
    fixset = f'Face{a.fix}'
    if fixset not in elsets or not elsets[fixset]:
        print(json.dumps({'ok': False, 'error': f'no ELSET {fixset} in {a.mesh}'}))
        return 1
    fixnodes = sorted({n for e in elsets[fixset] for n in conn[e]})
    work = a.keep or tempfile.mkdtemp(prefix='ccx_accepts_')
    os.makedirs(work, exist_ok=True)
    job = os.path.join(work, 'job')
    gx, gy, gz = (float(v) for v in a.dir.split(','))
    with open(a.mesh) as src:
        text = src.read()
    wide = 0  # node coordinates longer than the 20 columns ccx reads
    head, sep, rest = text.partition('*NODE\n')
    body, sep2, tail = rest.partition('\n*')
    card_lines = body.split('\n')
    for k, ln in enumerate(card_lines):
        v = [x.strip() for x in ln.split(',')]
        if any(len(x) > 20 for x in v[1:]):
            wide += 1
            if a.fit_columns:
                card_lines[k] = v[0] + ', ' + ', '.join('%.13g' % float(x) for x in v[1:])
    if a.fit_columns:
        text = head + sep + '\n'.join(card_lines) + sep2 + tail
    with open(job + '.inp', 'w') as out:
        out.write(text)
        out.write(f"""
*NSET, NSET=PMALL
{id_lines(nodes)}
*ELSET, ELSET=PMEALL
{id_lines(elems)}
*NSET, NSET=PMFIX
{id_lines(fixnodes)}
*MATERIAL, NAME=STEEL
*ELASTIC
210000., 0.3
*DENSITY
7.9e-9
*SHELL SECTION, ELSET=PMEALL, MATERIAL=STEEL
{a.thickness}
*BOUNDARY
PMFIX, 1, 6, 0.
*STEP
*STATIC
*DLOAD
PMEALL, GRAV, {a.g}, {gx}, {gy}, {gz}
*NODE PRINT, NSET=PMALL
U
*END STEP
""")
    t0 = time.perf_counter()
    p = subprocess.run(['ccx', '-i', 'job'], cwd=work, capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS='1'))
    secs = time.perf_counter() - t0
    log = p.stdout + p.stderr
    res = {'mesh': a.mesh, 'elements': len(elems), 'types': types, 'nodes': len(nodes), 'fixed_face': a.fix,
           'fixed_nodes': len(fixnodes), 'node_cards_over_20_columns': wide, 'fit_columns': a.fit_columns, 'ccx_exit': p.returncode, 'ccx_seconds': round(secs, 1), 'work': work}
    errors = [ln.strip() for ln in log.splitlines() if '*ERROR' in ln.upper()]
    res['ccx_errors'] = errors[:5]
    res['ccx_warnings'] = sum('*WARNING' in ln.upper() for ln in log.splitlines())
    disp = {}
    dat = job + '.dat'
    if os.path.exists(dat):
        with open(dat) as f:
            for ln in f:
                v = ln.split()
                if len(v) == 4:
                    try:
                        disp[int(v[0])] = tuple(float(x) for x in v[1:])
                    except ValueError:
                        pass
    mags = [math.sqrt(sum(c * c for c in d)) for d in disp.values()]
    res['displaced_nodes'] = len(disp)
    res['finite'] = bool(mags) and all(math.isfinite(m) for m in mags)
    res['max_displacement'] = max(mags) if mags else None
    res['ok'] = (p.returncode == 0 and not errors and len(disp) == len(nodes) and res['finite']
                 and res['max_displacement'] > 0)
    if not res['ok']:
        res['log_tail'] = log.splitlines()[-15:]
    print(json.dumps(res))
    if not a.keep and res['ok']:
        shutil.rmtree(work, ignore_errors=True)
    return 0 if res['ok'] else 1


if __name__ == '__main__':
    sys.exit(main())
