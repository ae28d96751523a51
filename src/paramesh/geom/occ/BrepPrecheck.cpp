// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file BrepPrecheck.cpp
/// The BREP structure check (BrepPrecheck.hpp). It mirrors what OpenCASCADE 7.6's reader does
/// (TopTools_ShapeSet::Read, BRepTools_ShapeSet::ReadGeometry and their section readers), read
/// in its sources and measured on the installed library (tests/cpp/test_input_checks.cpp).
#include "paramesh/geom/occ/BrepPrecheck.hpp"

#include <algorithm>
#include <climits>
#include <string_view>

namespace paramesh::detail {
namespace {

constexpr size_t npos = std::string::npos;

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

/// Whitespace-separated tokens, as the reader's operator>> takes them.
class Tokens {
 public:
  Tokens(const std::string& text, size_t at) : t_(text), at_(at) {
    Tokens all(text, at, 0);
    for (std::string_view t = all.next(); !t.empty(); t = all.next()) {
      ++left_;
      if (t.size() > longest_) {
        longest_ = t.size();
        longestAt_ = all.last_;
      }
    }
  }
  /// The longest token's length and "line N".
  size_t longest() const { return longest_; }
  std::string longestWhere() const { return lineOf(longestAt_); }
  /// The next token, empty at the end of the text.
  std::string_view next() {
    while (at_ < t_.size() && isSpace(t_[at_])) ++at_;
    const size_t b = at_;
    while (at_ < t_.size() && !isSpace(t_[at_])) ++at_;
    last_ = b;
    if (at_ > b) --left_;
    return std::string_view(t_).substr(b, at_ - b);
  }
  /// Nothing but whitespace is left.
  bool atEnd() const { return t_.find_first_not_of(" \t\n\r\v\f", at_) == npos; }
  /// How many tokens are left.
  long long left() const { return left_; }
  /// "line N" of the last token, for messages.
  std::string where() const { return lineOf(last_); }

 private:
  Tokens(const std::string& text, size_t at, int) : t_(text), at_(at) {}  // no count
  std::string lineOf(size_t at) const {
    return "line " + std::to_string(1 + std::count(t_.begin(), t_.begin() + (std::ptrdiff_t)at, '\n'));
  }
  const std::string& t_;
  size_t at_;
  size_t last_ = 0;
  long long left_ = 0;
  size_t longest_ = 0;
  size_t longestAt_ = 0;
};

// TopTools_ShapeSet::THE_ASCII_VERSIONS: the reader compares whole lines with these
const char* const kVersions[] = {"CASCADE Topology V1, (c) Matra-Datavision",
                                 "CASCADE Topology V2, (c) Matra-Datavision",
                                 "CASCADE Topology V3, (c) Open Cascade"};

/// Where the text after the version line starts, or npos with problem set. The reader takes lines
/// of at most 99 characters (getline into char[100]: a longer one fails the stream), strips their
/// trailing '\r' and compares them as C strings until one is a version line.
size_t afterVersionLine(const std::string& text, int& version, std::string& problem) {
  size_t at = 0;
  for (int line = 1; at < text.size(); ++line) {
    const size_t nl = text.find('\n', at);
    const size_t end = nl == npos ? text.size() : nl;
    if (end - at > 99) {
      problem = "no version line ('" + std::string(kVersions[0]) + "', V2 or V3, to the letter) before line " +
                std::to_string(line) +
                ", which is longer than the 99 characters OpenCASCADE's reader takes while it looks for one";
      return npos;
    }
    std::string_view v = std::string_view(text).substr(at, end - at);
    v = v.substr(0, v.find('\0'));
    while (v.size() > 1 && v.back() == '\r') v.remove_suffix(1);
    for (int k = 0; k < 3; ++k)
      if (v == kVersions[k]) {
        version = k + 1;
        return nl == npos ? text.size() : nl + 1;
      }
    if (nl == npos) break;
    at = nl + 1;
  }
  problem = "no version line ('" + std::string(kVersions[0]) + "', V2 or V3, to the letter)";
  return npos;
}

/// The section readers in the order BRepTools_ShapeSet calls them. Each takes one token; the
/// exact ones must read their name, the others (the optional sections) a token containing it.
/// A reader whose token does not match returns: the token is gone and the next reader goes on.
struct Section {
  const char* name;
  bool exact;
};
const Section kSections[] = {{"Locations", true}, {"Curve2ds", true}, {"Curves", true},
                             {"Polygon3D", false}, {"PolygonOnTriangulations", false},
                             {"Surfaces", true}, {"Triangulations", false}, {"TShapes", true}};


/// An int as operator>> reads a whole token: optional sign, digits, within int's range.
bool parseCount(std::string_view tok, long long& v) {
  size_t i = !tok.empty() && (tok[0] == '+' || tok[0] == '-') ? 1 : 0;
  if (i == tok.size() || tok.size() - i > 10) return false;
  v = 0;
  for (; i < tok.size(); ++i) {
    if (tok[i] < '0' || tok[i] > '9') return false;
    v = v * 10 + (tok[i] - '0');
  }
  if (tok[0] == '-') v = -v;
  return v >= INT_MIN && v <= INT_MAX;
}

/// atoi as the root reference's reader applies it (after the orientation character).
long long atoiLike(std::string_view s) {
  size_t i = 0;
  const bool neg = i < s.size() && s[i] == '-';
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  long long v = 0;
  for (; i < s.size() && s[i] >= '0' && s[i] <= '9' && v < (1LL << 40); ++i) v = v * 10 + (s[i] - '0');
  return neg ? -v : v;
}

/// The records of the geometry sections, read as OpenCASCADE's section readers read them
/// (TopTools_LocationSet, GeomTools_Curve2dSet / CurveSet / SurfaceSet, BRepTools_ShapeSet's
/// polygon and triangulation readers). Every count the reader sizes an array by, or loops over,
/// is checked against the tokens left: each entry takes tokens of its own, so a larger count is
/// a damaged text, on which the reader would ask for gigabytes or loop on its failed stream.
class Records {
 public:
  Records(Tokens& tk, int version, std::string& problem) : tk_(tk), version_(version), problem_(problem) {}

  /// The count records of the section name; false with the problem set.
  bool section(std::string_view name, long long count) {
    section_ = name;
    record_ = 0;
    if (count > tk_.left()) return fail(std::to_string(count) + " records");
    for (long long i = 1; i <= count; ++i) {
      record_ = i;
      const bool ok = name == "Locations"                 ? location(i)
                      : name == "Curve2ds"                ? curve(2, 0)
                      : name == "Curves"                  ? curve(3, 0)
                      : name == "Surfaces"                ? surface(0)
                      : name == "Triangulations"          ? triangulation()
                      : name == "Polygon3D"               ? polygon3D()
                      : name == "PolygonOnTriangulations" ? polygonOnTriangulation()
                                                          : true;
      if (!ok) return false;
    }
    return true;
  }

 private:
  static constexpr int kMaxNesting = 32;  // trimmed / offset / swept geometry on geometry: the reader recurses

  bool fail(const std::string& what) {
    problem_ = "the '" + std::string(section_) + "' section" +
               (record_ > 0 ? ", record " + std::to_string(record_) + "," : std::string()) + " at " + tk_.where() +
               " declares " + what + " but " + std::to_string(tk_.left()) +
               " tokens are left: a damaged count (or the text is cut short)";
    return false;
  }
  bool bad(const std::string& what) {
    problem_ = "the '" + std::string(section_) + "' section, record " + std::to_string(record_) + ", at " +
               tk_.where() + ": " + what;
    return false;
  }
  /// n tokens (numbers the reader takes without sizing anything by them).
  bool skip(long long n) {
    for (long long k = 0; k < n; ++k)
      if (tk_.next().empty()) return fail(std::to_string(n) + " numbers");
    return true;
  }
  /// An int token into v.
  bool integer(const char* what, long long& v) {
    const std::string_view t = tk_.next();
    if (t.empty()) return fail(std::string("its ") + what);
    if (!parseCount(t, v)) return bad(std::string("its ") + what + " '" + std::string(t.substr(0, 40)) + "' is not an integer");
    return true;
  }
  /// A 0/1 flag (the reader's bool).
  bool flag(const char* what, long long& v) {
    if (!integer(what, v)) return false;
    return v == 0 || v == 1 ? true : bad(std::string("its ") + what + " flag is " + std::to_string(v) + ", not 0 or 1");
  }
  /// A count n >= 0 of entries of `per` tokens each (times `times`, a count already checked).
  bool count(const char* what, long long per, long long& n, long long times = 1) {
    if (!integer(what, n)) return false;
    if (n < 0) return bad(std::string("its ") + what + " count is negative (" + std::to_string(n) + ")");
    const long double need = (long double)n * (long double)times * (long double)per;
    if (need > (long double)tk_.left()) return fail(std::to_string(n) + " " + what);
    return true;
  }
  bool nested(int depth) {
    return depth < kMaxNesting ? true : bad("geometry nested more than " + std::to_string(kMaxNesting) + " deep");
  }

  // TopTools_LocationSet: 1 and a 3x4 matrix, or 2 and (earlier location, power) pairs ended by 0
  bool location(long long index) {
    long long type = 0;
    if (!integer("location type", type)) return false;
    if (type == 1) return skip(12);
    if (type != 2) return bad("location type " + std::to_string(type) + " (1 or 2)");
    for (;;) {
      long long l = 0, power = 0;
      if (!integer("location reference", l)) return false;
      if (l == 0) return true;
      if (l < 1 || l >= index) return bad("location reference " + std::to_string(l) + " names no earlier location");
      if (!integer("location power", power)) return false;
      // TopLoc_Location::Powered recurses once per power step
      if (power < -1000 || power > 1000) return bad("location power " + std::to_string(power) + " (beyond +-1000)");
    }
  }

  // GeomTools_Curve2dSet / GeomTools_CurveSet: a type code, then its numbers
  bool curve(int dim, int depth) {
    if (!nested(depth)) return false;
    long long type = 0, rational = 0, periodic = 0, degree = 0, poles = 0, knots = 0;
    if (!integer("curve type", type)) return false;
    const long long frame = dim == 3 ? 12 : 6;  // point and axes
    switch (type) {
      case 1: return skip(2 * dim);                         // line: point, direction
      case 2: case 4: return skip(frame + 1);               // circle, parabola
      case 3: case 5: return skip(frame + 2);               // ellipse, hyperbola
      case 6:                                               // Bezier: rational, degree, degree + 1 poles
        return flag("rational", rational) && count("degree", dim + rational, degree) &&
               skip((degree + 1) * (dim + rational));
      case 7:                                               // B-spline: poles, then (knot, multiplicity)s
        return flag("rational", rational) && flag("periodic", periodic) && integer("degree", degree) &&
               count("poles", dim + rational, poles) && count("knots", 2, knots) &&
               skip(poles * (dim + rational)) && skip(2 * knots);
      case 8: return skip(2) && curve(dim, depth + 1);      // trimmed: range, basis
      case 9: return skip(dim == 3 ? 4 : 1) && curve(dim, depth + 1);  // offset: distance (direction), basis
      default: return bad((dim == 3 ? "3D" : "2D") + std::string(" curve type ") + std::to_string(type) + " (1 to 9)");
    }
  }

  // GeomTools_SurfaceSet
  bool surface(int depth) {
    if (!nested(depth)) return false;
    long long type = 0, ur = 0, vr = 0, up = 0, vp = 0, ud = 0, vd = 0, nu = 0, nv = 0, ku = 0, kv = 0;
    if (!integer("surface type", type)) return false;
    switch (type) {
      case 1: return skip(12);                                       // plane: point and axes
      case 2: case 4: return skip(13);                               // cylinder, sphere: and a radius
      case 3: case 5: return skip(14);                               // cone, torus: and two numbers
      case 6: return skip(3) && curve(3, depth + 1);                 // linear extrusion: direction, curve
      case 7: return skip(6) && curve(3, depth + 1);                 // revolution: axis, curve
      case 8: {                                                      // Bezier: (udeg + 1) x (vdeg + 1) poles
        if (!flag("u rational", ur) || !flag("v rational", vr)) return false;
        const long long per = 3 + (ur || vr);
        return count("u degree", per, ud) && count("v degree", per, vd) &&
               (((long double)(ud + 1) * (vd + 1) * per <= (long double)tk_.left()) ? true
                    : fail(std::to_string(ud + 1) + " x " + std::to_string(vd + 1) + " poles")) &&
               skip((ud + 1) * (vd + 1) * per);
      }
      case 9: {                                                      // B-spline: poles, u and v knots
        if (!flag("u rational", ur) || !flag("v rational", vr) || !flag("u periodic", up) || !flag("v periodic", vp) ||
            !integer("u degree", ud) || !integer("v degree", vd))
          return false;
        const long long per = 3 + (ur || vr);
        if (!count("u poles", per, nu) || !count("v poles", per, nv, std::max(nu, 1LL)) || !count("u knots", 2, ku) ||
            !count("v knots", 2, kv))
          return false;
        return skip(nu * nv * per) && skip(2 * ku) && skip(2 * kv);
      }
      case 10: return skip(4) && surface(depth + 1);                 // rectangular trimmed: ranges, basis
      case 11: return skip(1) && surface(depth + 1);                 // offset: distance, basis
      default: return bad("surface type " + std::to_string(type) + " (1 to 11)");
    }
  }

  // nodes, has-parameters, deflection, the nodes' coordinates, their parameters
  bool polygon3D() {
    long long n = 0, params = 0;
    return count("nodes", 3, n) && flag("has-parameters", params) && skip(1 + 3 * n + params * n);
  }
  // nodes, their indices, "p", deflection, has-parameters, the parameters
  bool polygonOnTriangulation() {
    long long n = 0, params = 0;
    return count("nodes", 1, n) && skip(n + 2) && flag("has-parameters", params) && skip(params * n);
  }
  // nodes, triangles, has-UV, (V3: has-normals), deflection, nodes, UVs, triangles, normals
  bool triangulation() {
    long long n = 0, t = 0, uv = 0, normals = 0;
    if (!count("nodes", 3, n) || !count("triangles", 3, t) || !flag("has-UV", uv)) return false;
    if (version_ >= 3 && !flag("has-normals", normals)) return false;
    return skip(1 + 3 * n + 2 * uv * n + 3 * t + 3 * normals * n);
  }

  Tokens& tk_;
  int version_;
  std::string& problem_;
  std::string_view section_;
  long long record_ = 0;
};

/// Runs the section readers over the tokens; returns the TShapes count, or -1 with problem set.
long long readSections(Tokens& tk, int version, std::string& problem) {
  Records records(tk, version, problem);
  std::string firstMiss;  // the first required section whose reader found another token
  for (const Section& s : kSections) {
    const std::string_view tok = tk.next();
    if (tok.empty()) {
      problem = std::string("the text ends before its '") + s.name + "' section (it is cut short)";
      return -1;
    }
    const bool tshapes = std::string_view(s.name) == "TShapes";
    const bool match = s.exact ? tok == s.name : tok.find(s.name) != npos;
    if (!match) {
      if (s.exact && firstMiss.empty())
        firstMiss = std::string("OpenCASCADE's reader looks for its '") + s.name + "' section at " + tk.where() +
                    " and finds '" + std::string(tok.substr(0, 40)) + "'";
      if (tshapes) {
        problem = firstMiss + (tk.atEnd() ? " (the text is cut short)"
                                          : " (a section is missing, out of order or damaged): it would read no shape");
        return -1;
      }
      continue;  // the reader returns; its token is gone and the next reader takes the next one
    }
    long long count = 0;
    const std::string_view countTok = tk.next();
    if (!parseCount(countTok, count)) {
      problem = std::string("the '") + s.name + "' section at " + tk.where() +
                (countTok.empty() ? " has no count (the text is cut short)" : " has no valid count");
      return -1;
    }
    if (tshapes) return count;
    if (!records.section(s.name, count)) return -1;  // a negative count reads no record
  }
  return -1;  // not reached: the TShapes reader returns above
}

}  // namespace

std::string brepStructureProblem(const std::string& text) {
  std::string problem;
  int version = 1;
  const size_t start = afterVersionLine(text, version, problem);
  if (start == npos) return problem;
  Tokens tk(text, start);
  // the readers take names into char[255] buffers: a longer token would overrun them
  if (tk.longest() > 254)
    return "a token of " + std::to_string(tk.longest()) + " characters at " + tk.longestWhere() +
           " (OpenCASCADE's reader takes at most 254)";
  const long long shapes = readSections(tk, version, problem);
  if (!problem.empty()) return problem;
  if (shapes <= 0) return "the TShapes section holds no shape (count " + std::to_string(shapes) + ")";
  // each shape record ends with its sub-shape list's '*' token; then the root shape reference
  long long records = 0;
  while (records < shapes) {
    const std::string_view t = tk.next();
    if (t.empty()) break;
    if (t[0] == '*') ++records;
  }
  if (records < shapes)
    return "the TShapes section holds " + std::to_string(records) + " of its " + std::to_string(shapes) +
           " shape records (the text is cut short)";
  // the reader takes the orientation from the first character (+ - i e; any other leaves it), the
  // shape from atoi of the rest (counted from the last record) and then a location index, which
  // may be missing or out of range (identity)
  const std::string_view root = tk.next();
  if (root.empty()) return "no root shape reference after the TShapes section (the text is cut short)";
  if (root[0] == '*') return "the root shape reference is '*' (a null shape)";
  const long long index = atoiLike(root.substr(1));
  if (index < 1 || index > shapes)
    return "the root shape reference '" + std::string(root.substr(0, 40)) + "' names none of the " +
           std::to_string(shapes) + " shape records" + (tk.atEnd() ? " (the text is cut short)" : "");
  return "";
}

}  // namespace paramesh::detail
