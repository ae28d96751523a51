#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Gmsh (the benchmark rival) with the same size settings as `paramesh mesh MODEL --curvature-angle A`.

usage: gmsh_curvature.py MODEL OUT.msh [--angle 10] [--size H] [--min-size M] [--algo frontal]
ParaMesh's defaults: size = bounding-box diagonal / 50, min-size = size / 1000. Gmsh's
Mesh.MeshSizeFromCurvature is the number of elements per 2*pi, so 360 / angle. The shared
tools/gmsh_baseline.py --curvature fixes the min size at size/100; this one sets Gmsh's min and max
to ParaMesh's, so that both meshers may refine as far. Prints one JSON line (triangles, seconds of
the meshing call, 1 thread). Run with Debian's /usr/bin/python3 (python3-gmsh).
"""
import argparse, json, math, time
import gmsh

ALGOS = {'meshadapt': 1, 'delaunay': 5, 'frontal': 6}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('model'); ap.add_argument('out')
    ap.add_argument('--angle', type=float, default=10.0)
    ap.add_argument('--size', type=float, default=0.0, help='default: bounding-box diagonal / 50')
    ap.add_argument('--min-size', type=float, default=0.0, help='default: size / 1000')
    ap.add_argument('--algo', default='frontal', choices=sorted(ALGOS))
    a = ap.parse_args()
    gmsh.initialize()
    try:
        gmsh.option.setNumber('General.Terminal', 0)
        gmsh.option.setNumber('General.NumThreads', 1)
        gmsh.model.occ.importShapes(a.model)
        gmsh.model.occ.synchronize()
        x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(-1, -1)
        size = a.size or math.sqrt((x1 - x0) ** 2 + (y1 - y0) ** 2 + (z1 - z0) ** 2) / 50
        hmin = a.min_size or size / 1000
        gmsh.option.setNumber('Mesh.MeshSizeMin', hmin)
        gmsh.option.setNumber('Mesh.MeshSizeMax', size)
        gmsh.option.setNumber('Mesh.MeshSizeFromCurvature', round(360.0 / a.angle))
        gmsh.option.setNumber('Mesh.Algorithm', ALGOS[a.algo])
        t0 = time.perf_counter()
        gmsh.model.mesh.generate(2)
        t_mesh = time.perf_counter() - t0
        _, tags, _ = gmsh.model.mesh.getElements(2)
        gmsh.option.setNumber('Mesh.MshFileVersion', 4.1)
        gmsh.write(a.out)
        print(json.dumps({'mesher': 'gmsh ' + gmsh.option.getString('General.Version'), 'algo': a.algo,
                          'size': size, 'min_size': hmin, 'elements_per_2pi': round(360.0 / a.angle),
                          'triangles': int(sum(len(t) for t in tags)), 'mesh_s': round(t_mesh, 3)}))
    finally:
        gmsh.finalize()


if __name__ == '__main__':
    main()
