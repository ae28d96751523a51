// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file AuditResult.hpp
/// What the final mesh audit (MeshAudit.hpp) found: counts, the entities named, and the problems
/// in one line each. Part of the run's report.
#pragma once
#include <string>
#include <vector>

namespace paramesh {

/// What the audit found; every count is 0 on a sound mesh.
struct AuditResult {
  // conformity: per face, per solid, over the whole mesh
  int invalidEntries = 0;       ///< elements / segments naming a node or CAD entity that does not exist
  int emptyFaces = 0;           ///< faces without any element (failed faces)
  int openFaceEdges = 0;        ///< mesh edges used once by a face but not on a CAD edge (a hole in a face)
  int faceOverusedEdges = 0;    ///< mesh edges used by more than two elements of one face
  int faceMisorientedEdges = 0; ///< mesh edges whose two elements of one face run the same way
  int nonManifoldEdges = 0;     ///< mesh edges used by more elements than their CAD edge has faces
  int solidsChecked = 0;        ///< closed CAD solids whose closure was checked
  int solidsSkipped = 0;        ///< solids open in the CAD or with internal faces (not checked)
  int solidOpenEdges = 0, solidOverusedEdges = 0, solidMisorientedEdges = 0;
  // elements
  int duplicateElements = 0;    ///< triangles / quads with the same nodes as another
  int folds = 0;                ///< edges inside a face whose two elements fold onto each other
  int invertedElements = 0;     ///< elements facing against their face's outward normal
  int invertedTets = 0, duplicateTets = 0;
  // nodes
  int coincidentNodes = 0;      ///< pairs of distinct nodes closer than 1e-9 of the diagonal
  int nodesOffCad = 0;          ///< nodes farther from their CAD entity than its tolerance
  double worstNodeOffset = 0;   ///< the largest node distance to its CAD entity (model units)
  int nodesChecked = 0;
  // where
  std::vector<int> faces, edges, solids;  ///< 1-based entities touched by a finding (sorted)
  std::vector<std::string> problems;      ///< one line per kind of finding, naming entities
  std::vector<std::string> notes;         ///< what was not checked, and why
  /// elements folded onto a neighbour or facing against their surface (triangle t, or triangles +
  /// quad q): what the repair (audit/Repair.hpp) works on
  std::vector<int> badElements;
  int repairedNodes = 0;                  ///< nodes the repair moved (0: none, or no repair ran)
  double seconds = 0;

  bool run = false;  ///< the audit ran (false: the run stopped before it)
  bool passed() const { return problems.empty(); }
};

}  // namespace paramesh
