#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Worst elements: ParaMesh against Gmsh 4.8 Frontal-Delaunay, triangle by worst triangle.

usage: bench/worst_elements.py [--models a.stp,b.brep] [--div 100] [--extra "--curvature-angle 10"]
                               [--paramesh EXE] [--out DIR] [--no-gmsh] [--gmsh-from DIR]
                               [--no-check] [--json FILE]

For each model of ../shared/models at h = diagonal / div (the diagonal from `paramesh info`), meshes
with ParaMesh and with ../shared/tools/gmsh_baseline.py (frontal, MeshSizeMin = Max = h), checks
both with the independent ../shared/tools/meshcheck.py (gamma_min, gamma_mean, smallest angle, % of
triangles below 30 degrees, % of edges in [h/sqrt2, sqrt2 h]) and locates each mesher's worst
triangle in its MSH file: face, the CAD entities of its three nodes (V = vertex, E = edge,
F = face interior, from the MSH node blocks), its side lengths / h, and the length of each CAD edge
it touches (sum of that edge's segments). Prints a Markdown table; the ParaMesh report's warnings
that name an edge forcing the worst triangle are printed under it.
--gmsh-from DIR reuses DIR/<model>_<div>.gmsh.msh and its meshcheck (.gmsh.check.json): Gmsh's
mesh does not depend on ParaMesh.
Run with Debian's /usr/bin/python3.
"""
import argparse, json, os, re, subprocess, sys

import meshio
import numpy as np

from compare import MODELS, PY, ROOT, TOOLS, meshcheck  # noqa: F401 (the bench's paths, the checker)
from mesh_stats import radius_ratios


def diagonal(exe, model):
    out = subprocess.run([exe, 'info', model], capture_output=True, text=True).stdout
    return float(re.search(r'diagonal ([0-9.eE+-]+)', out).group(1))


def gammas(P, T):
    """meshcheck's radius ratio per triangle, and the side lengths (a opposite 0)."""
    g, a, b, c = radius_ratios(P, T)
    return g, np.stack([a, b, c], axis=1)


def worst_triangle(mesh, h):
    """Face, node entities and lengths of the mesh's worst triangle (by meshcheck's gamma)."""
    m = meshio.read(mesh)
    P = np.asarray(m.points, float)[:, :3]
    tris, faces, edge_len = [], [], {}
    for i, cb in enumerate(m.cells):
        ent = m.cell_data['gmsh:geometrical'][i]
        if cb.type in ('triangle', 'triangle6'):
            tris.append(cb.data[:, :3]); faces.append(ent)
        elif cb.type in ('line', 'line3'):
            L = np.linalg.norm(P[cb.data[:, 0]] - P[cb.data[:, 1]], axis=1)
            for e, l in zip(ent, L):
                edge_len[int(e)] = edge_len.get(int(e), 0.0) + float(l)
    T = np.concatenate(tris)
    F = np.concatenate(faces)
    g, sides = gammas(P, T)
    k = int(np.argmin(g))
    dt = m.point_data.get('gmsh:dim_tags')
    ents = []
    for v in T[k]:
        d, tag = (int(dt[v][0]), int(dt[v][1])) if dt is not None else (-1, -1)
        ents.append(({0: 'V', 1: 'E', 2: 'F'}.get(d, '?') + str(tag), d, tag))
    edges = sorted({tag for _, d, tag in ents if d == 1})
    return {'gamma': float(g[k]), 'face': int(F[k]), 'nodes': [e[0] for e in ents],
            'sides_h': sorted(float(x) / h for x in sides[k]),
            'edge_len_h': {e: edge_len.get(e, 0.0) / h for e in edges}}


def run_ours(exe, model, h, out, report, extra):
    cmd = [exe, 'mesh', model, '-o', out, '--size', repr(h), '--report', report, '--quiet'] + extra
    p = subprocess.run(cmd, capture_output=True, text=True)
    rep = json.load(open(report)) if os.path.exists(report) else {}
    return {'exit': p.returncode, 'status': rep.get('status'),
            'warnings': [w for w in rep.get('warnings', []) if 'worst triangle' in w]}


def run_gmsh(model, h, out, curvature):
    cmd = [PY, os.path.join(TOOLS, 'gmsh_baseline.py'), model, repr(h), out, '--algo', 'frontal']
    if curvature:
        cmd += ['--curvature', str(curvature)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    return {'exit': p.returncode}


def fmt(x, f='{:.3g}'):
    return '-' if x is None else f.format(x)


def where(w):
    if not w:
        return '-'
    ents = ' '.join(w['nodes'])
    sides = '/'.join(f'{s:.2g}' for s in w['sides_h'])
    el = ', '.join(f'E{e} {l:.2g}h' for e, l in w['edge_len_h'].items())
    return f"F{w['face']}: {ents}; sides {sides} h" + (f'; {el}' if el else '')


def render(rows):
    out = ('| model | h | γ min P / G | γ mean P / G | min angle ° P / G | % <30° P / G | % len OK P / G '
           '| ParaMesh worst triangle | Gmsh worst triangle |\n|---|---|---|---|---|---|---|---|---|\n')
    for r in rows:
        o, g = r['ours_check'], r['gmsh_check']
        pair = lambda k, f='{:.3g}': f"{fmt(o.get(k), f)} / {fmt(g.get(k), f)}"
        out += (f"| {r['model']} | {r['h']:.4g} | {pair('gamma_min')} | {pair('gamma_mean', '{:.4f}')} "
                f"| {pair('angle_min', '{:.2f}')} | {pair('pct_angle_lt_30', '{:.2f}')} "
                f"| {pair('pct_len_in_sqrt2', '{:.2f}')} | {where(r.get('ours_worst'))} "
                f"| {where(r.get('gmsh_worst'))} |\n")
    notes = [f"- {r['model']}: {w}" for r in rows for w in r['ours'].get('warnings', [])]
    return out + ('\nParaMesh warnings on forced worst triangles:\n' + '\n'.join(notes) + '\n' if notes else '')


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--models', default='')
    ap.add_argument('--div', type=float, default=100)
    ap.add_argument('--extra', default='', help='more ParaMesh options, e.g. "--curvature-angle 10"')
    ap.add_argument('--gmsh-curvature', type=int, default=0, help="gmsh_baseline.py's --curvature")
    ap.add_argument('--paramesh', default=os.path.join(ROOT, 'build', 'bin', 'paramesh'))
    ap.add_argument('--out', default=os.path.join(ROOT, 'out', 'worst'))
    ap.add_argument('--no-gmsh', action='store_true')
    ap.add_argument('--gmsh-from', default='')
    ap.add_argument('--no-check', action='store_true', help='skip meshcheck (gamma from the MSH only)')
    ap.add_argument('--json', default='')
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    names = a.models.split(',') if a.models else sorted(f for f in os.listdir(MODELS) if not f.endswith('.md'))
    rows = []
    for name in names:
        model = os.path.join(MODELS, name)
        h = diagonal(a.paramesh, model) / a.div
        tag = f'{name}_{a.div:g}'
        ours = os.path.join(a.out, tag + '.paramesh.msh')
        o = run_ours(a.paramesh, model, h, ours, os.path.join(a.out, tag + '.paramesh.json'),
                     a.extra.split())
        row = {'model': name, 'div': a.div, 'h': h, 'ours': o, 'ours_check': {}, 'gmsh_check': {}}
        if os.path.exists(ours) and o['exit'] in (0, 3):
            row['ours_worst'] = worst_triangle(ours, h)
            row['ours_check'] = {'gamma_min': row['ours_worst']['gamma']} if a.no_check else meshcheck(model, ours, h)
        gm = os.path.join(a.gmsh_from or a.out, tag + '.gmsh.msh')
        if not a.no_gmsh and not os.path.exists(gm):
            run_gmsh(model, h, gm, a.gmsh_curvature)
        if not a.no_gmsh and os.path.exists(gm):
            row['gmsh_worst'] = worst_triangle(gm, h)
            cached = gm[:-4] + '.check.json'  # Gmsh's meshcheck, kept beside its mesh
            if a.no_check:
                row['gmsh_check'] = {'gamma_min': row['gmsh_worst']['gamma']}
            elif os.path.exists(cached) and os.path.getmtime(cached) > os.path.getmtime(gm):
                row['gmsh_check'] = json.load(open(cached))
            else:
                row['gmsh_check'] = meshcheck(model, gm, h)
                json.dump(row['gmsh_check'], open(cached, 'w'))
        rows.append(row)
        print(f"{name:28s} ours {fmt(row['ours_check'].get('gamma_min'))} gmsh "
              f"{fmt(row['gmsh_check'].get('gamma_min'))}  {where(row.get('ours_worst'))}", file=sys.stderr, flush=True)
        if a.json:
            json.dump(rows, open(a.json, 'w'), indent=1)
    print(render(rows))


if __name__ == '__main__':
    main()
