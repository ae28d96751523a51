#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Reads a mesh file with meshio and prints its node count, its cells per type (count, blocks)
and, for Gmsh files, the entity tags they carry (cell_data "gmsh:geometrical").

Usage: check_msh_meshio.py FILE [FILE ...]
       check_msh_meshio.py --expect-faces N FILE   # also check that the surface cells carry
                                                   # exactly the entity tags 1..N
Exit status: 0 when every file reads (and matches --expect-faces), 1 otherwise.
Needs meshio (Debian: python3-meshio, run with /usr/bin/python3).
"""
import argparse
import sys

SURFACE_TYPES = ("triangle", "triangle6", "quad", "quad8")


def check(path, expect_faces):
    import meshio

    mesh = meshio.read(path)
    print(f"{path}: {len(mesh.points)} nodes")
    geometrical = mesh.cell_data.get("gmsh:geometrical")
    # Per cell type: number of blocks, number of cells and the entity tags they carry.
    per_type = {}
    for k, block in enumerate(mesh.cells):
        entry = per_type.setdefault(block.type, [0, 0, set()])
        entry[0] += 1
        entry[1] += len(block.data)
        if geometrical is not None:
            entry[2].update(int(t) for t in geometrical[k])
    surface_tags = set()
    for cell_type, (blocks, count, tags) in per_type.items():
        line = f"  {cell_type:10s} {count:9d} cells in {blocks} blocks"
        if geometrical is not None:
            shown = sorted(tags)
            shown = shown if len(shown) <= 16 else shown[:16] + ["..."]
            line += f"; gmsh:geometrical {shown}"
        print(line)
        if cell_type in SURFACE_TYPES:
            surface_tags.update(tags)
    for name in sorted(mesh.cell_data):
        if name != "gmsh:geometrical":
            print(f"  cell_data {name}")
    for name in sorted(mesh.point_data):
        print(f"  point_data {name}")
    if expect_faces is not None:
        want = set(range(1, expect_faces + 1))
        if surface_tags != want:
            print(f"  ERROR: surface entity tags {sorted(surface_tags)} != 1..{expect_faces}")
            return False
    return True


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--expect-faces", type=int, default=None)
    args = ap.parse_args()
    ok = True
    for f in args.files:
        try:
            ok = check(f, args.expect_faces) and ok
        except Exception as e:  # report and continue with the next file
            print(f"{f}: ERROR {type(e).__name__}: {e}")
            ok = False
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
