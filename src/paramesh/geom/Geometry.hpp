// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Geometry.hpp
/// The abstract CAD-kernel interface. Algorithms see only these classes; OpenCASCADE lives behind
/// geom/occ/. A discrete (STL) backend can implement the same interface.
///
/// Numbering: faces, edges and vertices are indexed 0-based here and named 1-based everywhere a
/// user sees them ("Face3" is index 2), in the order FreeCAD uses (TopExp::MapShapes order).
///
/// Thread safety: an IGeometryModel is read-only after construction and may be queried from several
/// threads. ISurface/ICurve/IPCurve objects returned by make*() carry evaluation caches and belong to
/// one thread: create one per task.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "paramesh/util/Vec.hpp"

namespace paramesh {

/// Geometric type of a face's underlying surface (for reports and fast paths).
enum class SurfaceKind { Plane, Cylinder, Cone, Sphere, Torus, BSpline, Bezier, Revolution, Extrusion, Offset, Other };
/// Geometric type of an edge's 3D curve.
enum class CurveKind { Line, Circle, Ellipse, BSpline, Bezier, Other };

const char* toString(SurfaceKind k);

/// Rectangle in the (u,v) parameter plane.
struct UVBox {
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
};

/// Value and derivatives of a surface up to order 2 at one (u,v).
struct SurfaceD2 {
  Vec3 p, du, dv, duu, duv, dvv;
};

/// A parametric surface S(u,v) (the geometry of one face, untrimmed).
class ISurface {
 public:
  virtual ~ISurface() = default;
  virtual SurfaceKind kind() const = 0;
  /// S(u,v).
  virtual Vec3 eval(Vec2 uv) const = 0;
  /// S, S_u, S_v.
  virtual void d1(Vec2 uv, Vec3& p, Vec3& du, Vec3& dv) const = 0;
  /// S and all derivatives up to order 2.
  virtual void d2(Vec2 uv, SurfaceD2& d) const = 0;
  /// Parameter bounds of the face (of its trimmed domain, not of the infinite surface).
  virtual UVBox bounds() const = 0;
  /// Periodicity of the underlying surface; period() is 0 when not periodic.
  virtual double uPeriod() const = 0;
  virtual double vPeriod() const = 0;

  /// Unit normal S_u x S_v / |S_u x S_v| (of the parametrisation, not accounting for face
  /// orientation). Near singular points it is estimated from second derivatives; returns false when
  /// it cannot be defined.
  bool normal(Vec2 uv, Vec3& n) const;

  /// Seeded closest-point projection: Newton on (S-x).S_u = (S-x).S_v = 0 starting from uv
  /// (in/out). Steps are damped and kept within bounds() widened by `margin` (relative to the
  /// parameter span; periodic directions are unbounded). Returns false when it did not converge.
  /// Cost: a handful of d2() calls. `out` receives S(uv) when given.
  bool project(Vec3 x, Vec2& uv, Vec3* out = nullptr, double margin = 0.0) const;

  /// Unseeded projection (expensive: a coarse sampling of the domain followed by project()).
  bool projectGlobal(Vec3 x, Vec2& uv, Vec3* out = nullptr) const;
};

/// A 3D curve C(t).
class ICurve {
 public:
  virtual ~ICurve() = default;
  virtual CurveKind kind() const = 0;
  virtual Vec3 eval(double t) const = 0;
  /// C(t) and C'(t).
  virtual void d1(double t, Vec3& p, Vec3& dt) const = 0;
  /// C, C', C''.
  virtual void d2(double t, Vec3& p, Vec3& d1, Vec3& d2) const = 0;
  /// Seeded closest point on the curve within [t0,t1]; returns the parameter.
  double project(Vec3 x, double seed, double t0, double t1) const;
};

/// A curve in the (u,v) plane of a face (a "pcurve"); shares the parameter t of the edge's 3D curve.
class IPCurve {
 public:
  virtual ~IPCurve() = default;
  virtual Vec2 eval(double t) const = 0;
  virtual void d1(double t, Vec2& p, Vec2& dt) const = 0;
};

/// One use of an edge in a face's wire.
struct EdgeUse {
  int edge = -1;          ///< 0-based edge index
  bool reversed = false;  ///< true: the wire traverses the edge from t1 to t0
};

/// A closed loop of edge uses bounding a face (outer boundary or hole), in wire order.
struct Wire {
  std::vector<EdgeUse> uses;
};

/// A face bounding a solid: reversed when the solid uses it against the face's own orientation
/// (faceReversed), so that the face's triangles must be flipped to point out of that solid.
struct SolidFace {
  int face = 0;  ///< 0-based
  bool reversed = false;
};

/// The topology and geometry of a CAD model, as the mesher sees it.
class IGeometryModel {
 public:
  virtual ~IGeometryModel() = default;

  virtual int numFaces() const = 0;
  virtual int numEdges() const = 0;
  virtual int numVertices() const = 0;
  virtual int numSolids() const = 0;

  // --- vertices
  virtual Vec3 vertexPoint(int v) const = 0;
  virtual double vertexTolerance(int v) const = 0;

  // --- edges
  /// Parameter range [t0,t1] of the edge on its curve (also for degenerate edges: the pcurve range).
  virtual void edgeRange(int e, double& t0, double& t1) const = 0;
  /// Vertex at t0 (end = 0) or t1 (end = 1); -1 if the edge has no vertex there.
  virtual int edgeVertex(int e, int end) const = 0;
  /// True for an edge that collapses to a point in 3D (e.g. a sphere pole, a cone apex).
  virtual bool edgeDegenerate(int e) const = 0;
  /// The 3D curve (null for degenerate edges).
  virtual std::unique_ptr<ICurve> makeCurve(int e) const = 0;
  virtual double edgeTolerance(int e) const = 0;
  /// Faces that use the edge (each once, even when the edge is a seam used twice by one face).
  virtual const std::vector<int>& edgeFaces(int e) const = 0;

  // --- faces
  virtual std::unique_ptr<ISurface> makeSurface(int f) const = 0;
  /// True when the face's outward normal is -S_u x S_v (face orientation reversed).
  virtual bool faceReversed(int f) const = 0;
  virtual const std::vector<Wire>& faceWires(int f) const = 0;
  /// The pcurve of use `use` of wire `wire` of face f (seam edges have one pcurve per use).
  virtual std::unique_ptr<IPCurve> makePCurve(int f, int wire, int use) const = 0;
  virtual double faceTolerance(int f) const = 0;
  /// Solid (0-based) that owns the face, -1 for a free face/shell.
  virtual int faceSolid(int f) const = 0;
  /// The faces bounding solid s (0-based), each with its orientation in that solid; a face shared
  /// by two solids appears in both. A face used twice by one solid (an internal face) appears twice.
  virtual std::vector<SolidFace> solidFaces(int s) const = 0;

  /// Bounding box of the whole model.
  virtual Box3 boundingBox() const = 0;
  /// Free-text description of where the model came from (file name, "BREP string").
  virtual std::string source() const = 0;
  /// What the reader noticed while reading a damaged file (entities it skipped), for the report.
  virtual std::vector<std::string> readWarnings() const { return {}; }
};

}  // namespace paramesh
