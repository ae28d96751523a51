// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshWriters.hpp
/// Writers of a SurfaceMesh to mesh files: Gmsh MSH 4.1, VTK XML (.vtu), STL and Abaqus/CalculiX
/// (.inp). Every writer writes to a temporary sibling file and renames it over the target, so a
/// failed write never leaves a half-written file; failures throw paramesh::Error naming the path.
/// Text output is locale-independent.
#pragma once
#include <fstream>
#include <string>
#include <string_view>

#include "paramesh/mesh/SurfaceMesh.hpp"

namespace paramesh {

/// Gmsh MSH 4.1 ASCII. One point entity per CAD vertex, one curve per CAD edge and one surface
/// per CAD face, each tagged with its 1-based CAD number (so meshio's "gmsh:geometrical" and
/// Gmsh's elementary tags are the FreeCAD Face<i>/Edge<i>/Vertex<i> numbers). Node tags are
/// node index + 1; element tags run from 1 in file order: points (type 15), segments (1 / line3
/// 8), then per face its triangles (2 / triangle6 9) and quads (3 / quad8 16), then per solid
/// (volume entity tag = 1-based solid number) its tetrahedra (4 / tet10 11).
void writeMsh41(const std::string& path, const SurfaceMesh& m);

/// VTK XML UnstructuredGrid (ASCII): triangles (VTK 5, quadratic 22), quads (9, quadratic
/// 23), then tetrahedra (10, quadratic 24). Cell data "face" (Int32, CAD face number; 0 for
/// tetrahedra), "solid" (Int32, only with tetrahedra: their solid, 0 for surface cells) and
/// "quality" (Float64, see triangleGamma / quadQuality, tetrahedra: tetRadiusRatio); point data
/// "entity_dim" (Int32, 0/1/2/3) and "entity" (Int32, CAD number).
/// Segments are not written.
void writeVtu(const std::string& path, const SurfaceMesh& m);

/// STL, binary (default) or ASCII. Quads are split into two triangles along the shorter diagonal;
/// order-2 elements are written through their corner nodes only. Facet normal = normalised
/// (b-a)x(c-a), (0,0,0) for a degenerate triangle.
void writeStl(const std::string& path, const SurfaceMesh& m, bool binary = true);

/// Abaqus / CalculiX input: *NODE, then per CAD face its *ELEMENT blocks (S3 / S6 triangles,
/// S4 / S8 quads; order-2 node order: corners then mid-nodes n12, n23, n31 (n34, n41)), then one
/// *ELSET, ELSET=Face<i> per CAD face. Segments are not written.
/// With tetrahedra (a solid FEM mesh) the elements are the tetrahedra only (C3D4 / C3D10, one
/// *ELSET, ELSET=Solid<i> per solid), and each CAD face is a node set (*NSET, NSET=Face<i>) and
/// an element-face surface (*SURFACE, NAME=Face<i>, TYPE=ELEMENT: the tetrahedron faces on it).
void writeInp(const std::string& path, const SurfaceMesh& m);

/// Named multi-solid ASCII STL for OpenFOAM (snappyHexMesh, surfaceCheck) and CfdOF: one
/// "solid NAME ... endsolid NAME" per user face group (a facet in two goes to the first), then
/// one "solid Face<i>" per CAD face holding facets no group took.
void writeStlGroups(const std::string& path, const SurfaceMesh& m);

/// SU2 native mesh (ASCII, 0-based). With tetrahedra: NDIME= 3, the tetrahedra as elements and
/// one MARKER per face group (Face<i> and the user's) holding its triangles. Without: the
/// surface elements (2D-in-3D, for converters: SU2's solvers need a volume mesh) and one MARKER
/// per user edge group holding its segments. Linear elements only (order 2 throws Error).
void writeSu2(const std::string& path, const SurfaceMesh& m);

/// How writeMesh writes what the extension leaves open.
struct WriteOptions {
  /// .stl: named multi-solid ASCII (writeStlGroups); also when the mesh has user face groups.
  bool stlGroups = false;
};

/// Dispatches on the lower-case extension: .msh, .vtu, .stl (binary; named multi-solid ASCII
/// with WriteOptions::stlGroups or user face groups), .inp or .su2; anything else throws
/// paramesh::Error.
void writeMesh(const std::string& path, const SurfaceMesh& m, const WriteOptions& options = {});

namespace io {

/// Radius-ratio quality of a triangle, 2*r_in/r_circ: 1 for equilateral, 0 for degenerate.
double triangleGamma(const Vec3& a, const Vec3& b, const Vec3& c);
/// Quality of a quad (a,b,c,d): the smallest corner sine, each signed against the quad's mean
/// normal: 1 for a rectangle, 0 for a degenerate corner, negative when non-convex/folded.
/// Independent of the aspect ratio (boundary-layer quads are stretched on purpose).
double quadQuality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Empty when m is consistent, else a short description of the first problem found (array sizes
/// that disagree, an element referring to a missing node, an invalid order or NodeKind).
std::string findMeshProblem(const SurfaceMesh& m);
/// Throws paramesh::Error("cannot write '<path>': invalid mesh (...)") when findMeshProblem
/// reports a problem. Called by every writer before it opens its file.
void checkMeshForWriting(const std::string& path, const SurfaceMesh& m);

/// A file written (in binary mode) through a temporary sibling "<path>.<N>.tmp" that commit()
/// renames over path.
/// Destroying an uncommitted AtomicFile removes the temporary file. Errors throw paramesh::Error
/// naming path.
class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// Buffered write.
  void write(std::string_view data);
  void write(const void* data, std::size_t n) {
    write(std::string_view(static_cast<const char*>(data), n));
  }
  /// Flushes, closes, checks for errors and renames the temporary file over the target.
  void commit();
  const std::string& path() const { return path_; }

 private:
  void flushBuffer();
  [[noreturn]] void fail(const std::string& what);

  std::string path_, tmp_;
  std::ofstream out_;
  std::string buf_;
  bool committed_ = false;
};

}  // namespace io
}  // namespace paramesh
