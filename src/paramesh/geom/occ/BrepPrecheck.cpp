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
  Tokens(const std::string& text, size_t at) : t_(text), at_(at) {}
  /// The next token, empty at the end of the text.
  std::string_view next() {
    while (at_ < t_.size() && isSpace(t_[at_])) ++at_;
    const size_t b = at_;
    while (at_ < t_.size() && !isSpace(t_[at_])) ++at_;
    last_ = b;
    return std::string_view(t_).substr(b, at_ - b);
  }
  /// Nothing but whitespace is left.
  bool atEnd() const { return t_.find_first_not_of(" \t\n\r\v\f", at_) == npos; }
  /// The last token is read again by the next call.
  void unread() { at_ = last_; }
  /// "line N" of the last token, for messages.
  std::string where() const {
    return "line " + std::to_string(1 + std::count(t_.begin(), t_.begin() + (std::ptrdiff_t)last_, '\n'));
  }

 private:
  const std::string& t_;
  size_t at_;
  size_t last_ = 0;
};

// TopTools_ShapeSet::THE_ASCII_VERSIONS: the reader compares whole lines with these
const char* const kVersions[] = {"CASCADE Topology V1, (c) Matra-Datavision",
                                 "CASCADE Topology V2, (c) Matra-Datavision",
                                 "CASCADE Topology V3, (c) Open Cascade"};

/// Where the text after the version line starts, or npos with problem set. The reader takes lines
/// of at most 99 characters (getline into char[100]: a longer one fails the stream), strips their
/// trailing '\r' and compares them as C strings until one is a version line.
size_t afterVersionLine(const std::string& text, std::string& problem) {
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
    for (const char* s : kVersions)
      if (v == s) return nl == npos ? text.size() : nl + 1;
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

bool isSectionName(std::string_view tok) {
  for (const Section& s : kSections)
    if (tok == s.name) return true;
  return false;
}

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

/// Runs the section readers over the tokens; returns the TShapes count, or -1 with problem set.
long long readSections(Tokens& tk, std::string& problem) {
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
    if (count <= 0) continue;  // no entries: the next token is the next reader's
    // the entries (numbers; "p" in polygons on triangulations) up to the next section's name
    std::string_view t;
    do t = tk.next();
    while (!t.empty() && !isSectionName(t));
    if (t.empty()) {
      problem = std::string("the '") + s.name + "' section runs to the end of the text (it is cut short)";
      return -1;
    }
    tk.unread();  // that name is the next reader's token
  }
  return -1;  // not reached: the TShapes reader returns above
}

}  // namespace

std::string brepStructureProblem(const std::string& text) {
  std::string problem;
  const size_t start = afterVersionLine(text, problem);
  if (start == npos) return problem;
  Tokens tk(text, start);
  const long long shapes = readSections(tk, problem);
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
