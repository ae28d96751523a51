// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshAudit.hpp
/// The final audit of a finished mesh, independent of how it was made: conformity and closure
/// (every closed solid's elements form a closed, consistently oriented 2-manifold), no duplicate
/// elements, no coincident nodes, no element folded onto its neighbour or facing against its
/// surface, every node on its CAD entity, every tetrahedron positive. A mesh whose audit finds
/// anything is never reported "ok".
#pragma once
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "paramesh/audit/AuditResult.hpp"
#include "paramesh/geom/Geometry.hpp"
#include "paramesh/mesh/SurfaceMesh.hpp"

namespace paramesh {

struct AuditInput {
  const IGeometryModel& model;
  const SurfaceMesh& mesh;
  /// per triangle / quad: (u,v) of its corners on its face (seam-safe); may be empty (then the
  /// orientation against the surface is not checked)
  const std::vector<std::array<Vec2, 3>>& triUv;
  const std::vector<std::array<Vec2, 4>>& quadUv;
  /// per 0-based face: 1 when its elements are a coincident face's copy (orientation not checked)
  std::vector<char> copyFace;
  /// per 0-based edge: the edge it coincides with and shares its nodes with (unsewn CAD; empty:
  /// every edge is its own); a mesh edge on such a group may be used by all the group's faces
  std::vector<int> edgeRep;
  int threads = 1;     ///< for the checks that evaluate the CAD (orientation, nodes); same result for any count
  bool nodes = true;   ///< check the nodes (coincident, on the CAD); false: the elements only
};

/// Runs work(begin, end, chunk) over [0, n) in fixed chunks on `threads` threads (chunk-ordered
/// results make the outcome independent of the thread count). Returns the number of chunks.
int auditChunks(int n, int threads, const std::function<void(int, int, int)>& work);
constexpr int kAuditChunk = 8192;

/// Audits in.mesh against in.model (reads only). The fold threshold: two elements of one face
/// meeting at an interior edge with normals more than foldAngleDeg apart.
AuditResult auditMesh(const AuditInput& in, double foldAngleDeg = 160.0);

// The audit's parts (audit/*.cpp); each adds its counts, entities and problems to r.
void auditEdgeUse(const AuditInput& in, double foldAngleDeg, AuditResult& r);
void auditElements(const AuditInput& in, AuditResult& r);
void auditNodes(const AuditInput& in, AuditResult& r);

/// 0-based face of element e (a triangle when e < triangles, else quad e - triangles).
int elementFace(const SurfaceMesh& m, int e);

/// Normal of element e (a triangle when e < triangles, else quad e - triangles), not normalised.
Vec3 elementNormal(const SurfaceMesh& m, int e);

/// Adds one finding: problem text with up to a few named entities, and where the first one is.
void addFinding(AuditResult& r, const std::string& what, int count, const std::vector<int>& faces,
                const std::vector<int>& edges = {}, const std::vector<int>& solids = {}, const Vec3* first = nullptr);

}  // namespace paramesh
