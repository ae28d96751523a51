// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file test_render.cpp
/// Tests of the PNG renderer: the file, views of the cube, hidden edges hidden, edges visible at a
/// grazing angle, and the focus box zooming and clipping.
#include <gtest/gtest.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>
#include "paramesh/io/MeshWriters.hpp"
#include "paramesh/io/PngRender.hpp"
#include "paramesh/mesh/SurfaceMesh.hpp"
#include "paramesh/util/Error.hpp"
#include "io_fixtures.hpp"

using namespace paramesh;
using namespace paramesh::test;


// ---------------------------------------------------------------------------------------------
// PNG rendering

namespace {

bool isWhite(const RgbImage& im, int x, int y) {
  const uint8_t* p = &im.rgb[(std::size_t(y) * im.width + x) * 3];
  return p[0] == 255 && p[1] == 255 && p[2] == 255;
}
bool isInk(const RgbImage& im, int x, int y) {
  const uint8_t* p = &im.rgb[(std::size_t(y) * im.width + x) * 3];
  return p[0] < 60 && p[1] < 60 && p[2] < 60;
}
bool inkNear(const RgbImage& im, int x, int y, int r) {
  for (int j = y - r; j <= y + r; ++j)
    for (int i = x - r; i <= x + r; ++i)
      if (isInk(im, i, j)) return true;
  return false;
}
std::size_t distinctColours(const RgbImage& im) {
  std::set<uint32_t> s;
  for (std::size_t i = 0; i < im.rgb.size(); i += 3)
    s.insert(uint32_t(im.rgb[i]) << 16 | uint32_t(im.rgb[i + 1]) << 8 | im.rgb[i + 2]);
  return s.size();
}

/// Square [0,1]^2 at height z as two triangles of CAD face `face`, split along the given diagonal.
void addSquare(SurfaceMesh& m, double z, int face, bool mainDiagonal) {
  int a = m.addNode({0, 0, z}, NodeKind::Face, face), b = m.addNode({1, 0, z}, NodeKind::Face, face);
  int c = m.addNode({1, 1, z}, NodeKind::Face, face), d = m.addNode({0, 1, z}, NodeKind::Face, face);
  if (mainDiagonal) {
    m.triangles.push_back({a, b, c});
    m.triangles.push_back({a, c, d});
  } else {
    m.triangles.push_back({a, b, d});
    m.triangles.push_back({b, c, d});
  }
  m.triangleFace.push_back(face);
  m.triangleFace.push_back(face);
}

}  // namespace

TEST_F(IoTest, PngFile) {
  SurfaceMesh m = makeCube(true, 2);
  RenderOptions o;
  o.width = 320;
  o.height = 200;
  std::string p = file("cube.png");
  renderPng(p, m, o);
  std::string s = readFile(p);
  ASSERT_GT(s.size(), 33u);
  EXPECT_EQ(s.compare(0, 8, std::string("\x89PNG\r\n\x1a\n", 8)), 0);
  EXPECT_EQ(s.compare(12, 4, "IHDR"), 0);
  auto be32 = [&](std::size_t off) {
    return uint32_t(uint8_t(s[off])) << 24 | uint32_t(uint8_t(s[off + 1])) << 16 |
           uint32_t(uint8_t(s[off + 2])) << 8 | uint32_t(uint8_t(s[off + 3]));
  };
  EXPECT_EQ(be32(16), 320u);
  EXPECT_EQ(be32(20), 200u);
  EXPECT_EQ(s[24], 8);  // bit depth
  EXPECT_EQ(s[25], 2);  // colour type RGB
  EXPECT_EQ(s.compare(s.size() - 8, 4, "IEND"), 0);
  // Errors name the path.
  o.width = 0;
  EXPECT_THROW(renderPng(file("bad.png"), m, o), Error);
  o.width = 320;
  std::string bad = file("missing_dir/x.png");
  try {
    renderPng(bad, m, o);
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos);
  }
}

TEST(IoRender, CubeViews) {
  RenderOptions o;
  o.width = 400;
  o.height = 300;
  for (int variant = 0; variant < 3; ++variant) {
    SurfaceMesh m = makeCube(variant >= 1, variant == 2 ? 2 : 1);
    o.edges = false;
    o.color = RenderOptions::Color::ByFace;
    RgbImage im = renderImage(m, o);
    ASSERT_EQ(im.rgb.size(), 400u * 300u * 3u);
    EXPECT_TRUE(isWhite(im, 0, 0));
    EXPECT_TRUE(isWhite(im, 399, 299));
    EXPECT_FALSE(isWhite(im, 200, 150));
    // Three faces visible, each flat-shaded in one colour (+ white background).
    EXPECT_EQ(distinctColours(im), 4u) << "variant " << variant;
    // Edges only add dark pixels.
    o.edges = true;
    RgbImage withEdges = renderImage(m, o);
    std::size_t ink = 0;
    for (std::size_t i = 0; i < im.rgb.size(); i += 3)
      if (std::memcmp(&im.rgb[i], &withEdges.rgb[i], 3) != 0) {
        ++ink;
        EXPECT_LT(withEdges.rgb[i], 60);
      }
    EXPECT_GT(ink, 500u);
    o.color = RenderOptions::Color::ByQuality;
    EXPECT_FALSE(isWhite(renderImage(m, o), 200, 150));
    o.color = RenderOptions::Color::Uniform;
    EXPECT_FALSE(isWhite(renderImage(m, o), 200, 150));
  }
  // Empty mesh: a white picture.
  RgbImage empty = renderImage(SurfaceMesh(), o);
  EXPECT_EQ(distinctColours(empty), 1u);
}

TEST(IoRender, HiddenEdgesAreHidden) {
  // Top view (x right, y up) of a front square (z=1, diagonal (0,0)-(1,1)) over a back square
  // (z=0, diagonal (1,0)-(0,1)).
  RenderOptions o;
  o.width = 400;
  o.height = 300;
  o.azimuthDeg = -90;
  o.elevationDeg = 90;
  SurfaceMesh both, front;
  addSquare(both, 1, 1, true);
  addSquare(both, 0, 2, false);
  addSquare(front, 1, 1, true);
  const double s = 0.9 * 300;
  auto px = [&](double x) { return int(200 + (x - 0.5) * s); };
  auto py = [&](double y) { return int(150 - (y - 0.5) * s); };
  RgbImage im = renderImage(both, o);
  EXPECT_TRUE(inkNear(im, px(0.25), py(0.25), 1));    // front diagonal visible
  EXPECT_FALSE(inkNear(im, px(0.75), py(0.25), 2));   // back diagonal hidden
  EXPECT_TRUE(im.rgb == renderImage(front, o).rgb);   // the back square is fully hidden
  // Seen from below (x right, y down) the back square is in front: the other way round.
  o.elevationDeg = -90;
  RgbImage below = renderImage(both, o);
  auto py2 = [&](double y) { return int(150 + (y - 0.5) * s); };
  std::size_t inkA = 0, inkB = 0;
  for (int k = 1; k <= 8; ++k) {  // samples along both diagonals
    double t = k / 10.0;
    inkA += inkNear(below, px(t), py2(t), 1);
    inkB += inkNear(below, px(1 - t), py2(t), 1);
  }
  EXPECT_EQ(inkA, 1u);  // only at t = 0.5, where the diagonals cross
  EXPECT_EQ(inkB, 8u);
}

TEST(IoRender, EdgesVisibleAtGrazingAngle) {
  // A square seen at 10 degrees elevation: every interior column shows the two boundary edges and
  // the diagonal despite the steep depth slope.
  SurfaceMesh m;
  addSquare(m, 0, 1, true);
  RenderOptions o;
  o.width = 400;
  o.height = 300;
  o.azimuthDeg = -90;
  o.elevationDeg = 10;
  RgbImage im = renderImage(m, o);
  int good = 0, cols = 0;
  for (int x = 80; x <= 320; ++x, ++cols) {
    int ink = 0;
    for (int y = 0; y < 300; ++y) ink += isInk(im, x, y);
    good += ink >= 3;
  }
  EXPECT_EQ(good, cols);
}

TEST(IoRender, FocusZoomsAndClipsFront) {
  SurfaceMesh cube = makeCube(false, 1);
  RenderOptions o;
  o.width = 300;
  o.height = 300;
  o.edges = false;
  RgbImage full = renderImage(cube, o);
  std::size_t coverFull = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 300; ++x) coverFull += !isWhite(full, x, y);
  // A box around the top front corner (1,1,1) fills the picture.
  o.hasFocus = true;
  o.focusLo = {0.8, 0.8, 0.8};
  o.focusHi = {1.0, 1.0, 1.0};
  RgbImage zoom = renderImage(cube, o);
  std::size_t coverZoom = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 300; ++x) coverZoom += !isWhite(zoom, x, y);
  EXPECT_GT(coverZoom, coverFull);
  // A box on the back face x=0 (behind the visible faces): without clipFront the front faces
  // hide it; with it the front is clipped away and the picture centre shows face 1 exactly as
  // when face 1 is rendered alone.
  o.focusLo = {-0.01, 0.3, 0.3};
  o.focusHi = {0.01, 0.7, 0.7};
  RgbImage hidden = renderImage(cube, o);
  o.clipFront = true;
  RgbImage back = renderImage(cube, o);
  SurfaceMesh face1 = cube;
  std::vector<std::array<int, 3>> tris;
  std::vector<int> faces;
  for (std::size_t t = 0; t < cube.triangles.size(); ++t)
    if (cube.triangleFace[t] == 1) tris.push_back(cube.triangles[t]), faces.push_back(1);
  face1.triangles = tris;
  face1.triangleFace = faces;
  RgbImage alone = renderImage(face1, o);
  EXPECT_FALSE(isWhite(back, 150, 150));
  EXPECT_EQ(std::memcmp(&back.rgb[(150 * 300 + 150) * 3], &alone.rgb[(150 * 300 + 150) * 3], 3), 0);
  EXPECT_NE(std::memcmp(&hidden.rgb[(150 * 300 + 150) * 3], &alone.rgb[(150 * 300 + 150) * 3], 3), 0);
  o.clipFront = false;
  // Extreme zoom into face 2 away from its edges (triangles far larger than the picture are
  // clipped before rasterisation): one uniform colour, no edge.
  o.edges = true;
  o.focusLo = {1 - 1e-6, 0.3 - 1e-6, 0.6 - 1e-6};
  o.focusHi = {1 + 1e-6, 0.3 + 1e-6, 0.6 + 1e-6};
  RgbImage tiny = renderImage(cube, o);
  EXPECT_EQ(distinctColours(tiny), 1u);
  EXPECT_FALSE(isWhite(tiny, 0, 0));
  // A focus box away from the model: an empty picture; a degenerate box still works.
  o.focusLo = {10, 10, 10};
  o.focusHi = {11, 11, 11};
  EXPECT_TRUE(isWhite(renderImage(cube, o), 150, 150));
  o.focusLo = o.focusHi = {0.5, 0.5, 0.5};
  EXPECT_EQ(renderImage(cube, o).rgb.size(), 300u * 300u * 3u);
}
