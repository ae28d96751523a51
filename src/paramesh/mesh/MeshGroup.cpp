// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file MeshGroup.cpp
#include "paramesh/mesh/MeshGroup.hpp"

#include <cctype>

#include "paramesh/util/Error.hpp"

namespace paramesh {

namespace {

/// "Face12" -> ("face", 12); ("", 0) when text is not a kind followed by digits.
std::pair<std::string, long> entityName(const std::string& text) {
  size_t i = 0;
  std::string kind;
  while (i < text.size() && std::isalpha((unsigned char)text[i])) kind += (char)std::tolower((unsigned char)text[i++]);
  if (i == text.size() || i == 0 || text.size() - i > 9) return {"", 0};
  long n = 0;
  for (; i < text.size(); ++i) {
    if (!std::isdigit((unsigned char)text[i])) return {"", 0};
    n = n * 10 + (text[i] - '0');
  }
  return {kind, n};
}

/// s quoted for a one-line message: control characters escaped, cut at 60 characters.
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (size_t i = 0; i < s.size() && i < 60; ++i) {
    const unsigned char c = (unsigned char)s[i];
    if (c < 0x20 || c == 0x7f) {
      static const char* hex = "0123456789abcdef";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    } else {
      out += (char)c;
    }
  }
  return out + (s.size() > 60 ? "...'" : "'");
}

}  // namespace

std::string groupNameProblem(const std::string& name) {
  if (name.empty()) return "a group needs a name";
  if (name.size() > 64) return "group name " + quoted(name) + " is longer than 64 characters";
  if (!(std::isalpha((unsigned char)name[0]) || name[0] == '_'))
    return "group name " + quoted(name) + " must start with a letter or _";
  for (char c : name)
    if (!(std::isalnum((unsigned char)c) || c == '_' || c == '.' || c == '-'))
      return "group name " + quoted(name) + " may hold letters, digits, _ . - only";
  const auto [kind, n] = entityName(name);
  if (kind == "face" || kind == "edge" || kind == "vertex" || kind == "solid" || kind == "boundarylayer")
    return "group name " + quoted(name) + " is the name of a default group (Face<i>, Edge<i>, Vertex<i>, Solid<i>, BoundaryLayer<i>)";
  return "";
}

MeshGroup parseGroup(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos) throw ParameterError("group " + quoted(text) + " must read NAME=Face3,Face7");
  MeshGroup g;
  g.name = text.substr(0, eq);
  if (const std::string why = groupNameProblem(g.name); !why.empty()) throw ParameterError(why);
  std::string kindSeen;
  size_t at = eq + 1;
  while (at <= text.size()) {
    const size_t comma = std::min(text.find(',', at), text.size());
    const std::string item = text.substr(at, comma - at);
    const auto [kind, n] = entityName(item);
    const int dim = kind == "edge" ? 1 : kind == "face" ? 2 : kind == "solid" ? 3 : 0;
    if (dim == 0 || n < 1)
      throw ParameterError("group " + quoted(g.name) + ": " + quoted(item) + " is no Face<i>, Edge<i> or Solid<i>");
    if (!kindSeen.empty() && kind != kindSeen)
      throw ParameterError("group " + quoted(g.name) + " mixes " + kindSeen + "s and " + kind +
                           "s: a group holds entities of one dimension");
    kindSeen = kind;
    g.dim = dim;
    g.entities.push_back((int)n);
    at = comma + 1;
  }
  return g;
}

}  // namespace paramesh
