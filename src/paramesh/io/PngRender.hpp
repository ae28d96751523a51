// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file PngRender.hpp
/// Software rasteriser that draws a SurfaceMesh into an RGB picture and writes it as PNG (no
/// OpenGL, no display): orthographic view, z-buffer, flat two-sided Lambert shading from a
/// headlight plus ambient, optional element edges (hidden edges hidden).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "paramesh/mesh/SurfaceMesh.hpp"
#include "paramesh/util/Vec.hpp"

namespace paramesh {

struct RenderOptions {
  int width = 1600, height = 1200;            ///< picture size in pixels (1..16384 each)
  /// View direction: the camera sits at azimuth (from +X towards +Y) and elevation (towards +Z)
  /// and looks at the model centre; +Z points up in the picture unless looking along Z.
  double azimuthDeg = 35, elevationDeg = 25;
  bool edges = true;  ///< draw element edges (dark 1-pixel lines, depth-tested)
  /// ByFace: pastel colour per CAD face (fixed for a face number). ByQuality: blue (0) -> cyan ->
  /// green -> yellow -> red (1) of the triangle radius ratio gamma / quad corner-sine quality.
  enum class Color { ByFace, ByQuality, Uniform } color = Color::ByFace;
  /// Close-up: frame only this 3D box (the rest of the model is still drawn where it falls into
  /// the picture, and may hide the box: choose the view direction accordingly, or clipFront).
  bool hasFocus = false;
  Vec3 focusLo, focusHi;
  /// With hasFocus: cut-away view, discarding every fragment nearer to the camera than the focus
  /// box's nearest corner (plus 5% of its diagonal). Surfaces through the box that are oblique to
  /// the view may then be cut inside the picture too.
  bool clipFront = false;
  std::string title;  ///< not drawn (no font rendering); kept for callers' convenience
};

/// An 8-bit RGB picture, rows top to bottom.
struct RgbImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  ///< width * height * 3 bytes
};

/// Renders m into a picture. Order-2 elements are drawn through their mid-nodes (4 sub-triangles
/// / 4 sub-quads). Segments (1D elements) are not drawn. Throws paramesh::Error on invalid
/// options or an inconsistent mesh.
RgbImage renderImage(const SurfaceMesh& m, const RenderOptions& o);

/// Renders m and writes the picture as PNG to path (through a temporary file, see AtomicFile).
/// Throws paramesh::Error naming path when the picture cannot be encoded or written.
void renderPng(const std::string& path, const SurfaceMesh& m, const RenderOptions& o);

/// Encodes img as PNG and writes it to path (through a temporary file).
void writePng(const std::string& path, const RgbImage& img);

}  // namespace paramesh
