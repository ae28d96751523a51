# SPDX-License-Identifier: LGPL-2.1-or-later
"""MeshResult -> FreeCAD Mesh.Mesh / Fem.FemMesh (no GUI).

FreeCAD 0.20.2 traps handled here: FreeCAD must be imported before Part/Mesh/Fem; Mesh.Mesh needs
FreeCAD.Vector points and tuple facets (plain tuples crash it), so meshes are handed over as a
binary STL file, which Mesh reads in C++ (measured: see tests/freecad/test_bridge.py).
"""
import os
import tempfile

import numpy as np


def _freecad():
    import FreeCAD  # noqa: F401  (must come first)
    return FreeCAD


def _triangles_with_quads(result):
    tris = np.asarray(result.triangles, dtype=np.int64)
    quads = np.asarray(result.quads, dtype=np.int64)
    if len(quads):
        tris = np.concatenate([tris, quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    return tris


def result_to_mesh(result):
    """A Mesh.Mesh with the triangles (quads split in two), one segment per CAD face."""
    _freecad()
    import Mesh
    P = np.asarray(result.nodes, dtype=np.float64)
    T = _triangles_with_quads(result)
    faces = np.concatenate([result.triangle_face, result.quad_face, result.quad_face])
    order = np.argsort(faces, kind="stable")  # group facets by CAD face for the segments
    T = T[order]
    faces = faces[order]
    v = P[T]  # (M, 3, 3)
    n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    ln = np.linalg.norm(n, axis=1)
    n = n / np.where(ln > 0, ln, 1)[:, None]
    rec = np.zeros(len(T), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"] = n
    rec["v"] = v
    fd, path = tempfile.mkstemp(suffix=".stl", prefix="paramesh_")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(b"ParaMesh".ljust(80, b" "))
            f.write(np.uint32(len(T)).tobytes())
            f.write(rec.tobytes())
        mesh = Mesh.Mesh(path)
    finally:
        os.remove(path)
    # STL merges coincident points in the same order as the facets: segments map 1:1 to facets
    if mesh.CountFacets == len(T) and len(T):
        bounds = np.flatnonzero(np.diff(faces)) + 1
        starts = np.concatenate([[0], bounds])
        ends = np.concatenate([bounds, [len(T)]])
        for s, e in zip(starts, ends):
            mesh.addSegment(list(range(int(s), int(e))))
    return mesh


_CHUNK = 16384  # rows handed to FemMesh per call burst: short holds of the GIL, and a cancel check


class BuildCancelled(Exception):
    """result_to_femmesh stopped because its cancelled() callback returned True."""


def _chunks(n, cancelled):
    for s in range(0, n, _CHUNK):
        if cancelled is not None and cancelled():
            raise BuildCancelled()
        yield s, min(n, s + _CHUNK)


def _add_rows(fm, rows, first_id, cancelled, add=None):
    """add(row, id) (default fm.addFace) for each row (ids from first_id), a chunk at a time (the
    loop runs inside map, in C; numpy -> list conversion per chunk, so no single call holds the GIL
    for long)."""
    add = add or fm.addFace
    for s, e in _chunks(len(rows), cancelled):
        for _ in map(add, rows[s:e].tolist(), range(first_id + s, first_id + e)):
            pass


#: our tetrahedron (CalculiX C3D4 / C3D10 order: positive volume, mid-nodes ab, bc, ca, ad, bd, cd)
#: -> SMDS's (FemMesh.addVolume): the first two corners swapped, and the mid-nodes with them. The
#: inverse of FreeCAD 0.20's own maps (FemMesh::writeABAQUS and getccxVolumesByFace read SMDS node
#: [1, 0, 2, 3] as C3D4's [0, 1, 2, 3]); tests/freecad/test_volume_fem.py checks the .inp it writes.
SMDS_TETRA4 = [1, 0, 2, 3]
SMDS_TETRA10 = [1, 0, 2, 3, 4, 6, 5, 8, 7, 9]


def smds_tetrahedra(tets):
    """(K, 4) / (K, 10) tetrahedra in our (CalculiX) node order -> the same in SMDS order."""
    tets = np.asarray(tets)
    return tets[:, SMDS_TETRA10 if tets.shape[1] == 10 else SMDS_TETRA4]


def owner_tetrahedra(triangles, tets):
    """(M,) index of the tetrahedron (row of tets, corners in any order) one of whose faces is each
    triangle, -1 where none is. FreeCAD draws a FemMesh with volumes by their faces only, so
    colouring a surface triangle means colouring this tetrahedron."""
    tris = np.sort(np.asarray(triangles, dtype=np.int64).reshape(-1, 3), axis=1)
    tets = np.asarray(tets, dtype=np.int64).reshape(-1, 4)
    if not len(tris) or not len(tets):
        return np.full(len(tris), -1, dtype=np.int64)
    faces = np.sort(tets[:, [[0, 1, 2], [0, 1, 3], [1, 2, 3], [0, 2, 3]]].reshape(-1, 3), axis=1)
    _, inverse = np.unique(np.concatenate([faces, tris]), axis=0, return_inverse=True)
    inverse = inverse.ravel()
    owner = np.full(inverse.max() + 1, -1, dtype=np.int64)
    owner[inverse[:len(faces)]] = np.repeat(np.arange(len(tets)), 4)
    return owner[inverse[len(faces):]]


def _add_groups(fm, keys, first_id, prefix, kind):
    """One group '<prefix><key>' of element type kind per distinct key > 0; element i has id
    first_id + i. One call per group: FemMesh.addGroupElements walks every element of the mesh on
    each call (FreeCAD 0.20), so calls are not split."""
    keys = np.asarray(keys, dtype=np.int64)
    ids = np.arange(first_id, first_id + len(keys))
    order = np.argsort(keys, kind="stable")
    keys, ids = keys[order], ids[order]
    bounds = np.flatnonzero(np.diff(keys)) + 1
    for chunk_k, chunk_ids in zip(np.split(keys, bounds), np.split(ids, bounds)):
        if len(chunk_k) and chunk_k[0] > 0:
            fm.addGroupElements(fm.addGroup(f"{prefix}{int(chunk_k[0])}", kind), chunk_ids.tolist())


def add_result_groups(fm, result):
    """Adds to a FemMesh built from result one face group per CAD face, 'Face<i>', one per
    boundary-layer spec, 'BoundaryLayer<k>', and with tetrahedra one volume group per solid,
    'Solid<i>'."""
    faces = np.concatenate([result.triangle_face, result.quad_face])
    _add_groups(fm, faces, 1, "Face", "Face")
    # one group per boundary-layer spec: BoundaryLayer1, BoundaryLayer2, ... (spec order)
    _add_groups(fm, np.concatenate([result.triangle_layer, result.quad_layer]), 1, "BoundaryLayer", "Face")
    tets = _tetrahedra(result)
    if len(tets):
        _add_groups(fm, result.tetra_solid, len(faces) + 1, "Solid", "Volume")
    # the user's groups (the groups parameter): face groups of surface elements, solid groups of
    # tetrahedra (edge groups live in the mesh files only: the FemMesh holds no segments)
    for name, dim, entities in getattr(result, "groups", None) or []:
        if dim == 2:
            ids = 1 + np.flatnonzero(np.isin(faces, entities))
            kind = "Face"
        elif dim == 3 and len(tets):
            ids = len(faces) + 1 + np.flatnonzero(np.isin(np.asarray(result.tetra_solid), entities))
            kind = "Volume"
        else:
            continue
        if len(ids):
            fm.addGroupElements(fm.addGroup(name, kind), ids.tolist())


def _tetrahedra(result):
    t = getattr(result, "tetrahedra", None)
    return np.zeros((0, 4), dtype=np.int32) if t is None else np.asarray(t)


def result_to_femmesh(result, groups=True, femmesh=None, cancelled=None):
    """A Fem.FemMesh: tria3/quad4 (tria6/quad8 when order 2), node ids = index + 1, element ids
    consecutive (triangles, then quads, then tetrahedra: Tetra4, Tetra10 when order 2), one face
    group per CAD face named 'Face<i>', one per boundary-layer spec named 'BoundaryLayer<k>' and
    one volume group per solid named 'Solid<i>'. With tetrahedra the surface triangles stay in the
    mesh: FreeCAD's CalculiX writer then writes the volumes only (highest dimension) and finds the
    mesh faces of a constraint's CAD face among the triangles (getFacesByFace).

    femmesh: an empty Fem.FemMesh to fill (else a new one). The GUI creates it on its own thread
    and fills it in the meshing worker (groups=False; add_result_groups later, on the GUI thread):
    filling touches only that mesh's own data, while creating or destroying a FemMesh changes
    state shared by all of them (the SMESH generator's mesh maps). Nodes and elements are added in
    short calls, so another Python thread never waits long for the GIL.
    cancelled: a callable polled between chunks; when it returns True, BuildCancelled is raised."""
    _freecad()
    if femmesh is None:
        import Fem
        femmesh = Fem.FemMesh()
    fm = femmesh
    P = np.asarray(result.nodes, dtype=np.float64)
    add_node = fm.addNode
    for s, e in _chunks(len(P), cancelled):
        c = P[s:e]
        for _ in map(add_node, c[:, 0].tolist(), c[:, 1].tolist(), c[:, 2].tolist(), range(s + 1, e + 1)):
            pass
    order2 = int(result.order) == 2
    T = np.asarray(result.triangles, dtype=np.int64) + 1
    Q = np.asarray(result.quads, dtype=np.int64) + 1
    if order2:
        T = np.concatenate([T, np.asarray(result.triangle_mid, dtype=np.int64) + 1], axis=1)
        Q = np.concatenate([Q, np.asarray(result.quad_mid, dtype=np.int64) + 1], axis=1) if len(Q) else Q
    _add_rows(fm, T, 1, cancelled)
    _add_rows(fm, Q, len(T) + 1, cancelled)
    tets = _tetrahedra(result)
    if len(tets):
        _add_rows(fm, smds_tetrahedra(tets.astype(np.int64) + 1), len(T) + len(Q) + 1, cancelled, fm.addVolume)
    if groups:
        add_result_groups(fm, result)
    return fm


def add_constraint_groups(femmesh, result, part_object, constraints):
    """Adds, for each FEM constraint that references faces of part_object, an element group named
    '<ConstraintName>_Faces' holding the mesh faces on those CAD faces. FreeCAD 0.20's CalculiX
    writer looks shell pressure loads up by such groups (meshtools.get_pressure_obj_faces)."""
    faces = np.concatenate([result.triangle_face, result.quad_face]).astype(np.int64)
    ids = np.arange(1, len(faces) + 1)
    for c in constraints:
        refs = getattr(c, "References", None) or []
        wanted = set()
        for obj, subs in refs:
            if obj != part_object:
                continue
            for s in (subs if isinstance(subs, (list, tuple)) else [subs]):
                if s.startswith("Face") and s[4:].isdigit():
                    wanted.add(int(s[4:]))
        if not wanted:
            continue
        sel = ids[np.isin(faces, list(wanted))]
        g = femmesh.addGroup(f"{c.Name}_Faces", "Face")
        femmesh.addGroupElements(g, sel.tolist())
