// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file OccTriangleReader.cpp
/// STL and OBJ through OpenCASCADE's RWStl / RWObj (maintained, already linked: no reader of our
/// own), after checks of the file's framing that those readers do not make.
#include <Poly_Triangulation.hxx>
#include <RWObj.hxx>
#include <RWStl.hxx>
#include <Standard_ErrorHandler.hxx>
#include <Standard_Failure.hxx>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>

#include "paramesh/geom/discrete/TriangleSoup.hpp"
#include "paramesh/util/Error.hpp"

namespace paramesh {
namespace {

std::string lowerExt(const std::string& path) {
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos) return "";
  std::string e = path.substr(dot + 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return (char)std::tolower(c); });
  return e;
}

/// A binary STL is 80 header bytes, a facet count and 50 bytes per facet. An ASCII one starts
/// with "solid" and its last word is "endsolid [name]". (Binary files may start with "solid" too:
/// the size decides.)
/// Returns the facet count the file declares (binary) or holds (ASCII "endfacet" lines).
long long checkStlFraming(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw InputError("cannot open '" + path + "'");
  const long long size = (long long)in.tellg();
  in.seekg(0);
  std::string head(std::min<long long>(size, 84), '\0');
  in.read(&head[0], (std::streamsize)head.size());
  uint32_t count = 0;
  if (size >= 84) std::memcpy(&count, head.data() + 80, 4);
  const bool binarySized = size >= 84 && size == 84 + 50LL * count;
  if (binarySized) {
    if (count == 0) throw InputError("'" + path + "' is a binary STL without a facet");
    return count;
  }
  size_t b = 0;
  while (b < head.size() && std::isspace((unsigned char)head[b])) ++b;
  const bool ascii = head.compare(b, 5, "solid") == 0;
  if (!ascii) {
    if (size < 84) throw InputError("'" + path + "' is cut short: " + std::to_string(size) + " bytes, less than a binary STL's 84-byte header");
    throw InputError("'" + path + "' is a damaged binary STL: its header counts " + std::to_string(count) +
                     " facets (" + std::to_string(84 + 50LL * count) + " bytes), the file has " + std::to_string(size) +
                     " bytes");
  }
  // the last non-blank line of an ASCII STL starts with "endsolid"
  const long long tail = std::min<long long>(size, 4096);
  std::string end(tail, '\0');
  in.seekg(size - tail);
  in.read(&end[0], tail);
  while (!end.empty() && std::isspace((unsigned char)end.back())) end.pop_back();
  const size_t nl = end.find_last_of("\r\n");
  std::string last = end.substr(nl == std::string::npos ? 0 : nl + 1);
  last.erase(0, last.find_first_not_of(" \t"));
  if (last.compare(0, 8, "endsolid") != 0)
    throw InputError("'" + path + "' is cut short: an ASCII STL ends with an 'endsolid' line");
  in.clear();
  in.seekg(0);
  long long facets = 0;
  for (std::string word; in >> word;) facets += word == "endfacet";
  return facets;
}

TriangleSoup fromTriangulation(const Handle(Poly_Triangulation)& t, const std::string& path) {
  TriangleSoup s;
  s.source = path;
  if (t.IsNull() || t->NbTriangles() == 0) throw InputError("'" + path + "' holds no triangle OpenCASCADE could read");
  s.points.reserve(t->NbNodes());
  for (int i = 1; i <= t->NbNodes(); ++i) {
    const gp_Pnt p = t->Node(i);
    s.points.push_back({p.X(), p.Y(), p.Z()});
  }
  s.triangles.reserve(t->NbTriangles());
  for (int i = 1; i <= t->NbTriangles(); ++i) {
    int a, b, c;
    t->Triangle(i).Get(a, b, c);
    s.triangles.push_back({a - 1, b - 1, c - 1});
  }
  return s;
}

}  // namespace

bool isTriangleFile(const std::string& path) {
  const std::string e = lowerExt(path);
  return e == "stl" || e == "obj";
}

TriangleSoup readTriangleFile(const std::string& path) {
  const std::string ext = lowerExt(path);
  if (ext != "stl" && ext != "obj") throw InputError("'" + path + "' is not an STL or OBJ file");
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw InputError("cannot open '" + path + "'");
  }
  const long long declared = ext == "stl" ? checkStlFraming(path) : -1;
  Handle(Poly_Triangulation) t;
  try {
    OCC_CATCH_SIGNALS
    t = ext == "stl" ? RWStl::ReadFile(path.c_str()) : RWObj::ReadFile(path.c_str());
  } catch (const Standard_Failure& e) {
    throw InputError("OpenCASCADE could not read '" + path + "': " + e.GetMessageString());
  }
  TriangleSoup soup = fromTriangulation(t, path);
  if (declared > (long long)soup.triangles.size()) soup.readerDropped = (int)(declared - (long long)soup.triangles.size());
  return soup;
}

}  // namespace paramesh
