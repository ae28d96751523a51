#!/usr/bin/python3
"""Tetrahedral meshes: ParaMesh --volume against Gmsh 4.8's own 3D mesh, both measured here.

usage: /usr/bin/python3 bench/volume_vs_gmsh.py [--models CrankArm.brep boxed_sphere.step ...]
           [--divisors 50,100] [--out docs/volume_benchmark.md] [--work DIR] [--json FILE]
           [--timeout 600] [--paramesh EXE] [--render FILE.json]

For every model of /work/shared/models (STEP / IGES / BREP) whose CAD has solids (OpenCASCADE via
gmsh.model.occ.importShapes: models without a volume entity are listed as skipped) and every
divisor D, at H = bounding-box diagonal / D:

  ParaMesh  build/bin/paramesh mesh MODEL -o X.msh --volume --size H --report R.json
            (1 thread, its default); seconds = wall clock of the whole process (CAD read, surface,
            volume, MSH and report written).
  Gmsh      a fresh /usr/bin/python3 process running the gmsh 4.8.4 API: General.Terminal 0,
            General.NumThreads 1 (and Mesh.MaxNumThreads1D/2D/3D 1), occ.importShapes + synchronize,
            Mesh.MeshSizeMin = Mesh.MeshSizeMax = H, Mesh.MeshSizeFromCurvature 0, Mesh.Algorithm 6
            (Frontal-Delaunay 2D), Mesh.Algorithm3D 1 (Delaunay), generate(3), write MSH 4.1;
            seconds = load + mesh, measured inside that process (the write is timed apart).

Each run has a time-out (--timeout, seconds); a run that fails, times out or writes no
tetrahedra gives its row a reason (exit code and the end of stderr) instead of numbers.

Both MSH files are then read by read_msh() below (a plain MSH 4.1 ASCII parser) and measured by
tet_quality() / mesh_checks() (numpy), which know nothing of either mesher:
  tets          linear tetrahedra (the 4 corners of tet10)
  min dihedral  smallest interior dihedral angle over all tets, degrees
  % < 10 deg    share (and count) of tets with a dihedral angle below 10 degrees (slivers)
  radius ratio  mean of 3 r_in / r_circ (1 for the regular tet, 0 for a flat one)
  inverted      tets with signed volume <= 0 (corner order as written)
  over-shared   distinct tet faces (corner triples) used by more than two tets
  vol err %     per solid: (sum of its tet volumes - CAD volume) / CAD volume, the CAD volume being
                gmsh.model.occ.getMass(3, tag); the table shows the solid with the largest |error|, signed
and, for ParaMesh only:
  boundary == surface  per solid: the tet faces used once among that solid's tets equal, as node
                sets, the surface triangles of the CAD faces bounding that solid (from
                gmsh.model.getAdjacencies on the CAD, after checking that every ParaMesh face
                entity lies on the gmsh face of the same number; cross-checked against the
                report's volume.solids[].faces)
  conformal     across solids: every CAD face bounding two solids, and every pair of distinct
                coincident CAD faces of two solids (nodes of one on the other's trimmed surface),
                is bounded on both sides by exactly the same triangles; no two distinct nodes of
                the tets at the same point
A second table splits the seconds (ParaMesh: its report's total minus its volume stage = surface, and
the volume stage; Gmsh: load, generate(3), write, whole process) and gives the surface triangles of
both files and the 1-minute load average before each run (timings on a busy machine are noisy).
Prints the tables and writes them as Markdown to --out: into the block between
'<!-- table:begin -->' and '<!-- table:end -->' when the file has one (the text around it is
kept), otherwise as a new file. All rows go to --json (default WORK/results.json);
--render FILE.json re-renders a saved run without meshing. Run with Debian's /usr/bin/python3.
"""
import argparse
import json
import math
import os
import subprocess
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS = '/work/shared/models'
PY = '/usr/bin/python3'
CAD_EXT = ('.step', '.stp', '.iges', '.igs', '.brep', '.brp')

GMSH_SCRIPT = r'''
import json, sys, time
t_start = time.perf_counter()
import gmsh
model, h, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
res = {}
gmsh.initialize()
try:
    gmsh.option.setNumber('General.Terminal', 0)
    gmsh.option.setNumber('General.NumThreads', 1)
    for d in ('1D', '2D', '3D'):
        gmsh.option.setNumber('Mesh.MaxNumThreads' + d, 1)
    gmsh.logger.start()
    t0 = time.perf_counter()
    gmsh.model.occ.importShapes(model)
    gmsh.model.occ.synchronize()
    t1 = time.perf_counter()
    gmsh.option.setNumber('Mesh.MeshSizeMin', h)
    gmsh.option.setNumber('Mesh.MeshSizeMax', h)
    gmsh.option.setNumber('Mesh.MeshSizeFromCurvature', 0)
    gmsh.option.setNumber('Mesh.Algorithm', 6)
    gmsh.option.setNumber('Mesh.Algorithm3D', 1)
    gmsh.model.mesh.generate(3)
    t2 = time.perf_counter()
    gmsh.write(out)
    t3 = time.perf_counter()
    res = {'ok': True, 'load_s': t1 - t0, 'mesh_s': t2 - t1, 'seconds': t2 - t0, 'write_s': t3 - t2,
           'gmsh_import_s': t0 - t_start}
except Exception as e:
    res = {'ok': False, 'error': str(e)}
try:
    log = gmsh.logger.get()
    res['log_errors'] = [l for l in log if l.startswith('Error')][-5:]
    res['log_warnings'] = len([l for l in log if l.startswith('Warning')])
except Exception:
    pass
gmsh.finalize()
print('RESULT ' + json.dumps(res), flush=True)
'''


# ----------------------------------------------------------------------------------------- reading

def read_msh(path):
    """MSH 4.1 ASCII -> dict(points (n,3), tag_index (node tag -> row), blocks [(dim, entity, type, (m,k) node tags)])."""
    with open(path) as f:
        lines = f.read().split('\n')
    i = 0
    n = len(lines)
    points = tags = None
    blocks = []
    while i < n:
        s = lines[i].strip()
        if s == '$MeshFormat':
            ver = lines[i + 1].split()
            if not ver[0].startswith('4') or ver[1] != '0':
                raise ValueError(f'{path}: MSH {ver[0]} file type {ver[1]}, expected 4.x ASCII')
            i += 2
        elif s == '$Nodes':
            nb, nn = (int(x) for x in lines[i + 1].split()[:2])
            i += 2
            tags = np.empty(nn, np.int64)
            points = np.empty((nn, 3))
            k = 0
            for _ in range(nb):
                _, _, param, m = (int(x) for x in lines[i].split())
                i += 1
                tags[k:k + m] = np.array(' '.join(lines[i:i + m]).split(), np.int64) if m else []
                i += m
                xyz = np.array(' '.join(lines[i:i + m]).split(), float).reshape(m, -1) if m else np.zeros((0, 3))
                points[k:k + m] = xyz[:, :3]
                i += m
                k += m
        elif s == '$Elements':
            nb = int(lines[i + 1].split()[0])
            i += 2
            for _ in range(nb):
                dim, ent, typ, m = (int(x) for x in lines[i].split())
                i += 1
                a = np.array(' '.join(lines[i:i + m]).split(), np.int64)
                i += m
                a = a.reshape(m, -1) if m else np.zeros((0, 1), np.int64)
                blocks.append((dim, ent, typ, a[:, 1:]))
        else:
            i += 1
    if points is None:
        raise ValueError(f'{path}: no $Nodes section')
    return {'points': points, 'tags': tags, 'blocks': blocks}


def elements(msh, kind):
    """kind 'tet' or 'tri': (m,4|3) row indices into points of the corner nodes, (m,) entity tags."""
    types = {'tet': {4: 4, 11: 4, 29: 4}, 'tri': {2: 3, 9: 3, 21: 3}}[kind]
    tags = msh['tags']
    order = np.argsort(tags)
    conn, ent = [], []
    for dim, e, typ, a in msh['blocks']:
        if typ in types:
            c = a[:, :types[typ]]
            pos = np.searchsorted(tags, c, sorter=order)
            conn.append(order[np.minimum(pos, len(tags) - 1)])
            if not np.array_equal(tags[conn[-1]], c):
                raise ValueError('element refers to a node tag the file does not define')
            ent.append(np.full(len(c), e, np.int64))
    k = 4 if kind == 'tet' else 3
    if not conn:
        return np.zeros((0, k), np.int64), np.zeros(0, np.int64)
    return np.concatenate(conn), np.concatenate(ent)


# ----------------------------------------------------------------------------------------- measuring

def tet_quality(P, T, chunk=500000):
    """Per tet: signed volume, min and max interior dihedral angle (degrees), radius ratio 3 r_in / r_circ."""
    vol = np.empty(len(T)); dmin = np.empty(len(T)); dmax = np.empty(len(T)); rho = np.empty(len(T))
    # face k is opposite corner k; edge (i, j) is shared by the two faces opposite the other two corners
    faces = [(1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1)]
    pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
    for s in range(0, len(T), chunk):
        X = P[T[s:s + chunk]]
        a, b, c = X[:, 1] - X[:, 0], X[:, 2] - X[:, 0], X[:, 3] - X[:, 0]
        V = np.einsum('nd,nd->n', a, np.cross(b, c)) / 6.0
        N = []
        for k, (i, j, l) in enumerate(faces):
            nk = np.cross(X[:, j] - X[:, i], X[:, l] - X[:, i])
            # point it away from corner k, whatever the corner order
            sgn = np.sign(np.einsum('nd,nd->n', nk, X[:, i] - X[:, k]))
            N.append(nk * np.where(sgn == 0, 1, sgn)[:, None])
        A = [np.linalg.norm(x, axis=1) for x in N]  # twice the face areas
        angs = []
        with np.errstate(all='ignore'):
            for k, l in pairs:
                cth = -np.einsum('nd,nd->n', N[k], N[l]) / (A[k] * A[l])
                angs.append(np.degrees(np.arccos(np.clip(np.nan_to_num(cth, nan=1.0), -1, 1))))
            angs = np.stack(angs, axis=1)
            num = (np.einsum('nd,nd->n', a, a)[:, None] * np.cross(b, c) + np.einsum('nd,nd->n', b, b)[:, None]
                   * np.cross(c, a) + np.einsum('nd,nd->n', c, c)[:, None] * np.cross(a, b))
            area = 0.5 * (A[0] + A[1] + A[2] + A[3])
            r = 108.0 * V * V / (area * np.linalg.norm(num, axis=1))
        vol[s:s + chunk] = V
        dmin[s:s + chunk] = angs.min(axis=1)
        dmax[s:s + chunk] = angs.max(axis=1)
        rho[s:s + chunk] = np.nan_to_num(r, nan=0.0)
    return vol, dmin, dmax, rho


def face_keys(F, nnodes):
    """(m,3) node rows -> (m,) int64 keys of the sorted triples (or (m,3) rows when too many nodes)."""
    F = np.sort(F, axis=1)
    if nnodes < (1 << 21):
        return (F[:, 0] << 42) | (F[:, 1] << 21) | F[:, 2]
    return F


def unique_counts(K):
    if K.ndim == 1:
        return np.unique(K, return_counts=True)
    u, c = np.unique(K, axis=0, return_counts=True)
    return u, c


def tet_faces(T):
    return np.concatenate([T[:, [1, 2, 3]], T[:, [0, 2, 3]], T[:, [0, 1, 3]], T[:, [0, 1, 2]]])


def setdiff_count(A, B):
    if A.ndim == 1:
        return int(len(np.setdiff1d(A, B, assume_unique=False)))
    sa = {tuple(r) for r in A}
    sb = {tuple(r) for r in B}
    return len(sa - sb)


def measure(path, cad_solids):
    """Quality and conformity numbers of one MSH file. cad_solids: {volume tag: CAD volume}."""
    msh = read_msh(path)
    P = msh['points']
    T, TE = elements(msh, 'tet')
    r = {'tets': int(len(T)), 'nodes': int(len(P)), 'triangles': int(len(elements(msh, 'tri')[0]))}
    if not len(T):
        return r, msh, T, TE
    vol, dmin, dmax, rho = tet_quality(P, T)
    r['min_dihedral'] = float(dmin.min())
    r['max_dihedral'] = float(dmax.max())
    r['pct_dihedral_lt_10'] = float(100.0 * (dmin < 10).mean())
    r['tets_dihedral_lt_10'] = int((dmin < 10).sum())
    r['mean_radius_ratio'] = float(rho.mean())
    r['min_radius_ratio'] = float(rho.min())
    r['inverted'] = int((vol <= 0).sum())
    K = face_keys(tet_faces(T), len(P))
    _, cnt = unique_counts(K)
    r['tet_faces'] = int(len(cnt))
    r['over_shared_faces'] = int((cnt > 2).sum())
    r['solids'] = {}
    for s in sorted(set(TE.tolist())):
        sel = TE == s
        cadv = cad_solids.get(int(s))
        v = float(np.abs(vol[sel]).sum())
        r['solids'][int(s)] = {'tets': int(sel.sum()), 'volume': v, 'cad_volume': cadv,
                               'volume_error_pct': (100.0 * (v - cadv) / cadv) if cadv else None,
                               'min_dihedral': float(dmin[sel].min()),
                               'pct_dihedral_lt_10': float(100.0 * (dmin[sel] < 10).mean())}
    missing = [t for t in cad_solids if t not in r['solids']]
    r['solids_without_tets'] = missing
    errs = [abs(x['volume_error_pct']) for x in r['solids'].values() if x['volume_error_pct'] is not None]
    r['max_abs_volume_error_pct'] = max(errs) if errs else None
    # the signed volume error of the whole mesh, for the table's sign
    tot = sum(x['volume'] for x in r['solids'].values())
    cad_tot = sum(cad_solids.values())
    r['total_volume_error_pct'] = 100.0 * (tot - cad_tot) / cad_tot if cad_tot else None
    return r, msh, T, TE


# ----------------------------------------------------------------------------------------- the CAD

def load_cad(gmsh, path):
    """Load the CAD into the (initialised) gmsh of this process: diagonal, solids, their faces and volumes."""
    gmsh.clear()
    gmsh.model.occ.importShapes(path)
    gmsh.model.occ.synchronize()
    b = gmsh.model.getBoundingBox(-1, -1)
    cad = {'diagonal': math.dist(b[:3], b[3:]), 'faces': len(gmsh.model.getEntities(2)), 'solids': {}}
    for _, t in gmsh.model.getEntities(3):
        _, down = gmsh.model.getAdjacencies(3, t)
        cad['solids'][int(t)] = {'faces': sorted(int(f) for f in down), 'volume': float(gmsh.model.occ.getMass(3, t)),
                                 'bbox': list(gmsh.model.getBoundingBox(3, t))}
    return cad


def face_nodes(msh, tri, tri_ent, face, limit=24):
    """Up to `limit` node rows of ParaMesh's face entity, preferring nodes that belong to that face alone."""
    on = np.unique(tri[tri_ent == face])
    other = np.unique(tri[tri_ent != face])
    own = np.setdiff1d(on, other)
    pick = own if len(own) else on
    if len(pick) > limit:
        pick = pick[np.linspace(0, len(pick) - 1, limit).astype(int)]
    return pick, bool(len(own))


def dist_to_face(gmsh, face, X, trimmed=True):
    """Distances of points X to the gmsh CAD face's (untrimmed) surface, and whether each lies in its
    trimmed domain (gmsh 4.8's getClosestPoint returns no usable (u, v): they come from
    getParametrization, which fails off the surface's parameter range: such a point is outside)."""
    try:
        cl, _ = gmsh.model.getClosestPoint(2, int(face), X.ravel().tolist())
    except Exception:
        return np.full(len(X), np.inf), np.zeros(len(X), bool)
    d = np.linalg.norm(np.asarray(cl).reshape(-1, 3) - X, axis=1)
    inside = np.zeros(len(X), bool)
    if trimmed:
        for k in range(len(X)):
            try:
                uv = gmsh.model.getParametrization(2, int(face), X[k].tolist())
                inside[k] = gmsh.model.isInside(2, int(face), list(uv)) > 0
            except Exception:
                inside[k] = False
    return d, inside


def bbox_overlap(a, b, tol):
    return all(a[i] - tol <= b[i + 3] and b[i] - tol <= a[i + 3] for i in range(3))


def paramesh_checks(gmsh, cad, msh, T, TE, report, h):
    """Boundary == surface per solid, and conformity across solids (see the module doc)."""
    P = msh['points']
    tri, tri_ent = elements(msh, 'tri')
    nn = len(P)
    out = {}
    diag = cad['diagonal']
    tol = 1e-6 * diag
    # 1. ParaMesh face k lies on gmsh face k (the two numberings agree), else the nearest gmsh face
    fmap, bad = {}, []
    all_faces = [int(t) for _, t in gmsh.model.getEntities(2)]
    for k in sorted(set(tri_ent.tolist())):
        rows, own = face_nodes(msh, tri, tri_ent, k)
        d, _ = dist_to_face(gmsh, k, P[rows], False) if k in all_faces else (np.array([np.inf]), None)
        if np.median(d) <= tol * (1 if own else 100):
            fmap[k] = k
            continue
        best = min(all_faces, key=lambda f: np.median(dist_to_face(gmsh, f, P[rows], False)[0]))
        fmap[k] = best
        if best != k:
            bad.append(k)
    out['face_numbering_mismatches'] = bad
    inv = {}
    for k, g in fmap.items():
        inv.setdefault(g, []).append(k)
    # 2. the faces of each ParaMesh solid, from OpenCASCADE; compared with the report's lists
    rep_faces = {}
    for s in (report or {}).get('volume', {}).get('solids', []):
        rep_faces[int(s['solid'])] = sorted(s['faces'])
    solid_faces = {}
    for s, info in cad['solids'].items():
        solid_faces[s] = sorted(k for g in info['faces'] for k in inv.get(g, [g]))
    out['faces_differ_from_report'] = [s for s in solid_faces if s in rep_faces and rep_faces[s] != solid_faces[s]]
    # 3. boundary of each solid's tets == surface triangles of its faces
    tri_keys = face_keys(tri, nn)
    boundary, per = {}, {}
    for s in sorted(cad['solids']):
        sel = TE == s
        K = face_keys(tet_faces(T[sel]), nn)
        u, c = unique_counts(K)
        bnd = u[c == 1]
        surf = tri_keys[np.isin(tri_ent, solid_faces[s])]
        surf_u = unique_counts(surf)[0]
        boundary[s] = bnd
        per[s] = {'boundary_faces': int(len(bnd)), 'surface_triangles': int(len(surf_u)),
                  'duplicate_surface_triangles': int(len(surf) - len(surf_u)),
                  'boundary_not_surface': setdiff_count(bnd, surf_u), 'surface_not_boundary': setdiff_count(surf_u, bnd),
                  'faces_used_3_or_more_in_solid': int((c > 2).sum()), 'tets': int(sel.sum())}
        per[s]['ok'] = (per[s]['tets'] > 0 and per[s]['boundary_not_surface'] == 0 and per[s]['surface_not_boundary'] == 0
                        and per[s]['faces_used_3_or_more_in_solid'] == 0)
    out['solids'] = per
    out['boundary_ok'] = all(p['ok'] for p in per.values()) and not out['faces_differ_from_report']
    # 4. conformity across solids
    conf = {'shared_faces': [], 'coincident_pairs': [], 'failures': []}
    sol = sorted(cad['solids'])
    rep_pairs = [tuple(p) for p in (report or {}).get('coincident_faces', [])]
    conf['report_coincident_faces'] = rep_pairs
    gbox = {f: gmsh.model.getBoundingBox(2, f) for f in all_faces}
    for i, A in enumerate(sol):
        for B in sol[i + 1:]:
            shared = sorted(set(solid_faces[A]) & set(solid_faces[B]))
            for f in shared:
                t = unique_counts(tri_keys[tri_ent == f])[0]
                ma, mb = setdiff_count(t, boundary[A]), setdiff_count(t, boundary[B])
                conf['shared_faces'].append({'face': f, 'solids': [A, B], 'triangles': int(len(t)),
                                             'missing_in_A': ma, 'missing_in_B': mb})
                if ma or mb:
                    conf['failures'].append(f'Face{f} (shared by solids {A}, {B}): {ma} / {mb} of its {len(t)} '
                                            'triangles not on the boundary of solid A / B')
            if not bbox_overlap(cad['solids'][A]['bbox'], cad['solids'][B]['bbox'], 0.01 * h):
                continue
            onlyA = [f for f in solid_faces[A] if f not in shared]
            onlyB = [f for f in solid_faces[B] if f not in shared]
            for (S1, F1s, S2, F2s) in ((A, onlyA, B, onlyB), (B, onlyB, A, onlyA)):
                for x in F1s:
                    gx = fmap.get(x, x)
                    rows, _ = face_nodes(msh, tri, tri_ent, x, limit=16)
                    if not len(rows):
                        continue
                    for y in F2s:
                        gy = fmap.get(y, y)
                        reported = (x, y) in rep_pairs or (y, x) in rep_pairs
                        if not reported and not bbox_overlap(gbox[gx], gbox[gy], 0.01 * h):
                            continue
                        d, ins = dist_to_face(gmsh, gy, P[rows])
                        on = (d <= 1e-5 * diag) & ins
                        if not reported and on.mean() < 0.8:
                            continue
                        t = unique_counts(tri_keys[tri_ent == x])[0]
                        miss = setdiff_count(t, boundary[S2])
                        conf['coincident_pairs'].append({'face': x, 'solid': S1, 'on_face': y, 'of_solid': S2,
                                                         'nodes_on': f'{int(on.sum())}/{len(on)}', 'reported': reported,
                                                         'triangles': int(len(t)), 'not_on_other_solid': miss})
                        if miss:
                            conf['failures'].append(f'Face{x} of solid {S1} lies on Face{y} of solid {S2}: {miss} of '
                                                    f'its {len(t)} triangles are not faces of solid {S2}\'s tets')
    # triangles bounding two solids, and coincident distinct nodes among the tets' nodes
    inter = 0
    for i, A in enumerate(sol):
        for B in sol[i + 1:]:
            inter += int(len(boundary[A]) + len(boundary[B]) - len(unique_counts(np.concatenate([boundary[A], boundary[B]]))[0]))
    conf['interface_triangles'] = inter
    used = np.unique(T.ravel())
    try:
        from scipy.spatial import cKDTree
        conf['coincident_nodes'] = int(len(cKDTree(P[used]).query_pairs(1e-9 * diag)))
    except ImportError:
        key = np.round(P[used] / (1e-9 * diag)).astype(np.int64)
        conf['coincident_nodes'] = int(len(key) - len(np.unique(key, axis=0)))
    if conf['coincident_nodes']:
        conf['failures'].append(f"{conf['coincident_nodes']} pairs of distinct tet nodes at the same point")
    contact = bool(conf['shared_faces'] or conf['coincident_pairs'] or inter)
    conf['contact'] = contact
    conf['ok'] = not conf['failures']
    out['conformity'] = conf
    return out


# ----------------------------------------------------------------------------------------- running

def tail(s, n=300):
    s = (s or '').strip()
    return s[-n:].replace('\n', ' | ')


def run_paramesh(exe, model, h, msh, rep, timeout):
    for p in (msh, rep):
        if os.path.exists(p):
            os.remove(p)
    cmd = [exe, 'mesh', model, '-o', msh, '--volume', '--size', repr(h), '--report', rep]
    r = {'cmd': ' '.join(cmd), 'load_before': os.getloadavg()[0]}
    t0 = time.perf_counter()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        r.update(ok=False, error=f'timed out after {timeout} s', seconds=None)
        return r, None
    r['seconds'] = time.perf_counter() - t0
    r['exit'] = p.returncode
    report = None
    if os.path.exists(rep):
        try:
            report = json.load(open(rep))
        except Exception as e:
            r['report_error'] = str(e)
    if report:
        r['report_seconds'] = report.get('seconds')
        r['status'] = report.get('status')
        bad = [s for s in report.get('volume', {}).get('solids', []) if not s.get('ok')]
        if bad:
            r['solid_errors'] = [f"solid {s['solid']}: {s.get('error', 'failed')}" for s in bad]
    r['ok'] = p.returncode == 0 and os.path.exists(msh) and not r.get('solid_errors')
    if not r['ok']:
        why = [f'exit {p.returncode}']
        if r.get('solid_errors'):
            why += r['solid_errors']
        lines = [l for l in p.stderr.strip().splitlines() if l.strip()]
        if lines:
            why.append(tail(lines[-1], 240))
        if not os.path.exists(msh):
            why.append('no mesh written')
        r['error'] = '; '.join(why)
    return r, report


def run_gmsh(model, h, msh, timeout):
    if os.path.exists(msh):
        os.remove(msh)
    r = {'load_before': os.getloadavg()[0]}
    t0 = time.perf_counter()
    try:
        p = subprocess.run([PY, '-c', GMSH_SCRIPT, model, repr(h), msh], capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        r.update(ok=False, error=f'timed out after {timeout} s', seconds=None)
        return r
    r['process_seconds'] = time.perf_counter() - t0
    r['exit'] = p.returncode
    res = None
    for l in p.stdout.splitlines():
        if l.startswith('RESULT '):
            res = json.loads(l[7:])
    if res is None:
        r.update(ok=False, seconds=None, error=f'exit {p.returncode}: {tail(p.stderr or p.stdout, 240)}')
        return r
    r.update(res)
    if not res.get('ok'):
        r['seconds'] = None
        errs = '; '.join(res.get('log_errors') or [])
        r['error'] = tail(res.get('error', '') + ('; ' + errs if errs and errs not in res.get('error', '') else ''), 300)
    return r


# ----------------------------------------------------------------------------------------- the table

def f(v, fmt='{:.2f}', none='-'):
    if v is None:
        return none
    return fmt.format(v)


def pair(p, g, key, fmt='{:.2f}'):
    return f"{f(p.get(key), fmt) if p else '-'} / {f(g.get(key), fmt) if g else '-'}"


def worst_error(m):
    """The signed volume error % of the solid whose |error| is largest."""
    e = [v['volume_error_pct'] for v in (m.get('solids') or {}).values() if v.get('volume_error_pct') is not None]
    return max(e, key=abs) if e else None


def slivers(m):
    if m.get('pct_dihedral_lt_10') is None:
        return '-'
    return f"{m['pct_dihedral_lt_10']:.3f} ({m['tets_dihedral_lt_10']})"


def summary(rows):
    """One paragraph of counts over the rows where both meshers produced a measured mesh."""
    both = [r for r in rows if (r.get('paramesh') or {}).get('ok') and (r.get('gmsh') or {}).get('ok')
            and (r.get('paramesh_mesh') or {}).get('tets') and (r.get('gmsh_mesh') or {}).get('tets')]
    if not both:
        return ''
    rat = sorted(r['paramesh']['seconds'] / r['gmsh']['seconds'] for r in both)
    prat = sorted(r['paramesh']['seconds'] / r['gmsh']['process_seconds'] for r in both)
    med = lambda v: v[len(v) // 2] if len(v) % 2 else 0.5 * (v[len(v) // 2 - 1] + v[len(v) // 2])
    sl = [(r['paramesh_mesh']['tets_dihedral_lt_10'], r['gmsh_mesh']['tets_dihedral_lt_10']) for r in both]
    md = [(r['paramesh_mesh']['min_dihedral'], r['gmsh_mesh']['min_dihedral']) for r in both]
    rr = [(r['paramesh_mesh']['mean_radius_ratio'], r['gmsh_mesh']['mean_radius_ratio']) for r in both]
    chk = [r for r in both if (r.get('checks') or {}).get('boundary_ok')
           and (r['checks'].get('conformity') or {}).get('ok')
           and r['paramesh_mesh']['inverted'] == 0 and r['paramesh_mesh']['over_shared_faces'] == 0]
    return (f"\nOver the {len(both)} rows meshed by both: seconds ParaMesh / Gmsh median {med(rat):.2f} "
            f"({rat[0]:.2f} to {rat[-1]:.2f}; ParaMesh faster in {sum(x < 1 for x in rat)}); against Gmsh's whole "
            f"process (G process s) median {med(prat):.2f} ({prat[0]:.2f} to {prat[-1]:.2f}; ParaMesh faster in "
            f"{sum(x < 1 for x in prat)}). Tets with a dihedral < 10°: ParaMesh fewer in "
            f"{sum(p < g for p, g in sl)}, Gmsh fewer in {sum(g < p for p, g in sl)}, equal in "
            f"{sum(p == g for p, g in sl)} (counts); min dihedral higher for ParaMesh in {sum(p > g for p, g in md)}, "
            f"for Gmsh in {sum(g > p for p, g in md)}; mean radius ratio higher for ParaMesh in "
            f"{sum(p > g for p, g in rr)}, for Gmsh in {sum(g > p for p, g in rr)}. ParaMesh checks (boundary == "
            f"surface, conformal, no inverted, no over-shared face) pass in {len(chk)} of {len(both)}.\n")


def render(rows, skipped):
    hdr = ('| model | D | H | tets P / G | min dihedral ° P / G | % (count) tets < 10° P / G | radius ratio P / G '
           '| inverted P / G | over-shared faces P / G | vol err % P / G | P boundary == surface | P conformal '
           '| seconds P / G | P/G | notes |\n'
           '|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n')
    out = hdr
    for r in rows:
        pm, gm = r.get('paramesh_mesh') or {}, r.get('gmsh_mesh') or {}
        pr, gr = r.get('paramesh') or {}, r.get('gmsh') or {}
        chk = r.get('checks') or {}
        notes = []
        if not pr.get('ok'):
            notes.append('ParaMesh failed: ' + str(pr.get('error')))
        if not gr.get('ok'):
            notes.append('Gmsh failed: ' + str(gr.get('error')))
        for who, m in (('ParaMesh', pm), ('Gmsh', gm)):
            if m.get('measure_error'):
                notes.append(f"{who} mesh not measured: {m['measure_error']}")
            if m.get('solids_without_tets'):
                notes.append(f"{who}: solids without tets {m['solids_without_tets']}")
        if chk.get('check_error'):
            notes.append('checks not run: ' + chk['check_error'])
        if chk.get('face_numbering_mismatches'):
            notes.append(f"ParaMesh faces not on the gmsh face of that number: {chk['face_numbering_mismatches']}")
        if chk.get('faces_differ_from_report'):
            notes.append(f"report's face lists differ from OpenCASCADE's for solids {chk['faces_differ_from_report']}")
        if 'solids' in chk:
            bad = {s: v for s, v in chk['solids'].items() if not v['ok']}
            bnd = 'yes' if chk.get('boundary_ok') else 'NO'
            for s, v in bad.items():
                notes.append(f"solid {s}: {v['boundary_not_surface']} boundary faces not surface triangles, "
                             f"{v['surface_not_boundary']} surface triangles not boundary faces, "
                             f"{v['faces_used_3_or_more_in_solid']} faces in 3+ tets (of {v['boundary_faces']} / "
                             f"{v['surface_triangles']})")
            c = chk['conformity']
            if len(chk['solids']) < 2:
                conf = 'n/a (1 solid)'
            elif not c['ok']:
                conf = 'NO'
                notes += c['failures']
            elif c['contact']:
                conf = f"yes ({c['interface_triangles']} interface tris)"
            else:
                conf = 'yes (solids do not touch)'
        else:
            bnd = conf = '-'
        ps, gs = pr.get('seconds') if pr.get('ok') else None, gr.get('seconds') if gr.get('ok') else None
        ratio = f(ps / gs) if ps and gs else '-'
        vp, vg = worst_error(pm), worst_error(gm)
        out += (f"| {r['model']} | {r['divisor']} | {r['h']:.4g} | {pm.get('tets', '-')} / {gm.get('tets', '-')} "
                f"| {pair(pm, gm, 'min_dihedral')} | {slivers(pm)} / {slivers(gm)} "
                f"| {pair(pm, gm, 'mean_radius_ratio', '{:.3f}')} | {pm.get('inverted', '-')} / {gm.get('inverted', '-')} "
                f"| {pm.get('over_shared_faces', '-')} / {gm.get('over_shared_faces', '-')} "
                f"| {f(vp, '{:.3f}')} / {f(vg, '{:.3f}')} | {bnd} | {conf} | {f(ps)} / {f(gs)} | {ratio} "
                f"| {'; '.join(notes).replace('|', '/')} |\n")
    out += ('\nSeconds in detail (ParaMesh: whole process, then its report\'s total split into the surface '
            '(total - volume) and the volume stage; Gmsh: CAD load, generate(3), write, whole process incl. '
            'starting Python and importing gmsh), surface triangles in each file, and the 1-minute load average '
            'just before each run:\n\n'
            '| model | D | surface tris P / G | P process s | P surface s | P volume s | P volume s per solid '
            '| G load s | G mesh s | G write s | G process s | load avg before P / G |\n'
            '|---|---|---|---|---|---|---|---|---|---|---|---|\n')
    for r in rows:
        pm, gm = r.get('paramesh_mesh') or {}, r.get('gmsh_mesh') or {}
        pr, gr = r.get('paramesh') or {}, r.get('gmsh') or {}
        rs = pr.get('report_seconds') or {}
        surf = rs['total'] - rs.get('volume', 0) if 'total' in rs else None
        ss = (r.get('paramesh_report_volume') or {}).get('solid_seconds') or {}
        per_solid = ' / '.join(f(v) for _, v in sorted(ss.items(), key=lambda kv: int(kv[0]))) or '-'
        out += (f"| {r['model']} | {r['divisor']} | {pm.get('triangles', '-')} / {gm.get('triangles', '-')} "
                f"| {f(pr.get('seconds'))} | {f(surf)} | {f(rs.get('volume'))} | {per_solid} | {f(gr.get('load_s'))} "
                f"| {f(gr.get('mesh_s'))} | {f(gr.get('write_s'))} | {f(gr.get('process_seconds'))} "
                f"| {f(pr.get('load_before'))} / {f(gr.get('load_before'))} |\n")
    out += summary(rows)
    if skipped:
        out += '\nNot in the table (no solid in the CAD as OpenCASCADE reads it): ' + ', '.join(
            f'{m} ({why})' for m, why in skipped) + '.\n'
    return out


def write_out(path, table, meta):
    block = '<!-- table:begin -->\n' + meta + '\n' + table + '<!-- table:end -->\n'
    if os.path.exists(path):
        lines = open(path).read().split('\n')
        # the markers count only as lines of their own (the page may name them in its text)
        a = next((i for i, l in enumerate(lines) if l.strip() == '<!-- table:begin -->'), None)
        b = next((i for i, l in enumerate(lines) if l.strip() == '<!-- table:end -->' and a is not None and i > a), None)
        if a is not None and b is not None:
            text = '\n'.join(lines[:a]) + ('\n' if a else '') + block + '\n'.join(lines[b + 1:])
            open(path, 'w').write(text)
            return
    open(path, 'w').write('# Volume meshes: ParaMesh --volume vs Gmsh 4.8.4\n\nWritten by bench/volume_vs_gmsh.py '
                          '(its docstring explains every column).\n\n' + block)


# ----------------------------------------------------------------------------------------- main

def git_head():
    try:
        return subprocess.check_output(['git', '-C', ROOT, 'rev-parse', '--short', 'HEAD'], text=True).strip()
    except Exception:
        return '?'


def binary_id(exe):
    import hashlib
    try:
        h = hashlib.sha256(open(exe, 'rb').read()).hexdigest()[:12]
        return f"{exe} (sha256 {h}, built {time.strftime('%Y-%m-%d %H:%M', time.localtime(os.path.getmtime(exe)))})"
    except OSError as e:
        return f'{exe} ({e})'


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--models', nargs='*', default=None,
                    help='model files (names in /work/shared/models or paths; commas also separate); default: all')
    ap.add_argument('--divisors', default='50,100', help='H = bounding-box diagonal / D for each D (comma list)')
    ap.add_argument('--out', default=os.path.join(ROOT, 'docs', 'volume_benchmark.md'))
    ap.add_argument('--work', default='/tmp/volume_vs_gmsh', help='directory for the meshes and reports')
    ap.add_argument('--json', default=None, help='all results (default WORK/results.json)')
    ap.add_argument('--timeout', type=float, default=600, help='seconds per mesher run')
    ap.add_argument('--paramesh', default=os.path.join(ROOT, 'build', 'bin', 'paramesh'))
    ap.add_argument('--render', default=None, help='re-render the table of a saved results.json, no meshing')
    a = ap.parse_args()
    if a.render:
        saved = json.load(open(a.render))
        table = render(saved['rows'], saved['skipped'])
        print(table)
        write_out(a.out, table, saved['meta'])
        return
    os.makedirs(a.work, exist_ok=True)
    jpath = a.json or os.path.join(a.work, 'results.json')
    if a.models:
        names = [m for x in a.models for m in x.split(',') if m]
    else:
        names = sorted(x for x in os.listdir(MODELS) if x.lower().endswith(CAD_EXT))
    divisors = [int(x) for x in a.divisors.split(',') if x]
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber('General.Terminal', 0)
    rows, skipped = [], []
    t_start = time.time()
    meta = (f"Run {time.strftime('%Y-%m-%d %H:%M', time.localtime(t_start))}, ParaMesh {binary_id(a.paramesh)} "
            f"(tree at {git_head()}), Gmsh {gmsh.option.getString('General.Version')}, {os.cpu_count()} CPUs, divisors {a.divisors}, "
            f"time-out {a.timeout:g} s.\n")

    def save():
        json.dump({'meta': meta, 'rows': rows, 'skipped': skipped}, open(jpath, 'w'), indent=1, default=str)

    for name in names:
        path = name if os.path.isabs(name) or os.path.exists(name) else os.path.join(MODELS, name)
        base = os.path.basename(path)
        try:
            cad = load_cad(gmsh, path)
        except Exception as e:
            for D in divisors:
                rows.append({'model': base, 'divisor': D, 'h': float('nan'),
                             'paramesh': {'ok': False, 'error': 'not run (no H: the CAD did not load)'},
                             'gmsh': {'ok': False, 'error': f'CAD not loaded by gmsh/OCC: {e}'}})
            save()
            continue
        if not cad['solids']:
            skipped.append((base, f"{cad['faces']} faces, no solid"))
            print(f'{base}: no solid, skipped', flush=True)
            save()
            continue
        cad_vol = {s: v['volume'] for s, v in cad['solids'].items()}
        for D in divisors:
            h = cad['diagonal'] / D
            stem = os.path.join(a.work, f'{os.path.splitext(base)[0]}_d{D}')
            row = {'model': base, 'divisor': D, 'h': h, 'diagonal': cad['diagonal'],
                   'cad_solids': {s: {'faces': len(v['faces']), 'volume': v['volume']} for s, v in cad['solids'].items()}}
            pmsh, prep, gmsh_msh = stem + '_paramesh.msh', stem + '_paramesh.json', stem + '_gmsh.msh'
            pr, report = run_paramesh(a.paramesh, path, h, pmsh, prep, a.timeout)
            row['paramesh'] = pr
            if report and 'volume' in report:
                row['paramesh_report_volume'] = {k: v for k, v in report['volume'].items() if k != 'solids'}
                row['paramesh_report_volume']['solid_seconds'] = {s['solid']: s.get('seconds')
                                                                  for s in report['volume'].get('solids', [])}
            gr = run_gmsh(path, h, gmsh_msh, a.timeout)
            row['gmsh'] = gr
            for who, mp in (('paramesh', pmsh), ('gmsh', gmsh_msh)):
                if not os.path.exists(mp):
                    continue
                try:
                    m, msh, T, TE = measure(mp, cad_vol)
                    row[who + '_mesh'] = m
                    if who == 'paramesh' and len(T):
                        try:
                            row['checks'] = paramesh_checks(gmsh, cad, msh, T, TE, report, h)
                        except Exception as e:
                            row['checks'] = {'check_error': f'{type(e).__name__}: {e}'}
                    if not len(T) and row[who].get('ok'):
                        row[who]['ok'] = False
                        row[who]['error'] = 'no tetrahedra in the mesh'
                    del msh, T, TE
                except Exception as e:
                    row[who + '_mesh'] = {'measure_error': f'{type(e).__name__}: {e}'}
            rows.append(row)
            save()
            pm, gm = row.get('paramesh_mesh', {}), row.get('gmsh_mesh', {})
            print(f"{base} D={D} H={h:.4g}: ParaMesh {pm.get('tets')} tets min {f(pm.get('min_dihedral'))} "
                  f"<10 {f(pm.get('pct_dihedral_lt_10'), '{:.3f}')}% {f(pr.get('seconds'))} s "
                  f"{'' if pr.get('ok') else 'FAILED ' + str(pr.get('error'))}| Gmsh {gm.get('tets')} tets min "
                  f"{f(gm.get('min_dihedral'))} <10 {f(gm.get('pct_dihedral_lt_10'), '{:.3f}')}% {f(gr.get('seconds'))} s "
                  f"{'' if gr.get('ok') else 'FAILED ' + str(gr.get('error'))}", flush=True)
    gmsh.finalize()
    loads = [r[w]['load_before'] for r in rows for w in ('paramesh', 'gmsh') if 'load_before' in r.get(w, {})]
    if loads:
        meta += (f"1-minute load average before each run: {min(loads):.2f} to {max(loads):.2f}; whole run "
                 f"{(time.time() - t_start) / 60:.0f} min.\n")
    save()
    table = render(rows, skipped)
    print(table)
    write_out(a.out, table, meta)


if __name__ == '__main__':
    main()
