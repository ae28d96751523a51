#!/usr/bin/env python3
"""Issue 36's measurement: every model tessellated by FreeCAD's MeshPart (linear deflection 5e-4 of
the diagonal, angular 0.5 rad), the binary STL remeshed by ParaMesh at diagonal / 100 and checked
against the ORIGINAL CAD: meshcheck.py (conformity, per-solid closure, quality), the distance of
1500 sampled nodes to the whole CAD shape (meshcheck judges nodes by the face of their MSH entity,
which for discrete input is a patch, not a CAD face), beside Gmsh 4.8.4 Frontal's mesh of the CAD
at the same h (gmsh_baseline.py).

    /usr/bin/python3 bench/discrete_vs_gmsh.py [MODEL ...] [--work DIR] [--paramesh EXE] [--angular 0.5]
"""
import argparse
import glob
import json
import os
import subprocess
import sys

sys.path.append("/usr/lib/freecad-python3/lib")
import numpy as np  # noqa: E402
import FreeCAD  # noqa: E402,F401
import Part  # noqa: E402
import MeshPart  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(os.path.dirname(ROOT), "shared")


def meshcheck(model, mesh, h, samples=4000):
    p = subprocess.run([sys.executable, os.path.join(SHARED, "tools", "meshcheck.py"), model, mesh, "--size", str(h),
                        "--samples", str(samples)],
                       capture_output=True, text=True, timeout=1800)
    try:
        return json.loads(p.stdout[p.stdout.index("{"):])
    except ValueError:
        return {"error": (p.stderr or p.stdout)[-300:]}


def node_deviation(shape, mesh):
    import meshio
    m = meshio.read(mesh)
    tri = np.vstack([c.data for c in m.cells if c.type == "triangle"])
    P = m.points[np.unique(tri)]
    pick = np.random.default_rng(0).choice(len(P), size=min(1500, len(P)), replace=False)
    return max(Part.Vertex(FreeCAD.Vector(*P[i])).distToShape(shape)[0] for i in pick)


def run(model, work, exe, angular):
    name = os.path.splitext(os.path.basename(model))[0]
    shape = Part.Shape()
    shape.read(model)
    diag = shape.BoundBox.DiagonalLength
    defl, h = 5e-4 * diag, diag / 100
    mesh = MeshPart.meshFromShape(Shape=shape, LinearDeflection=defl, AngularDeflection=angular, Relative=False)
    stl = os.path.join(work, name + ".stl")
    mesh.write(stl)
    out = os.path.join(work, name + "_paramesh.msh")
    p = subprocess.run([exe, "mesh", stl, "-o", out, "--size", str(h), "--quiet", "--report", out + ".json"],
                       capture_output=True, text=True, timeout=1800)
    row = {"model": os.path.basename(model), "h": h, "deflection": defl, "stl_facets": mesh.CountFacets,
           "exit": p.returncode, "message": p.stderr.strip()[-400:]}
    if os.path.exists(out):
        # 300 samples: meshcheck looks for the nearest CAD face of every sampled triangle of a
        # discrete patch (its MSH entity is no CAD face), over all faces
        row["paramesh"] = meshcheck(model, out, h, samples=300)
        row["node_dev"] = node_deviation(shape, out)
    g = os.path.join(work, name + "_gmsh.msh")
    subprocess.run([sys.executable, os.path.join(SHARED, "tools", "gmsh_baseline.py"), "--algo", "frontal", model, str(h), g],
                   capture_output=True, text=True, timeout=1800)
    if os.path.exists(g):
        row["gmsh"] = meshcheck(model, g, h)
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("models", nargs="*")
    ap.add_argument("--work", default="/tmp/discrete_vs_gmsh")
    ap.add_argument("--paramesh", default=os.path.join(ROOT, "build", "bin", "paramesh"))
    ap.add_argument("--angular", type=float, default=0.5)
    a = ap.parse_args()
    models = a.models or sorted(glob.glob(os.path.join(SHARED, "models", "*.st*p")) +
                                glob.glob(os.path.join(SHARED, "models", "*.brep")) +
                                glob.glob(os.path.join(SHARED, "models", "*.ig*s")))
    os.makedirs(a.work, exist_ok=True)
    rows = []
    done = os.path.join(a.work, "results.jsonl")
    if os.path.exists(done):  # a run stopped half-way goes on where it was
        rows = [json.loads(l) for l in open(done)]
    for m in models:
        if any(r["model"] == os.path.basename(m) for r in rows):
            continue
        rows.append(run(m, a.work, a.paramesh, a.angular))
        print(json.dumps(rows[-1]), flush=True)
        with open(done, "a") as f:
            f.write(json.dumps(rows[-1]) + "\n")
    json.dump(rows, open(os.path.join(a.work, "results.json"), "w"), indent=1)


if __name__ == "__main__":
    main()
