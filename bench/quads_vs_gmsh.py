#!/usr/bin/python3
"""Quad-dominant meshes: ParaMesh --quads against Gmsh's recombination, measured by one function.

usage: bench/quads_vs_gmsh.py [--models bottle.brep nist_ctc_01.brep] [--fractions 100 200]
                              [--samples 3000] [--out DIR] [--json FILE]

For each model and h = bbox diagonal / F: ParaMesh (build/bin/paramesh mesh MODEL -o X.msh --size h
--quads) and Gmsh 4.8 (OCC import, Mesh.MeshSizeMin = Mesh.MeshSizeMax = h, Mesh.Algorithm = 6
frontal-Delaunay, Mesh.RecombineAll = 1 with the default Mesh.RecombinationAlgorithm, 1 thread),
each run as its own process and timed wall clock end to end (CAD load + surface mesh + .msh write).
Both .msh files are then measured by measure() below (meshio + numpy; FreeCAD Part for the CAD
normals), which knows nothing of either mesher:
  quad area %      area of quads / total area (a quad's area: mean of its two diagonal splits)
  quad angles      corner angles in 3D; max over all quads, mean of the per-quad max, % of quads
                   with a corner > 160 deg
  conformal        every edge shared by exactly 2 elements (closed solids: no boundary edge), no
                   edge in more than 2 (non-manifold), no duplicate node
  oriented         neighbours traverse their shared edge in opposite directions (count of
                   inconsistent edges), and % of sampled elements whose normal points like the CAD
                   face normal (Part Face.normalAt, i.e. outward for a solid) at the element
Prints a Markdown table. Run with Debian's /usr/bin/python3.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

sys.path.append('/usr/lib/freecad-python3/lib')
import numpy as np
import meshio
import FreeCAD  # noqa: F401  (before Part)
import Part

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS = '/work/shared/models'
PARAMESH = os.path.join(ROOT, 'build', 'bin', 'paramesh')

GMSH_SCRIPT = r'''
import sys, gmsh
model, h, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
gmsh.initialize()
gmsh.option.setNumber('General.Terminal', 0)
gmsh.option.setNumber('General.NumThreads', 1)
gmsh.model.occ.importShapes(model)
gmsh.model.occ.synchronize()
gmsh.option.setNumber('Mesh.MeshSizeMin', h)
gmsh.option.setNumber('Mesh.MeshSizeMax', h)
gmsh.option.setNumber('Mesh.MeshSizeFromCurvature', 0)
gmsh.option.setNumber('Mesh.Algorithm', 6)
gmsh.option.setNumber('Mesh.RecombineAll', 1)
gmsh.model.mesh.generate(2)
gmsh.write(out)
gmsh.finalize()
'''


def load_cad(path):
    if path.lower().endswith(('.brep', '.brp')):
        s = Part.Shape()
        s.read(path)
        return s
    return Part.read(path)


def diag(shape):
    return shape.BoundBox.DiagonalLength


def corner_angles(X):
    """X: (n, k, 3) polygon corners; returns (n, k) interior angles in degrees (3D)."""
    k = X.shape[1]
    out = np.zeros(X.shape[:2])
    for i in range(k):
        u = X[:, (i + 1) % k] - X[:, i]
        w = X[:, (i - 1) % k] - X[:, i]
        c = np.einsum('nd,nd->n', u, w) / np.maximum(np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1), 1e-300)
        out[:, i] = np.degrees(np.arccos(np.clip(c, -1, 1)))
    return out


def measure(shape, mesh_path, h, samples=3000, seed=1):
    """Independent measurements of a linear tri/quad surface mesh (see module doc)."""
    m = meshio.read(mesh_path)
    P = np.asarray(m.points, float)[:, :3]
    key = next((k for k in ('gmsh:geometrical', 'gmsh:physical') if k in m.cell_data), None)
    T, TE, Q, QE = [], [], [], []
    for i, cb in enumerate(m.cells):
        ent = np.asarray(m.cell_data[key][i]) if key else np.full(len(cb.data), -1)
        if cb.type == 'triangle':
            T.append(cb.data); TE.append(ent)
        elif cb.type == 'quad':
            Q.append(cb.data); QE.append(ent)
        elif cb.type in ('triangle6', 'quad8', 'triangle7', 'quad9'):
            raise ValueError('measure() expects a linear mesh')
    T = np.concatenate(T) if T else np.zeros((0, 3), int)
    Q = np.concatenate(Q) if Q else np.zeros((0, 4), int)
    TE = np.concatenate(TE) if TE else np.zeros(0, int)
    QE = np.concatenate(QE) if QE else np.zeros(0, int)
    r = {'triangles': int(len(T)), 'quads': int(len(Q))}
    # areas
    at = 0.5 * np.linalg.norm(np.cross(P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]]), axis=1)
    if len(Q):
        d1 = 0.5 * (np.linalg.norm(np.cross(P[Q[:, 1]] - P[Q[:, 0]], P[Q[:, 2]] - P[Q[:, 0]]), axis=1)
                    + np.linalg.norm(np.cross(P[Q[:, 2]] - P[Q[:, 0]], P[Q[:, 3]] - P[Q[:, 0]]), axis=1))
        d2 = 0.5 * (np.linalg.norm(np.cross(P[Q[:, 2]] - P[Q[:, 1]], P[Q[:, 3]] - P[Q[:, 1]]), axis=1)
                    + np.linalg.norm(np.cross(P[Q[:, 3]] - P[Q[:, 1]], P[Q[:, 0]] - P[Q[:, 1]]), axis=1))
        aq = 0.5 * (d1 + d2)
        ang = corner_angles(P[Q])
        qmax = ang.max(axis=1)
        r['quad_area_pct'] = float(100 * aq.sum() / (aq.sum() + at.sum()))
        r['quad_angle_max'] = float(qmax.max())
        r['quad_angle_max_mean'] = float(qmax.mean())
        r['quad_angle_min'] = float(ang.min())
        r['pct_quads_over_160'] = float(100 * (qmax > 160).mean())
        r['quads_over_160'] = int((qmax > 160).sum())
    else:
        r.update(quad_area_pct=0.0, quad_angle_max=None, quad_angle_max_mean=None, quad_angle_min=None,
                 pct_quads_over_160=0.0, quads_over_160=0)
    r['area'] = float(at.sum() + (aq.sum() if len(Q) else 0))
    r['cad_area'] = float(shape.Area)
    # conformity: directed edges of every element
    de = [T[:, [i, (i + 1) % 3]] for i in range(3)] + [Q[:, [i, (i + 1) % 4]] for i in range(4)]
    de = np.concatenate(de)
    und = np.sort(de, axis=1)
    ue, inv, cnt = np.unique(und, axis=0, return_inverse=True, return_counts=True)
    r['edges'] = int(len(ue))
    r['boundary_edges'] = int((cnt == 1).sum())
    r['nonmanifold_edges'] = int((cnt > 2).sum())
    used = np.unique(np.concatenate([T.ravel(), Q.ravel()]))
    dg = float(np.linalg.norm(P[used].max(0) - P[used].min(0)))
    keyp = np.round(P[used] / (dg * 1e-9)).astype(np.int64)
    r['duplicate_nodes'] = int(len(keyp) - len(np.unique(keyp, axis=0)))
    r['conformal'] = bool(r['boundary_edges'] == 0 and r['nonmanifold_edges'] == 0 and r['duplicate_nodes'] == 0)
    # orientation consistency: an edge shared by 2 elements must appear once in each direction
    fwd = (de[:, 0] < de[:, 1]).astype(int)
    s = np.bincount(inv.ravel(), weights=fwd, minlength=len(ue))
    two = cnt == 2
    r['inconsistent_edges'] = int((two & (s != 1)).sum())
    # orientation against the CAD normal, sampled
    faces = shape.Faces
    rng = np.random.default_rng(seed)
    elems = [(P[T[k]], TE[k]) for k in range(len(T))] + [(P[Q[k]], QE[k]) for k in range(len(Q))]
    pick = rng.choice(len(elems), size=min(samples, len(elems)), replace=False)
    agree = checked = 0
    for k in pick:
        X, f = elems[k]
        n = np.cross(X[1] - X[0], X[2] - X[0]) if len(X) == 3 else np.cross(X[2] - X[0], X[3] - X[1])
        c = FreeCAD.Vector(*X.mean(axis=0))
        if not (1 <= f <= len(faces)):
            continue
        face = faces[int(f) - 1]
        try:
            u, v = face.Surface.parameter(c)
            if (face.Surface.value(u, v) - c).Length > 0.5 * h:  # entity tag not this CAD face
                continue
            nv = face.normalAt(u, v)
        except Exception:
            continue
        checked += 1
        agree += bool(n[0] * nv.x + n[1] * nv.y + n[2] * nv.z > 0)
    r['normal_samples'] = checked
    r['pct_outward'] = float(100 * agree / checked) if checked else None
    r['oriented'] = bool(r['inconsistent_edges'] == 0 and checked > 0 and agree == checked)
    return r


def run_paramesh(model, h, out):
    t0 = time.perf_counter()
    subprocess.run([PARAMESH, 'mesh', model, '-o', out, '--size', repr(h), '--quads', '--quiet'], check=True,
                   capture_output=True)
    return time.perf_counter() - t0


def run_gmsh(model, h, out):
    t0 = time.perf_counter()
    subprocess.run(['/usr/bin/python3', '-c', GMSH_SCRIPT, model, repr(h), out], check=True, capture_output=True)
    return time.perf_counter() - t0


def fmt(v, d=1):
    if v is None:
        return '-'
    if isinstance(v, bool):
        return 'yes' if v else 'NO'
    if isinstance(v, float):
        return f'{v:.{d}f}'
    return str(v)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--models', nargs='+', default=['bottle.brep', 'nist_ctc_01.brep'])
    ap.add_argument('--fractions', nargs='+', type=float, default=[100, 200])
    ap.add_argument('--samples', type=int, default=3000)
    ap.add_argument('--out', default=None, help='directory for the meshes (default: temporary)')
    ap.add_argument('--json', default=None)
    a = ap.parse_args()
    out = a.out or tempfile.mkdtemp(prefix='quads_vs_gmsh_')
    os.makedirs(out, exist_ok=True)
    rows = []
    for name in a.models:
        path = name if os.path.isabs(name) else os.path.join(MODELS, name)
        shape = load_cad(path)
        for F in a.fractions:
            h = diag(shape) / F
            stem = os.path.join(out, f'{os.path.splitext(os.path.basename(path))[0]}_d{int(F)}')
            for mesher, run in (('ParaMesh', run_paramesh), ('Gmsh 4.8', run_gmsh)):
                mp = f'{stem}_{mesher.split()[0].lower()}.msh'
                secs = run(path, h, mp)
                r = measure(shape, mp, h, a.samples)
                r.update(model=os.path.basename(path), h=h, F=F, mesher=mesher, seconds=secs, mesh=mp)
                rows.append(r)
                print(json.dumps(r), file=sys.stderr)
    if a.json:
        with open(a.json, 'w') as f:
            json.dump(rows, f, indent=1)
    print('| model | h | mesher | quads | tris | area in quads % | max quad angle ° | mean per-quad max ° '
          '| quads > 160° % | boundary / non-manifold edges | dup. nodes | inconsistent edges | outward % (sampled) | s |')
    print('|---|---|---|---|---|---|---|---|---|---|---|---|---|---|')
    for r in rows:
        print(f"| {r['model']} | diag/{int(r['F'])} = {r['h']:.4g} | {r['mesher']} | {r['quads']} | {r['triangles']} "
              f"| {fmt(r['quad_area_pct'])} | {fmt(r['quad_angle_max'])} | {fmt(r['quad_angle_max_mean'])} "
              f"| {fmt(r['pct_quads_over_160'], 2)} | {r['boundary_edges']} / {r['nonmanifold_edges']} "
              f"| {r['duplicate_nodes']} | {r['inconsistent_edges']} | {fmt(r['pct_outward'])} | {r['seconds']:.2f} |")


if __name__ == '__main__':
    main()
