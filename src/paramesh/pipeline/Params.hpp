// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Params.hpp
/// Meshing parameters: one plain struct passed by value, validated once at entry.
/// Lengths are in model units. The optional lengths (size, min_size, max_size, volume_max_size)
/// start as kNotGiven: the setup stage puts their defaults in their place; a number given, 0
/// included, is checked as given.
#pragma once
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "paramesh/mesh/MeshGroup.hpp"

namespace paramesh {

/// The value of an optional length the caller left out. A NaN: no reader passes one on as a
/// value (the CLI, the parameters JSON and the Python binding refuse NaN).
inline constexpr double kNotGiven = std::numeric_limits<double>::quiet_NaN();
/// An optional length was given (is not kNotGiven).
inline bool isGiven(double v) { return !std::isnan(v); }

/// A local size on CAD entities ("Face3=0.5" on the command line).
struct LocalSize {
  enum class Kind { Face, Edge, Vertex };
  Kind kind = Kind::Face;
  std::vector<int> entities;  ///< 1-based entity numbers
  double size = 0;            ///< target element size near the entities (> 0)
};

/// One surface boundary-layer specification.
struct BoundaryLayerSpec {
  std::vector<int> edges;      ///< 1-based CAD edges the layers grow from
  double firstHeight = 0;      ///< height of the first row h0 (> 0)
  double growth = 1.2;         ///< ratio between consecutive row heights (>= 1)
  int layers = 0;              ///< number of rows N (0: derived from thickness)
  double thickness = 0;        ///< total thickness T (0: derived from layers)
  double maxAspect = 0;        ///< a column stops when its row height reaches spacing*maxAspect^-1 ... 0 = off
  bool quads = true;           ///< stretched quads (true) or each quad split into two triangles (false)
  bool autoEdges = false;      ///< grow from the automatically detected leading edges (edges may be empty)
};

/// The layer's total thickness: the one given, or h0 (r^N - 1) / (r - 1) from its N layers.
double layerThickness(const BoundaryLayerSpec& b);
/// How messages name spec i (0-based): "boundary layer #2 (edges 3,5)", "(auto edges)".
std::string describeBoundaryLayer(const BoundaryLayerSpec& b, size_t i);

/// Parameters of a meshing run. Defaults give a uniform-size mesh at diagonal/50.
struct MeshParams {
  double size = kNotGiven;     ///< target element edge length (> 0); not given: bounding-box diagonal / 50
  double minSize = kNotGiven;  ///< lower clamp of every size source (> 0); not given: size / 100 (/ 1000 with curvature)
  double maxSize = kNotGiven;  ///< upper clamp (> 0); not given: size
  double curvatureAngle = 0;  ///< degrees an element may subtend on curved faces/edges; 0: off
  double maxDeviation = 0;    ///< max chordal deviation from the CAD as a fraction of size (refines small radii); 0: off
  double grading = 1.3;       ///< max size ratio between neighbouring elements (> 1)
  int threads = 1;            ///< worker threads for face meshing; 0: all cores
  int order = 1;              ///< element order, 1 or 2 (mid-nodes on the CAD)
  bool quads = false;         ///< quad-dominant surface mesh
  bool shortEdgeSources = true;  ///< segments much shorter than the size field refine their surroundings
  /// Where two sides of a face are closer than about half their node spacing (a thread flank, a
  /// ligament), the nodes of one side are staggered against the other's (NarrowZones.hpp).
  bool staggerNarrowGaps = true;
  int proximity = 0;          ///< at least this many elements across thin walls / narrow faces; 0: off
  /// Triangles cut more than 4.5 % of the size deep into a thin part, so that their centroid lies
  /// nearer another CAD face than their own, are refined: the mesh is redone with sizes there, at
  /// most 6 times. Off by default (it trades size conformity for fidelity on coarse meshes).
  bool nearestFaceCheck = false;
  /// The same check runs by default, and its refinement is kept when it adds at most this
  /// fraction of triangles (otherwise the unrefined mesh is kept and the report warns how many
  /// triangles lie nearer another face). 0: no automatic check. Ignored when nearestFaceCheck.
  double nearestFaceBudget = 0.10;
  int optimizePasses = 4;     ///< passes of the 3D optimiser (swap + smooth + split/collapse)
  /// The run stops with a ParameterError when the faces would hold more elements than this (about
  /// 330 bytes each: 50 M is about 16 GB): a size far too small for the model is an error, not
  /// hours of meshing until memory runs out.
  long maxElements = 50000000;
  /// Fill every closed solid with tetrahedra bounded by the surface triangles (stages/volume).
  bool volume = false;
  /// Largest tetrahedron edge inside the solids (> 0); not given: max_size (the interior grows
  /// from the surface sizes at the grading up to it).
  double volumeMaxSize = kNotGiven;
  /// nglib's 3D optimisation passes after the fill (swaps, smoothing); each costs about as much
  /// as the fill itself (docs/tuning/volume.md).
  int volumeOptimize = 1;
  std::vector<LocalSize> localSizes;
  std::vector<BoundaryLayerSpec> boundaryLayers;
  /// Named groups the writers tag beside the default ones (Face<i>, Solid<i>, BoundaryLayer<i>).
  std::vector<MeshGroup> groups;

  /// Throws ParameterError naming the first invalid field.
  void validate() const;
};

/// max_elements from a number read as a double (CLI, parameters JSON): range-checked before the
/// conversion to an integer; throws ParameterError outside [1000, 1e10].
long checkedMaxElements(double v);

}  // namespace paramesh
