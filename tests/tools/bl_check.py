#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""ParaMesh's boundary-layer checker: measures the rows of quads grown from CAD edges.

Usage:
  bl_check.py CAD MESH --edges 21,6 --first-height H0 --growth R --layers N
              [--json] [--verbose] [--nodes auto|tags|cad] [--tol T]
              [--require [--max-height-err 0.02] [--max-growth-err 0.02] [--min-full 95]
                         [--min-ortho 75] [--max-jump 1.5] [--max-inverted 0]]

MESH is a Gmsh MSH 4.1 file (read with meshio): triangles are the isotropic mesh, quads are the
boundary-layer (BL) rows, line elements are the CAD edges' segments (entity tag = 1-based FreeCAD
edge number) and every node carries the CAD entity it lies on (dim 0/1/2, tag).

What is measured
  base nodes   the mesh nodes on the BL edges: from the node entity tags and line elements of the
               MSH file (`--nodes tags`: exact for ParaMesh's own meshes), or geometrically, the
               nodes within --tol (default 0.05 * H0) of the CAD edges with FreeCAD's distToShape
               (`--nodes cad`: works on any mesh). `auto`: tags when the file has them.
  column       a stack of quads over one mesh segment of a BL edge, walked upward row by row
               across each quad's top edge (a fan column at a reflex corner starts with the fan
               triangle at the corner). It ends at a triangle (the isotropic hand-off), at the
               face boundary, or where the next quad touches a BL edge again (another layer).
  height       of a row: the mean of the quad's two side lengths (straight 3D lengths).
  first height the first row's height; error = |h_1 - H0| / H0.
  growth       h_(k+1) / h_k between consecutive rows; error = max |g - R| / R over the column.
  layers       rows reached; a column is full when it has N rows.
  orthogonality the angle between a column's first side segment and the edge tangent at its base
               node (90 = orthogonal); sides standing on a CAD vertex (the end columns, which run
               along the neighbouring edge, and corners) are left out. The tangent comes from the CAD
               edge (FreeCAD) when available, else from the edge's mesh segments.
  jump         the size jump at the hand-off: the height of the triangle standing on the column's
               top edge (2 area / top length) against the last row's height, max(t/h, h/t).
  mesh checks  every mesh edge used by 1 or 2 elements (triangles and quads), edges used once only
               on CAD edges that are free (all their segments used once), neighbours in one face
               traversing their shared edge in opposite directions, and quads convex and facing
               like the surface normal: the CAD face normal (FreeCAD) when available, else the
               normals of the neighbouring elements of the same face.

Height and growth errors for --require are taken over the full columns (partial columns are
listed with their stop reason); fan columns are measured apart (their first row is a triangle).
Exit status: 0 ok, 1 a --require threshold failed, 2 bad input.
Needs numpy and meshio; FreeCAD (Part) only for --nodes cad and CAD normals/tangents.
Run with Debian's /usr/bin/python3.
"""
import argparse
import json
import os
import sys

import numpy as np

# The measures live in three modules beside this one; bl_check stays the checker's one public
# module (tests import it as `bl_check`), so the names they use are re-exported here.
from bl_mesh import FREECAD_LIB, CadModel, SurfMesh, import_part, read_shape  # noqa: F401
from bl_columns import (base_nodes_from_cad, base_nodes_from_tags, cad_tangents, corner_fans,  # noqa: F401
                        end_columns, measure_columns, mesh_tangents, rising_sides, vertex_nodes,
                        walk_columns)
from bl_quality import (cad_quad_normals, conformity, element_normals, handoff_triangles,  # noqa: F401
                        quad_validity)


# ----------------------------------------------------------------------------------------------
# The whole check

def _stats(v):
    v = [x for x in v if x is not None]
    if not v:
        return {"n": 0, "min": None, "max": None, "mean": None}
    a = np.asarray(v, float)
    return {"n": int(len(a)), "min": float(a.min()), "max": float(a.max()), "mean": float(a.mean())}


def check(mesh, edges, first_height, growth, layers, cad=None, nodes="auto", tol=None, normals="auto",
          tangents="auto"):
    """Measures the BL columns grown from `edges` (1-based CAD edges) in `mesh` (a SurfMesh).
    cad: a CadModel, a Part.Shape or a path (optional; needed for nodes='cad'). Returns a dict
    (JSON-serialisable) with the summary, and the per-column list under '_columns'."""
    if isinstance(edges, int):
        edges = [edges]
    edges = [int(e) for e in edges]
    if first_height <= 0 or growth <= 0 or layers < 1:
        raise ValueError("first_height and growth must be > 0 and layers >= 1")
    tol = 0.05 * first_height if tol is None else tol
    if cad is not None and not isinstance(cad, CadModel):
        cad = CadModel(read_shape(cad))
    if nodes == "auto":
        nodes = "tags" if (len(mesh.segments) or (mesh.node_dim >= 0).any()) else "cad"
    if nodes == "tags":
        on = base_nodes_from_tags(mesh, edges)
    elif nodes == "cad":
        if cad is None:
            raise ValueError("--nodes cad needs the CAD model and FreeCAD")
        on = base_nodes_from_cad(mesh, cad, edges, tol)
    else:
        raise ValueError(f"nodes must be auto, tags or cad, got {nodes!r}")
    if not on:
        raise ValueError(f"no mesh node lies on the edges {edges}")
    verts = vertex_nodes(mesh, on, cad if nodes == "cad" else None, tol)
    use_cad_t = cad is not None and tangents in ("auto", "cad")
    T = cad_tangents(cad, mesh, on) if use_cad_t else mesh_tangents(mesh, on)
    cols = walk_columns(mesh, on)
    measure_columns(mesh, cols, on, verts, T, first_height, growth, layers)
    reg = [c for c in cols if c["kind"] == "quad"]
    fan = [c for c in cols if c["kind"] == "fan"]
    full = [c for c in reg if c["full"]]
    use_cad_n = cad is not None and normals in ("auto", "cad")
    ends = end_columns(mesh, cols, verts)
    out = {
        "mesh": mesh.name,
        "edges": edges,
        "first_height": first_height, "growth": growth, "layers": layers,
        "node_source": nodes, "tangent_source": "cad" if use_cad_t else "mesh",
        "normal_source": "cad" if use_cad_n else "mesh",
        "base_nodes": len(on), "vertex_nodes": len(verts),
        "columns": len(reg), "fan_columns": len(fan), "full_columns": len(full),
        "pct_full": 100.0 * len(full) / len(reg) if reg else 0.0,
        "faces": {str(f): sum(1 for c in reg if c["face"] == f) for f in sorted({c["face"] for c in reg})},
        "layers_reached": _stats([c["layers"] for c in reg]),
        "first_height_measured": _stats([c["first_height"] for c in reg]),
        "height_err_full": _stats([c["height_err"] for c in full]),
        "height_err_all": _stats([c["height_err"] for c in reg]),
        "growth_measured": _stats([g for c in reg for g in c["growth"]]),
        "growth_err_full": _stats([c["growth_err"] for c in full]),
        "growth_err_all": _stats([c["growth_err"] for c in reg]),
        "row_err_full": _stats([c["row_err"] for c in full]),
        "ortho_deg": _stats([c["ortho"] for c in reg]),
        "base_angle_deg": _stats([c["base_angle"] for c in reg]),
        "ortho_whole_deg": _stats([c["ortho_whole"] for c in reg]),
        "jump": _stats([c["jump"] for c in reg + fan]),
        "handoff_triangles": handoff_triangles(mesh),
        "stops": {s: sum(1 for c in reg if c["stop"] == s and not c["full"]) for s in
                  sorted({c["stop"] for c in reg if not c["full"]})},
        "fan": {"columns": len(fan), "layers": _stats([c["layers"] for c in fan]),
                "first_height": _stats([c["first_height"] for c in fan]),
                "corners": corner_fans(mesh, cols)},
        "end_columns": [{k: v for k, v in e.items() if k != "nodes"} for e in ends],
        "conformity": conformity(mesh),
        "quads": quad_validity(mesh, cad if use_cad_n else None),
        "_columns": cols,
        "_vertices": verts,
        "_base": on,
        "_ends": ends,
        "_mesh": mesh,
    }
    return out


def requirements(res, max_height_err=0.02, max_growth_err=0.02, min_full=95.0, min_ortho=75.0, max_jump=1.5,
                 max_inverted=0, conformal=True):
    """The failed requirements as a list of strings (empty when all hold)."""
    fails = []
    he = res["height_err_full"]["max"]
    if he is None or he > max_height_err:
        fails.append(f"first height error {he} > {max_height_err} on a full column")
    ge = res["growth_err_full"]["max"]
    if ge is None or ge > max_growth_err:
        fails.append(f"growth error {ge} > {max_growth_err} on a full column")
    if res["pct_full"] < min_full:
        fails.append(f"full columns {res['pct_full']:.1f}% < {min_full}%")
    om = res["ortho_deg"]["min"]
    if om is not None and om < min_ortho:
        fails.append(f"orthogonality {om:.1f} deg < {min_ortho}")
    jm = res["jump"]["max"]
    if jm is not None and jm > max_jump:
        fails.append(f"hand-off jump {jm:.2f} > {max_jump}")
    if res["quads"]["inverted"] > max_inverted:
        fails.append(f"{res['quads']['inverted']} inverted quads > {max_inverted}")
    if conformal and not res["conformity"]["ok"]:
        fails.append(f"mesh not conformal: {json.dumps(res['conformity'])}")
    return fails


def worst_columns(res, count=5):
    """The worst columns for each measure, as printable lines."""
    cols = [c for c in res["_columns"] if c["kind"] == "quad"]
    lines = []

    def where(c):
        x, y, z = c["where"]
        return f"Face{c['face']} at ({x:.4g}, {y:.4g}, {z:.4g}), {c['layers']} rows, stop {c['stop']}"

    for title, key, rev, only in (("first height error", "height_err", True, True),
                                  ("growth error", "growth_err", True, True),
                                  ("orthogonality (deg)", "ortho", False, False),
                                  ("hand-off jump", "jump", True, False),
                                  ("layers", "layers", False, False)):
        pool = [c for c in cols if c[key] is not None and (c["full"] or not only)]
        pool.sort(key=lambda c: c[key], reverse=rev)
        lines.append(f"worst {title}:")
        for c in pool[:count]:
            lines.append(f"  {c[key]:.4g}  {where(c)}")
    return lines


def summary_json(res):
    return {k: v for k, v in res.items() if not k.startswith("_")}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[1:]))
    ap.add_argument("cad", help="the CAD model (STEP/IGES/BREP); '-' for none (tags only)")
    ap.add_argument("mesh", help="the mesh (Gmsh MSH 4.1)")
    ap.add_argument("--edges", required=True, help="BL edges, 1-based FreeCAD numbers: 21,6")
    ap.add_argument("--first-height", type=float, required=True)
    ap.add_argument("--growth", type=float, required=True)
    ap.add_argument("--layers", type=int, required=True)
    ap.add_argument("--nodes", choices=("auto", "tags", "cad"), default="auto",
                    help="how the base nodes are found (default: tags when the file has them)")
    ap.add_argument("--tol", type=float, default=None, help="distance to a CAD edge (default 0.05 * first height)")
    ap.add_argument("--no-cad", action="store_true", help="do not load the CAD (mesh tangents and normals)")
    ap.add_argument("--json", action="store_true", help="print the summary as JSON")
    ap.add_argument("--verbose", "-v", action="store_true", help="also print the worst columns")
    ap.add_argument("--require", action="store_true", help="exit 1 when a threshold below fails")
    ap.add_argument("--max-height-err", type=float, default=0.02)
    ap.add_argument("--max-growth-err", type=float, default=0.02)
    ap.add_argument("--min-full", type=float, default=95.0)
    ap.add_argument("--min-ortho", type=float, default=75.0)
    ap.add_argument("--max-jump", type=float, default=1.5)
    ap.add_argument("--max-inverted", type=int, default=0)
    a = ap.parse_args(argv)
    try:
        edges = [int(x.strip().removeprefix("Edge")) for x in a.edges.split(",") if x.strip()]
        if not os.path.isfile(a.mesh):
            raise ValueError(f"cannot read the mesh {a.mesh!r}: no such file")
        try:
            mesh = SurfMesh.from_msh(a.mesh)
        except (Exception, SystemExit) as e:  # meshio raises ReadError or calls sys.exit(1)
            raise ValueError(f"cannot read the mesh {a.mesh!r}: {e}") from e
        cad = None
        if a.cad != "-" and not a.no_cad:
            if import_part() is None:
                if a.nodes == "cad":
                    raise ValueError("--nodes cad needs FreeCAD")
                print("note: FreeCAD not available, using mesh tangents and normals", file=sys.stderr)
            else:
                cad = CadModel(read_shape(a.cad))
        res = check(mesh, edges, a.first_height, a.growth, a.layers, cad=cad, nodes=a.nodes, tol=a.tol)
    except (OSError, ValueError, RuntimeError) as e:
        print(f"bl_check: {e}", file=sys.stderr)
        return 2
    fails = requirements(res, a.max_height_err, a.max_growth_err, a.min_full, a.min_ortho, a.max_jump,
                         a.max_inverted) if a.require else []
    if a.json:
        out = summary_json(res)
        if a.require:
            out["failed_requirements"] = fails
        print(json.dumps(out, indent=1))
    else:
        print(format_text(res))
        for f in fails:
            print("FAIL:", f)
    if a.verbose:
        for line in worst_columns(res):
            print(line, file=sys.stderr if a.json else sys.stdout)
    return 1 if fails else 0


def _fmt(s, f="{:.4g}"):
    if s["n"] == 0:
        return "-"
    return f"min {f.format(s['min'])}  max {f.format(s['max'])}  mean {f.format(s['mean'])}"


def format_text(res):
    c, q, t = res["conformity"], res["quads"], res["handoff_triangles"]
    fans = ", ".join("({:.4g}, {:.4g}, {:.4g}): {}".format(*f["xyz"], f["columns"]) for f in res["fan"]["corners"])
    along = ", ".join(f"Face{e['face']} along Edge{e['along_edge']} ({e['rows']} rows)"
                      for e in res["end_columns"] if e["along_edge"])
    corner_sides = sum(1 for e in res["end_columns"] if not e["along_edge"])
    min_angle = "-" if t["min_angle"] is None else f"{t['min_angle']:.2f}"
    lines = [
        f"{res['mesh']}: BL on edges {res['edges']} (h0 {res['first_height']}, r {res['growth']}, "
        f"N {res['layers']}); nodes from {res['node_source']}, tangents {res['tangent_source']}, "
        f"normals {res['normal_source']}",
        f"  columns {res['columns']} (+{res['fan_columns']} fan), full {res['full_columns']} "
        f"({res['pct_full']:.1f}%), per face {res['faces']}",
        f"  layers reached      {_fmt(res['layers_reached'], '{:.0f}')}",
        f"  first height        {_fmt(res['first_height_measured'])}",
        f"  height error (full) {_fmt(res['height_err_full'], '{:.2e}')}",
        f"  growth              {_fmt(res['growth_measured'])}",
        f"  growth error (full) {_fmt(res['growth_err_full'], '{:.2e}')}",
        f"  orthogonality (deg) {_fmt(res['ortho_deg'], '{:.2f}')}  (to the edge tangent)",
        f"  base angle (deg)    {_fmt(res['base_angle_deg'], '{:.2f}')}  (to the base segment)",
        f"  column tilt (deg)   {_fmt(res['ortho_whole_deg'], '{:.2f}')}  (base-to-top chord to the edge tangent)",
        f"  hand-off jump       {_fmt(res['jump'], '{:.3f}')}",
        f"  partial columns by stop: {res['stops']}",
        f"  triangles touching the layer: {t['n']}, smallest angle {min_angle} deg, {t['below_10']} below 10 deg",
        f"  fan corners: {fans or '-'}",
        f"  end columns along CAD edges: {along or '-'}; {corner_sides} other column sides on CAD vertices",
        f"  mesh edges {c['edges']}: used once {c['used_once']}, twice {c['used_twice']}, more {c['used_more']}; "
        f"free CAD edges {c['free_cad_edges']}; cracked {c['cracked_cad_edges']}; "
        f"orientation mismatches {c['orientation_mismatches']}; conformal {'yes' if c['ok'] else 'NO'}",
        f"  quads {q['quads']}: inverted {q['inverted']} (flipped {q['flipped']}, non-convex {q['nonconvex']}), "
        f"min corner sine {q['min_corner_sine']:.3g}",
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
