#!/usr/bin/python3
"""Side-by-side benchmark: ParaMesh vs Gmsh 4.8 Frontal-Delaunay on the shared CAD models.

usage: bench/compare.py [--models a.step,b.brep] [--divs 100,200] [--out DIR] [--threads N] [--repeat N]
                        [--extra "--curvature-angle 10"] [--no-gmsh] [--table FILE.md]
                        [--gmsh-from OLD/results.json] [--paramesh EXE]

For each model and each h = bounding-box diagonal / div, meshes with `build/bin/paramesh` and with
../shared/tools/gmsh_baseline.py (same h, frontal), checks both meshes with the independent
../shared/tools/meshcheck.py, and prints a Markdown table (seconds are wall-clock meshing times:
ParaMesh's from its report, total minus file reading; Gmsh's mesh_s from gmsh_baseline.py).
Run with Debian's /usr/bin/python3.
"""
import argparse, json, os, subprocess, sys, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.abspath(os.path.join(ROOT, '..', 'shared'))
MODELS = os.path.join(SHARED, 'models')
TOOLS = os.path.join(SHARED, 'tools')
PY = '/usr/bin/python3'


def diagonal(model):
    code = ("import sys; sys.path.append('/usr/lib/freecad-python3/lib'); import FreeCAD, Part\n"
            "p=sys.argv[1]\n"
            "s=Part.Shape()\n"
            "s.read(p) if p.lower().endswith(('.brep','.brp')) else None\n"
            "s = s if p.lower().endswith(('.brep','.brp')) else Part.read(p)\n"
            "print(s.BoundBox.DiagonalLength)")
    return float(subprocess.check_output([PY, '-c', code, model]).decode().strip().splitlines()[-1])


def meshcheck(model, mesh, h):
    out = subprocess.run([PY, os.path.join(TOOLS, 'meshcheck.py'), model, mesh, '--size', repr(h)],
                         capture_output=True, text=True)
    try:
        return json.loads(out.stdout[out.stdout.index('{'):])
    except Exception:
        return {'error': (out.stderr or out.stdout)[-300:]}


def run_ours(model, h, out, report, threads, extra, exe):
    cmd = [exe, 'mesh', model, '-o', out, '--size', repr(h),
           '--report', report, '--threads', str(threads), '--quiet'] + extra
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    rep = json.load(open(report)) if os.path.exists(report) else {}
    secs = rep.get('seconds', {})
    mesh_s = secs.get('total')
    return {'exit': p.returncode, 'stderr': p.stderr.strip()[-300:], 'wall_s': wall, 'mesh_s': mesh_s,
            'status': rep.get('status'), 'message': rep.get('message'),
            'failed_faces': [f['name'] for f in rep.get('faces', []) if f.get('status') != 'ok']}


def fastest(run, n):
    """The result of run() with the smallest mesh_s over n calls (a failed call never wins)."""
    best = None
    for _ in range(max(1, n)):
        r = run()
        if best is None or (r.get('mesh_s') is not None and best.get('mesh_s') is not None and r['mesh_s'] < best['mesh_s']):
            best = r
    return best


def run_gmsh(model, h, out, extra_curv):
    cmd = [PY, os.path.join(TOOLS, 'gmsh_baseline.py'), model, repr(h), out, '--algo', 'frontal']
    if extra_curv:
        cmd += ['--curvature', str(extra_curv)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    try:
        return json.loads(p.stdout.strip().splitlines()[-1])
    except Exception:
        return {'error': (p.stderr or p.stdout)[-300:]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--models', default='')
    ap.add_argument('--divs', default='100,200')
    ap.add_argument('--out', default=os.path.join(ROOT, 'out', 'bench'))
    ap.add_argument('--threads', type=int, default=1)
    ap.add_argument('--repeat', type=int, default=1,
                    help='run each mesher this many times per case and keep the fastest run (single runs '
                    'of sub-second meshes vary by +-30 %% on a shared machine)')
    ap.add_argument('--extra', default='')
    ap.add_argument('--no-gmsh', action='store_true')
    ap.add_argument('--no-check', action='store_true')
    ap.add_argument('--table', default='')
    ap.add_argument('--paramesh', default=os.path.join(ROOT, 'build', 'bin', 'paramesh'),
                    help='the paramesh executable (default build/bin/paramesh; a copy keeps a long run '
                    'independent of rebuilds)')
    ap.add_argument('--gmsh-from', default='', help="reuse the Gmsh rows of an earlier run's results.json "
                    "(same models and divisions; Gmsh's results do not depend on ParaMesh)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    names = a.models.split(',') if a.models else sorted(
        f for f in os.listdir(MODELS) if not f.endswith('.md'))
    rows = []
    earlier = {}
    if a.gmsh_from:
        for r in json.load(open(a.gmsh_from)):
            earlier[(r['model'], r['div'])] = (r['gmsh'], r['gmsh_check'])
    for name in names:
        model = os.path.join(MODELS, name)
        diag = diagonal(model)
        for div in [int(x) for x in a.divs.split(',')]:
            h = diag / div
            tag = f'{name}_{div}'
            ours_msh = os.path.join(a.out, f'{tag}.paramesh.msh')
            rep = os.path.join(a.out, f'{tag}.paramesh.json')
            o = fastest(lambda: run_ours(model, h, ours_msh, rep, a.threads, a.extra.split() if a.extra else [],
                                         a.paramesh), a.repeat)
            oc = meshcheck(model, ours_msh, h) if (not a.no_check and os.path.exists(ours_msh)) else {}
            g, gc = {}, {}
            if (name, div) in earlier:
                g, gc = earlier[(name, div)]
            elif not a.no_gmsh:
                gm = os.path.join(a.out, f'{tag}.gmsh.msh')
                g = fastest(lambda: run_gmsh(model, h, gm, 0), a.repeat)
                gc = meshcheck(model, gm, h) if (not a.no_check and os.path.exists(gm)) else {}
            row = {'model': name, 'div': div, 'h': h, 'ours': o, 'ours_check': oc, 'gmsh': g, 'gmsh_check': gc}
            rows.append(row)
            json.dump(rows, open(os.path.join(a.out, 'results.json'), 'w'), indent=1)
            print(line(row), flush=True)
    table = render(rows)
    print(table)
    if a.table:
        open(a.table, 'w').write(table)


def fmt(x, f='{:.3f}'):
    return '-' if x is None else f.format(x)


def line(r):
    o, oc, g, gc = r['ours'], r['ours_check'], r['gmsh'], r['gmsh_check']
    return (f"{r['model']:28s} /{r['div']} ours: {fmt(o.get('mesh_s'))}s {oc.get('triangles')} tris "
            f"g={fmt(oc.get('gamma_mean'),'{:.4f}')} <30={fmt(oc.get('pct_angle_lt_30'),'{:.2f}')}% "
            f"len={fmt(oc.get('pct_len_in_sqrt2'),'{:.2f}')}% bnd={oc.get('boundary_edges')} "
            f"nm={oc.get('nonmanifold_edges')} flip={oc.get('pct_flipped_vs_cad')} "
            f"dev={fmt(oc.get('node_dev_max_rel'),'{:.1e}')} fail={o.get('failed_faces')} | "
            f"gmsh: {fmt(g.get('mesh_s'))}s {gc.get('triangles')} g={fmt(gc.get('gamma_mean'),'{:.4f}')} "
            f"<30={fmt(gc.get('pct_angle_lt_30'),'{:.2f}')}% len={fmt(gc.get('pct_len_in_sqrt2'),'{:.2f}')}%")


def render(rows):
    hdr = ('| model | h | ParaMesh s | Gmsh s | ParaMesh tris | Gmsh tris | γ mean P / G | % <30° P / G '
           '| % len OK P / G | failed faces | bnd / nm edges | flipped % | node dev |\n'
           '|---|---|---|---|---|---|---|---|---|---|---|---|---|\n')
    out = hdr
    for r in rows:
        o, oc, g, gc = r['ours'], r['ours_check'], r['gmsh'], r['gmsh_check']
        out += (f"| {r['model']} | d/{r['div']} | {fmt(o.get('mesh_s'),'{:.2f}')} | {fmt(g.get('mesh_s'),'{:.2f}')} "
                f"| {oc.get('triangles','-')} | {gc.get('triangles','-')} "
                f"| {fmt(oc.get('gamma_mean'),'{:.4f}')} / {fmt(gc.get('gamma_mean'),'{:.4f}')} "
                f"| {fmt(oc.get('pct_angle_lt_30'),'{:.2f}')} / {fmt(gc.get('pct_angle_lt_30'),'{:.2f}')} "
                f"| {fmt(oc.get('pct_len_in_sqrt2'),'{:.2f}')} / {fmt(gc.get('pct_len_in_sqrt2'),'{:.2f}')} "
                f"| {len(o.get('failed_faces') or [])} | {oc.get('boundary_edges','-')} / {oc.get('nonmanifold_edges','-')} "
                f"| {fmt(oc.get('pct_flipped_vs_cad'),'{:.2f}')} | {fmt(oc.get('node_dev_max_rel'),'{:.1e}')} |\n")
    return out


if __name__ == '__main__':
    main()
